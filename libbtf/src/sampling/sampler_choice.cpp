#include "btf/sampling/sampler_choice.h"

#include <array>
#include <utility>

#include "btf/core/error.h"
#include "btf/sampling/octree_bound_sampler.h"
#include "btf/sampling/rgl_warp_sampler.h"
#include "btf/core/warp.h"

namespace btf {
namespace {

constexpr std::array<std::pair<SamplerChoice, std::string_view>, 8> kNames = {{
    {SamplerChoice::Uniform, "uniform"},
    {SamplerChoice::Cosine, "cosine"},
    {SamplerChoice::Own, "material"},
    {SamplerChoice::Tabulated, "tabulated"},
    {SamplerChoice::DpCdf, "dp-cdf"},
    {SamplerChoice::Quadtree, "quadtree"},
    {SamplerChoice::OctreeBound, "octree-bound"},
    {SamplerChoice::DjWarp, "dj-warp"},
}};

// A material sampled by a fixed hemisphere warp: what a renderer without importance sampling does.
class WarpSampled final : public Material {
 public:
  WarpSampled(std::shared_ptr<const Material> material, bool cosine) : material_(std::move(material)), cosine_(cosine) {}

  Rgb eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv) const override { return material_->eval(wi, wo, uv); }
  std::optional<BsdfSample> sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const override {
    float pdf = 0;
    const glm::vec3 wi = draw(u, pdf);
    if (!(pdf > 0)) return std::nullopt;
    return BsdfSample{wi, material_->eval(wi, wo, uv) * (wi.z / pdf), pdf};
  }
  float pdf(const glm::vec3& wi, const glm::vec3&, glm::vec2) const override {
    return cosine_ ? cosineHemispherePdf(wi) : uniformHemispherePdf(wi);
  }
  std::string name() const override { return material_->name() + (cosine_ ? " [cosine]" : " [uniform]"); }
  bool isAnisotropic() const override { return material_->isAnisotropic(); }

  glm::vec3 draw(glm::vec2 u, float& pdf) const {
    const glm::vec3 wi = cosine_ ? squareToCosineHemisphere(u) : squareToUniformHemisphere(u);
    pdf = cosine_ ? cosineHemispherePdf(wi) : uniformHemispherePdf(wi);
    return wi;
  }

 private:
  std::shared_ptr<const Material> material_;
  bool cosine_;
};

}  // namespace

std::string_view toString(SamplerChoice choice) {
  for (const auto& [c, name] : kNames)
    if (c == choice) return name;
  return "?";
}

std::optional<SamplerChoice> parseSamplerChoice(std::string_view name) {
  for (const auto& [c, n] : kNames)
    if (n == name) return c;
  return std::nullopt;
}

std::string samplerChoiceNames() {
  std::string names;
  for (const auto& [c, n] : kNames) names += (names.empty() ? "" : ", ") + std::string(n);
  return names;
}

std::shared_ptr<const Material> withSampler(SamplerChoice choice, std::shared_ptr<const Material> material,
                                            const SamplerOptions& options) {
  switch (choice) {
    case SamplerChoice::Uniform: return std::make_shared<WarpSampled>(std::move(material), false);
    case SamplerChoice::Cosine: return std::make_shared<WarpSampled>(std::move(material), true);
    case SamplerChoice::Own: return material;
    case SamplerChoice::Tabulated: return makeSampler(SamplerKind::Tabulated, std::move(material), options);
    case SamplerChoice::DpCdf: return makeSampler(SamplerKind::DpCdf, std::move(material), options);
    case SamplerChoice::Quadtree: return makeSampler(SamplerKind::Quadtree, std::move(material), options);
    case SamplerChoice::DjWarp: return std::make_shared<RglWarpSampler>(std::move(material));
    case SamplerChoice::OctreeBound: {
      auto octree = std::dynamic_pointer_cast<const OctreeBrdf>(material);
      if (!octree)
        throw Error("sampler 'octree-bound' reads the node bounds of an octree table; " +
                    (material ? material->name() : std::string("no material")) + " is not one (convert it with btf convert ... .octree)");
      return std::make_shared<OctreeBoundSampler>(std::move(octree));
    }
  }
  throw Error("unknown sampler choice");
}

bool tabulatesOneBrdf(SamplerChoice choice) {
  return choice == SamplerChoice::Tabulated || choice == SamplerChoice::DpCdf || choice == SamplerChoice::Quadtree ||
         choice == SamplerChoice::OctreeBound || choice == SamplerChoice::DjWarp;
}

std::size_t samplerTableBytes(const Material& sampled) {
  if (const auto* binned = dynamic_cast<const BinnedSampler*>(&sampled)) return binned->stats().bytes;
  if (const auto* octree = dynamic_cast<const OctreeBoundSampler*>(&sampled)) return octree->bytes();
  if (const auto* warp = dynamic_cast<const RglWarpSampler*>(&sampled)) return warp->bytes();
  return 0;
}

std::optional<glm::vec3> drawDirection(const Material& sampled, const glm::vec3& wo, glm::vec2 u, float& pdf) {
  if (const auto* warp = dynamic_cast<const WarpSampled*>(&sampled)) return warp->draw(u, pdf);
  if (const auto* binned = dynamic_cast<const BinnedSampler*>(&sampled)) {
    int tries = 0;
    const auto d = binned->sampleDirection(wo, u, tries);
    if (!d) return std::nullopt;
    pdf = d->pdf;
    return d->wi;
  }
  if (const auto* warp = dynamic_cast<const RglWarpSampler*>(&sampled)) {
    const auto d = warp->sampleDirection(wo, u);
    if (!d) return std::nullopt;
    pdf = d->pdf;
    return d->wi;
  }
  if (const auto* octree = dynamic_cast<const OctreeBoundSampler*>(&sampled)) {
    const auto d = octree->sampleDirection(wo, u);
    if (!d) return std::nullopt;
    pdf = d->pdf;
    return d->wi;
  }
  const auto s = sampled.sample(wo, {}, u);
  if (!s) return std::nullopt;
  pdf = s->pdf;
  return s->wi;
}

}  // namespace btf
