// The warp of Dupuy & Jakob 2018 as a sampler of any isotropic material (`dj-warp`): the material
// is written to an RGL file in memory by virtual acquisition (material/rgl_acquisition.h) and
// sampled through that file's luminance and VNDF warps, while eval stays the material's own. It
// is how a renderer that reads RGL files samples a table converted for it, so `btf bench sampling`
// can compare it with libbtf's tabulated samplers built from the same table, each at the bytes it
// needs (bytes(): the .bsdf file's).
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "btf/material/material.h"
#include "btf/material/rgl_acquisition.h"
#include "btf/material/rgl_brdf.h"

namespace btf {

class RglWarpSampler final : public Material {
 public:
  // Throws btf::Error as acquireRglFields does (an anisotropic material, NaN or negative values).
  explicit RglWarpSampler(std::shared_ptr<const Material> material, const RglAcquisitionOptions& options = {});

  Rgb eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override {
    return material_->eval(wi, wo, uv);
  }
  void evalMany(const glm::vec3& wo, std::span<const glm::vec3> wi, std::span<Rgb> out,
                glm::vec2 uv = {}) const override {
    material_->evalMany(wo, wi, out, uv);
  }
  std::optional<BsdfSample> sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const override;
  float pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::string name() const override { return material_->name() + " [dj-warp]"; }

  // The direction and its pdf without the weight's eval.
  std::optional<RglBrdf::DirectionSample> sampleDirection(const glm::vec3& wo, glm::vec2 u) const {
    return warp_.sampleDirection(wo, u);
  }
  const Material& material() const { return *material_; }
  std::size_t bytes() const { return bytes_; }

 private:
  RglWarpSampler(std::shared_ptr<const Material> material, const TensorFile& file);
  std::shared_ptr<const Material> material_;
  RglBrdf warp_;
  std::size_t bytes_;
};

}  // namespace btf
