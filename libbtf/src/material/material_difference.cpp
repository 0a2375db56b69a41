#include "btf/material/material_difference.h"

#include <algorithm>
#include <cmath>

#include "btf/core/error.h"
#include "btf/core/half_diff.h"
#include "btf/core/math.h"
#include "btf/core/rng.h"
#include "btf/material/albedo.h"

namespace btf {
namespace {

const float kCos80 = std::cos(80.0f * kPi / 180.0f);

}  // namespace

MaterialDifference compareMaterials(const Material& material, const Material& reference,
                                    const MaterialDifferenceOptions& options) {
  if (material.isAnisotropic() || reference.isAnisotropic())
    throw Error("compareMaterials measures isotropic materials; " +
                (material.isAnisotropic() ? material.name() : reference.name()) + " is anisotropic");
  MaterialDifference d;
  Rng rng(options.seed);
  double error = 0, norm = 0;
  for (std::uint32_t k = 0; k < options.pair_count; ++k) {
    HalfDiff hd;
    const float t = rng.uniform();
    hd.theta_h = kHalfPi * t * t;
    hd.phi_h = kTwoPi * rng.uniform();
    hd.theta_d = kHalfPi * rng.uniform();
    hd.phi_d = kTwoPi * rng.uniform();
    const DirectionPair p = fromHalfDiff(hd);
    if (!(p.wi.z >= kCos80) || !(p.wo.z >= kCos80)) continue;
    ++d.pairs;
    const Rgb f = material.eval(p.wi, p.wo), f_ref = reference.eval(p.wi, p.wo);
    for (int c = 0; c < 3; ++c) {
      const double e = double(p.wi.z) * (double(f[c]) - double(f_ref[c])), r = double(p.wi.z) * double(f_ref[c]);
      error += e * e;
      norm += r * r;
    }
  }
  d.fcos_rel_rmse = norm > 0 ? std::sqrt(error / norm) : (error > 0 ? INFINITY : 0.0);
  d.theta_o_deg = options.theta_o_deg;
  for (const float theta : d.theta_o_deg) {
    const Rgb a = integrateAlbedoHalfVector(material, theta * kPi / 180.0f, options.albedo_theta_h_steps,
                                            options.albedo_phi_h_steps);
    const Rgb r = integrateAlbedoHalfVector(reference, theta * kPi / 180.0f, options.albedo_theta_h_steps,
                                            options.albedo_phi_h_steps);
    d.albedo.push_back(a);
    d.reference_albedo.push_back(r);
    for (int c = 0; c < 3; ++c)
      if (r[c] >= 1e-3f) d.max_albedo_rel_error = std::max(d.max_albedo_rel_error, std::abs(double(a[c]) - r[c]) / r[c]);
  }
  return d;
}

}  // namespace btf
