// The interface every reflectance model implements: analytic models, tabulated measurements,
// compressed BTFs. Directions are unit vectors in the local shading frame (+z = normal), both
// pointing away from the surface; wi is the incoming (light) direction, wo the outgoing (view).
#pragma once

#include <glm/glm.hpp>

#include <optional>
#include <span>
#include <string>

#include "btf/core/rgb.h"

namespace btf {

struct BsdfSample {
  glm::vec3 wi;  // sampled incoming direction
  Rgb weight;    // f(wi, wo) * cos(theta_i) / pdf
  float pdf;     // solid-angle density of wi, equal to Material::pdf(wi, wo, uv)
};

class Material {
 public:
  virtual ~Material() = default;

  // Reflectance f(wi, wo) in 1/sr; zero when either direction is below the horizon.
  virtual Rgb eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const = 0;
  // Draws wi for the given wo from two uniform numbers in [0,1)^2, or nothing when the draw falls
  // where the material reflects nothing (the pdf then integrates to the probability of a sample).
  virtual std::optional<BsdfSample> sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const = 0;
  // Solid-angle density with which sample() returns wi; agrees with sample() exactly.
  virtual float pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const = 0;

  // eval(wi[k], wo, uv) into out[k] for every k, the same floats: the stream form a renderer or a
  // sampler's stream call uses to weight many draws at one wo. Materials that set up work per wo
  // (an RGL file's warps) do it once here. Throws btf::Error when the spans' sizes differ.
  virtual void evalMany(const glm::vec3& wo, std::span<const glm::vec3> wi, std::span<Rgb> out,
                        glm::vec2 uv = {}) const;
  // Short human-readable description, e.g. "ggx(alpha=0.2)".
  virtual std::string name() const = 0;
  // True when f depends on the azimuth of the half vector (phi_h) and not only on relative angles.
  virtual bool isAnisotropic() const { return false; }
  // True when eval(wi, wo) == eval(wo, wi) by construction (Helmholtz reciprocity). False, the
  // safe default, for measured data that is only approximately reciprocal; tabulate() then stores
  // the mean of both orders.
  virtual bool isReciprocal() const { return false; }

 protected:
  // evalMany's contract: as many outputs as directions (btf::Error otherwise).
  static void checkEvalManySizes(std::span<const glm::vec3> wi, std::span<const Rgb> out);
};

}  // namespace btf
