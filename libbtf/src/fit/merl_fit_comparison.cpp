// compareMerlFits: how far the published fits of one material disagree in directional albedo.
#include <algorithm>

#include "btf/core/math.h"
#include "btf/fit/merl_fits.h"
#include "btf/material/albedo.h"

namespace btf {

MerlFitComparison compareMerlFits(const MerlFits& fits, std::string_view name, double threshold,
                                  const std::vector<float>& theta_o_deg) {
  MerlFitComparison result;
  result.name = fits.resolve(name);
  result.theta_o_deg = theta_o_deg;
  result.threshold = threshold;
  for (ModelFamily model : fits.modelsFor(result.name)) {
    const auto material = makeMerlFitMaterial(fits, result.name, model);
    FitAlbedos row{model, {}};
    for (float deg : theta_o_deg) row.albedo.push_back(integrateAlbedoHalfVector(*material, deg * kPi / 180.0f));
    result.fits.push_back(std::move(row));
  }
  if (result.fits.size() < 2) return result;
  // Mean over RGB rather than per channel: a channel with albedo 0.003 against 0.005 is not a
  // disagreement anyone would see.
  for (std::size_t a = 0; a < theta_o_deg.size(); ++a) {
    double lo = 1e300, hi = 0;
    for (const FitAlbedos& f : result.fits) {
      const double v = f.albedo[a].average();
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
    const double spread = hi > 0 ? (hi - lo) / hi : 0.0;
    if (spread > result.spread) {
      result.spread = spread;
      result.spread_theta_o_deg = theta_o_deg[a];
    }
  }
  result.disagree = result.spread > threshold;
  return result;
}

}  // namespace btf
