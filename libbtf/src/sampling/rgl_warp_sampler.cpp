#include "btf/sampling/rgl_warp_sampler.h"

#include <utility>

namespace btf {

RglWarpSampler::RglWarpSampler(std::shared_ptr<const Material> material, const RglAcquisitionOptions& options)
    : RglWarpSampler(material, inMemoryTensorFile(acquireRglFields(*material, options), material->name() + ".bsdf")) {}

RglWarpSampler::RglWarpSampler(std::shared_ptr<const Material> material, const TensorFile& file)
    : material_(std::move(material)), warp_(file), bytes_(file.file_size) {}

std::optional<BsdfSample> RglWarpSampler::sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const {
  const auto d = warp_.sampleDirection(wo, u);
  if (!d) return std::nullopt;
  return BsdfSample{d->wi, material_->eval(d->wi, wo, uv) * (d->wi.z / d->pdf), d->pdf};
}

float RglWarpSampler::pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2) const { return warp_.pdf(wi, wo); }

}  // namespace btf
