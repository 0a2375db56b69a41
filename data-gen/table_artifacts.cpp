#include "table_artifacts.h"

#include <tbb/parallel_for.h>

#include <atomic>
#include <cmath>

#include "btf/core/half_diff.h"
#include "btf/core/math.h"
#include "btf/core/progress.h"
#include "btf/core/rng.h"

namespace btf::datagen {
namespace {

// Largest polar angle of the light and view directions a cell stands for.
float steepestTheta(int theta_h, int theta_d, int phi_d) {
  const DirectionPair pair = MerlTable::directionsOf(theta_h, theta_d, phi_d);
  return std::max(sphericalTheta(pair.wi), sphericalTheta(pair.wo));
}

}  // namespace

std::size_t applyArtifacts(MerlTable& table, const TableArtifacts& artifacts, std::uint64_t seed) {
  const float grazing_limit = (90.0f - artifacts.grazing_gap_degrees) * kPi / 180.0f;
  const float sigma = artifacts.noise_sigma;
  std::atomic<std::size_t> holes{0};
  Progress progress("measurement artifacts", MerlTable::kThetaHalfRes);
  tbb::parallel_for(0, MerlTable::kThetaHalfRes, [&](int th) {
    std::size_t row_holes = 0;
    for (int td = 0; td < MerlTable::kThetaDiffRes; ++td) {
      for (int pd = 0; pd < MerlTable::kPhiDiffRes; ++pd) {
        const std::size_t i = MerlTable::index(th, td, pd);
        if (!table.isMeasured(i)) continue;
        Rng rng(seed, i);
        const bool dropped = rng.uniform() < artifacts.hole_fraction ||
                             (artifacts.grazing_gap_degrees > 0 && steepestTheta(th, td, pd) > grazing_limit);
        if (dropped) {
          table.setUnmeasured(i);
          ++row_holes;
          continue;
        }
        if (sigma <= 0) continue;
        NormalDeviates normal(rng);
        for (int c = 0; c < 3; ++c) table.raw(c, i) *= std::exp(sigma * normal.next() - 0.5f * sigma * sigma);
      }
    }
    holes += row_holes;
    progress.advance();
  });
  return holes;
}

}  // namespace btf::datagen
