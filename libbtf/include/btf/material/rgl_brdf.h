// A measured material of the RGL database (Dupuy & Jakob 2018, "An Adaptive Parameterization for
// Efficient Material Acquisition and Rendering"), read from its `tensor_file` (.bsdf).
//
// The file parameterizes reflection by the view direction (the fixed direction, our wo) and the
// microfacet normal m = normalize(wi + wo):
// - `vndf` (per theta_o): a bilinear warp from the unit square to m's unit coordinates
//   u_m = (sqrt(theta_m / (pi/2)), (phi_m - phi_o + pi) / (2 pi)), with density proportional to the
//   visible normal distribution D(m) <m.wo> / sigma(wo). Isotropic files store phi_m relative to
//   phi_o, so each theta_o has one slice.
// - `luminance` (per theta_o, R x R over the square the VNDF warp starts from): a bilinear warp
//   towards where the reflected luminance is, applied before the VNDF warp.
// - `rgb` (per theta_o and channel, R x R over the same square): reflectance, such that
//   f(wi, wo) cos(theta_i) = rgb(s) * D(m) / (4 sigma(wo)) where s is the square point that the
//   VNDF warp maps to m (found by inverting it). When the file's `jacobian` flag is 0 the table
//   already includes the factor D / (4 sigma) and is used alone (as Mitsuba 3 does).
// - `ndf` and `sigma`: D(m) over u_m, and the projected area sigma over the direction's unit
//   coordinates.
//
// eval inverts the VNDF warp at m, interpolates rgb there (negative, out-of-gamut values clamp to
// 0, as in the reference loader), and divides by cos(theta_i) to return f in 1/sr.
// sample draws the luminance warp, then the VNDF warp, and reflects wo about m; its pdf is the
// product of both warps' densities times the Jacobians of u_m -> m (2 pi^2 u_m.x sin(theta_m),
// held at 1e-6 or more as in the reference loader, see rgl_brdf.cpp) and m -> wi (4 <wo.m>), in
// solid angle. pdf() evaluates that density through the inverse maps, and sample() returns pdf()
// of the wi it drew (and the weight through the same inverse maps), so the two agree exactly.
// Draws whose wi falls below the horizon, or whose m faces away from wo, return nothing (the pdf
// integrates to the probability of a sample).
//
// Convention: in the reference loader the fixed direction is called wi and the sampled one wo; in
// libbtf sample() draws wi given wo, so our wo plays the file's "incident" role throughout.
//
// Colour: the `rgb` table, or, in a file without one (the RGL database's spectral downloads) or
// when asked for (RglChannels::Spectra), the `spectra` table (per theta_o, wavelength and node)
// turned into linear sRGB per node under D65 by the CIE 1931 observer (btf/core/cie.h). That is
// linear, so interpolating the converted nodes is what integrating a spectral renderer's per-
// wavelength lookups gives, except where a file holds negative spectral values: pbrt-v4 clips each
// wavelength before integrating, this reader the interpolated RGB.
// Supported: isotropic files (phi_i has one value). Anisotropic files (several phi_i) are rejected
// with a FileError that says so. Nothing is allocated per eval/sample/pdf call; all calls are thread-safe.
#pragma once

#include <filesystem>
#include <optional>
#include <span>
#include <utility>
#include <string>
#include <vector>

#include "btf/io/rgl_tensor.h"
#include "btf/material/material.h"
#include "btf/core/bilinear_warp2d.h"

namespace btf {

// Which colour table of the file RglBrdf reads.
enum class RglChannels {
  Rgb,      // `rgb`, or `spectra` where the file has no `rgb`
  Spectra,  // `spectra` (a file without it is refused)
};

class RglBrdf final : public Material {
 public:
  // Throws btf::FileError for unreadable, corrupt or unsupported files.
  explicit RglBrdf(const std::filesystem::path& path, RglChannels channels = RglChannels::Rgb);
  explicit RglBrdf(const TensorFile& file, RglChannels channels = RglChannels::Rgb);

  Rgb eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::optional<BsdfSample> sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const override;
  float pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  // The direction sample() draws and its pdf, without the RGB lookup of the weight (the warp's own
  // cost, for callers that evaluate another material at wi: the `dj-warp` sampler).
  struct DirectionSample {
    glm::vec3 wi;
    float pdf;
  };
  std::optional<DirectionSample> sampleDirection(const glm::vec3& wo, glm::vec2 u) const;
  // wo's angles, unit coordinates, warp slices and projected area are found once for all wi, and
  // eight wi run per step in AVX2 lanes where the CPU has them: eval()'s floats bit for bit.
  void evalMany(const glm::vec3& wo, std::span<const glm::vec3> wi, std::span<Rgb> out,
                glm::vec2 uv = {}) const override;
  std::string name() const override;

  const std::string& description() const { return description_; }
  // Resolution R of the luminance and RGB tables (R x R per theta_o).
  int resolution() const { return luminance_.width(); }
  // Resolution of the VNDF warp (theta_m x phi_m nodes).
  int vndfResolution() const { return vndf_.width(); }
  const std::vector<float>& thetaSamples() const { return theta_o_; }

 private:
  // What depends on wo alone: its angles and unit coordinates, the VNDF warp and RGB table at its
  // theta_o, and the projected area sigma(wo). Every query sets it up once (evalMany once for all
  // its wi); the luminance warp only the queries that need a pdf.
  struct Outgoing {
    float theta_o;
    float phi_o_turns;  // wo's azimuth / (2 pi) (fastAtan2Turns), which m's azimuth is taken relative to
    glm::vec2 u_o;
    BilinearWarp2D::Fixed vndf, rgb;
    float sigma;  // only with jacobian_
  };
  BilinearWarp2D::Fixed luminanceAt(const Outgoing& o) const;
  Outgoing outgoing(const glm::vec3& wo) const;
  // f cos(theta_i) per channel at the square point s (VNDF domain) and m's unit coordinates u_m.
  Rgb reflectanceTimesCos(glm::vec2 s, glm::vec2 u_m, const Outgoing& o) const;
  // (wi, wo) through the inverse maps: m's unit coordinates, the VNDF square point s, and (given
  // the luminance warp at wo) the solid-angle density of sample(), 0 where it is not finite. eval,
  // pdf and sample all go through it, so that they agree exactly.
  // m's unit coordinates: theta_m through a square root, phi_m relative to wo's; sin_theta_m is
  // |m.xy|, which the caller also needs for the Jacobian. The angles come from fastAtan2Turns, not
  // std::atan2, which is a large share of an eval (`btf bench` measures eval speed).
  static glm::vec2 halfVectorUnit(const glm::vec3& m, float sin_theta_m, const Outgoing& o);
  struct InverseMap {
    glm::vec2 s{0.0f}, u_m{0.0f};
    float pdf = 0.0f;
  };
  InverseMap mapBack(const glm::vec3& wi, const glm::vec3& wo, const Outgoing& o,
                     const BilinearWarp2D::Fixed* luminance) const;
  Rgb evalWith(const glm::vec3& wi, const glm::vec3& wo, const Outgoing& o) const;
  // sample()'s draw: wi and its inverse map (pdf included), or nothing where it returns nothing.
  std::optional<std::pair<glm::vec3, InverseMap>> draw(const glm::vec3& wo, const Outgoing& o,
                                                       const BilinearWarp2D::Fixed& luminance, glm::vec2 u) const;
  // evalWith for the leading multiple of 8 of wi in AVX2 lanes (rgl_eval_lanes.cpp), the same
  // floats; returns how many it did (0 without AVX2).
  std::size_t evalLanes(const glm::vec3& wo, const Outgoing& o, std::span<const glm::vec3> wi,
                        std::span<Rgb> out) const;

  std::string stem_;
  std::string description_;
  std::vector<float> theta_o_;
  bool jacobian_ = true;
  BilinearWarp2D ndf_, sigma_;      // interpolants over unit direction coordinates
  BilinearWarp2D vndf_, luminance_; // distributions, parameter theta_o
  BilinearWarp2D rgb_;              // interpolant, parameters theta_o and channel
};

}  // namespace btf
