// How far one isotropic material is from another: what a conversion (an RGL file written from a
// material, a table made from a model) lost, in the two measures that matter to a renderer: the
// shape of f cos(theta_i) and the energy reflected.
#pragma once

#include <cstdint>
#include <vector>

#include "btf/core/rgb.h"
#include "btf/material/material.h"

namespace btf {

struct MaterialDifference {
  // sqrt(sum (cos_i (f - f_ref))^2) / sqrt(sum (cos_i f_ref)^2) over all channels of random
  // direction pairs with both directions within 80 degrees of the normal (the measure of btf fit,
  // analytic_fit.h), drawn as a MERL table spaces its cells: theta_h = pi/2 t^2, theta_d and
  // phi_d uniform, so that narrow lobes around the mirror direction get their share of pairs.
  double fcos_rel_rmse = 0;
  std::uint32_t pairs = 0;  // pairs within 80 degrees that the measure used
  // Directional albedo by deterministic quadrature (integrateAlbedoHalfVector) at these theta_o.
  std::vector<float> theta_o_deg;
  std::vector<Rgb> albedo, reference_albedo;
  // The largest |albedo - reference| / reference over the angles and channels, where a channel's
  // reference albedo is at least 1e-3 (a channel that reflects nothing has no relative error).
  double max_albedo_rel_error = 0;
};

struct MaterialDifferenceOptions {
  std::uint32_t pair_count = 200'000;
  std::uint64_t seed = 1;
  std::vector<float> theta_o_deg = {0.0f, 15.0f, 30.0f, 45.0f, 60.0f, 75.0f};
  // Of the albedo quadrature (integrateAlbedoHalfVector's defaults); fewer for slow materials.
  int albedo_theta_h_steps = 256, albedo_phi_h_steps = 512;
};

// Both materials must be isotropic (btf::Error otherwise); deterministic for the seed.
MaterialDifference compareMaterials(const Material& material, const Material& reference,
                                    const MaterialDifferenceOptions& options = {});

}  // namespace btf
