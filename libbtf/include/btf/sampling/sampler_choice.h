// The samplers `btf sample`, `btf bench sampling` and scenes choose from, by name: two warps that ignore the
// material (uniform and cosine hemisphere), the material's own sample() (for an RGL file the
// Dupuy-Jakob warp of its tensor: the peer baseline), the three tabulated samplers of libbtf, and
// for octree tables the sampler driven by the tree's node bounds (octree_bound_sampler.h), and the
// Dupuy-Jakob warp of any isotropic material, built by writing it to an RGL file in memory
// (rgl_warp_sampler.h).
#pragma once

#include <glm/glm.hpp>

#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "btf/material/material.h"
#include "btf/sampling/binned_sampler.h"

namespace btf {

enum class SamplerChoice { Uniform, Cosine, Own, Tabulated, DpCdf, Quadtree, OctreeBound, DjWarp };

// "uniform", "cosine", "material", "tabulated", "dp-cdf", "quadtree", "octree-bound", "dj-warp".
std::string_view toString(SamplerChoice choice);
std::optional<SamplerChoice> parseSamplerChoice(std::string_view name);
// The names above, comma-separated, for help and error messages.
std::string samplerChoiceNames();

// The material with the chosen sampler: eval is always the material's, sample/pdf the sampler's.
// Throws btf::Error as makeSampler does for invalid options, and for octree-bound on a material
// that is not an octree table.
std::shared_ptr<const Material> withSampler(SamplerChoice choice, std::shared_ptr<const Material> material,
                                            const SamplerOptions& options);

// The samplers that tabulate one BRDF (the binned samplers and octree-bound): a BTF, which varies
// over the surface, takes none of them.
bool tabulatesOneBrdf(SamplerChoice choice);

// Bytes of the tables a sampled material holds beside its material (0 for the hemisphere warps and
// a material's own sampler; the .bsdf file's bytes for dj-warp).
std::size_t samplerTableBytes(const Material& sampled);

// One draw of a direction with its pdf and nothing else where the sampler allows it (warps and the
// tabulated samplers); a material's own sampler can only be called through sample(), which also
// evaluates the weight. What "samples_per_s" times. Nothing when the draw returns no direction.
std::optional<glm::vec3> drawDirection(const Material& sampled, const glm::vec3& wo, glm::vec2 u, float& pdf);

}  // namespace btf
