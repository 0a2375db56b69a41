// Directional albedo rho(wo) = int f(wi, wo) cos(theta_i) dwi of a material: the fraction of light
// from wo (by reciprocity, towards wo) that is reflected. A physical material has rho <= 1.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>

#include "btf/core/rgb.h"
#include "btf/material/material.h"

namespace btf {

struct AlbedoEstimate {
  Rgb value;           // the estimate per channel
  Rgb standard_error;  // one standard error of the estimate per channel
};

// Monte Carlo with the material's own importance sampling (a draw that returns nothing counts as
// 0). Deterministic for a seed: the samples are split into fixed chunks, each with its own RNG
// stream, summed in chunk order, so the result does not depend on the number of threads.
// sample_count must be >= 2 (throws btf::Error).
AlbedoEstimate estimateAlbedo(const Material& m, const glm::vec3& wo, std::uint32_t sample_count,
                              std::uint64_t seed = 0);

// Deterministic quadrature for isotropic materials, with wo at (theta_o, phi = 0): integrates over
// half vectors h, wi = reflect(wo, h), dwi = 4 (wo.h) dwh. theta_h is sampled densely near the
// normal (theta_h = pi/2 t^2 with t uniform, as MERL tables are indexed) so sharp specular peaks
// are resolved; wi below the horizon contributes nothing. Throws btf::Error for an anisotropic
// material, theta_o outside [0, pi/2) or non-positive step counts.
Rgb integrateAlbedoHalfVector(const Material& m, float theta_o, int theta_h_steps = 256, int phi_h_steps = 512);

}  // namespace btf
