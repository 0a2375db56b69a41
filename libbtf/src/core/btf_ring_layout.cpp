#include "btf/core/btf_ring_layout.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "btf/core/btf_directions.h"
#include "btf/core/error.h"

namespace btf {
namespace {

// Lights within this elevation of a ring's first light join it: measured sets put their rings
// degrees apart, and a file's angles differ from the nominal ones in the last bits.
constexpr float kRingThetaToleranceDeg = 0.5f;
// Level 1's functions need a few lights each to repeat across texels; the measured sets' rings
// hold 6 to 24 (the pole's one aside).
constexpr int kMinMeanRingSize = 4;

float azimuthKey(float phi_deg) {
  const float p = std::fmod(phi_deg, 360.0f);
  return p < 0.0f ? p + 360.0f : p;
}

// Rings of the light list: elevation order, then azimuth order within a ring; long runs split.
std::vector<std::vector<int>> ringsOf(std::span<const BtfAngles> lights) {
  std::vector<int> by_theta(lights.size());
  std::iota(by_theta.begin(), by_theta.end(), 0);
  std::stable_sort(by_theta.begin(), by_theta.end(),
                   [&](int a, int b) { return lights[std::size_t(a)].theta_deg < lights[std::size_t(b)].theta_deg; });
  std::vector<std::vector<int>> rings;
  float first_theta = 0;
  for (const int l : by_theta) {
    const float theta = lights[std::size_t(l)].theta_deg;
    if (rings.empty() || theta - first_theta > kRingThetaToleranceDeg) {
      rings.emplace_back();
      first_theta = theta;
    }
    rings.back().push_back(l);
  }
  std::vector<std::vector<int>> out;
  for (std::vector<int>& ring : rings) {
    std::stable_sort(ring.begin(), ring.end(), [&](int a, int b) {
      return azimuthKey(lights[std::size_t(a)].phi_deg) < azimuthKey(lights[std::size_t(b)].phi_deg);
    });
    for (std::size_t i = 0; i < ring.size(); i += BtfRingLayout::kBandSize)
      out.emplace_back(ring.begin() + std::ptrdiff_t(i),
                       ring.begin() + std::ptrdiff_t(std::min(ring.size(), i + BtfRingLayout::kBandSize)));
  }
  // Scattered: rings of fewer than kMinMeanRingSize lights on average (elevations nearly all
  // distinct, a few lights sharing one by chance). Bands of consecutive elevations instead.
  if (lights.size() > 1 && out.size() * std::size_t(kMinMeanRingSize) > lights.size()) {
    out.clear();
    for (std::size_t i = 0; i < by_theta.size(); i += BtfRingLayout::kBandSize)
      out.emplace_back(by_theta.begin() + std::ptrdiff_t(i),
                       by_theta.begin() + std::ptrdiff_t(std::min(by_theta.size(), i + BtfRingLayout::kBandSize)));
  }
  return out;
}

}  // namespace

BtfRingLayout::BtfRingLayout(std::vector<int> sizes, std::vector<int> order) : sizes_(std::move(sizes)), order_(std::move(order)) {
  std::size_t total = 0;
  for (const int n : sizes_) {
    if (n < 1 || n > kBandSize)
      throw Error("a ring layout has a ring of " + std::to_string(n) + " lights (1 to " + std::to_string(kBandSize) + ")");
    total += std::size_t(n);
    starts_.push_back(int(total) - n);
    max_size_ = std::max(max_size_, n);
  }
  if (sizes_.empty() || total != order_.size())
    throw Error("a ring layout's rings hold " + std::to_string(total) + " lights, its order " +
                std::to_string(order_.size()));
  ring_of_.assign(order_.size(), -1);
  place_of_.assign(order_.size(), -1);
  for (int r = 0; r < ringCount(); ++r)
    for (int a = 0; a < size(r); ++a) {
      const int l = order_[std::size_t(start(r) + a)];
      if (l < 0 || std::size_t(l) >= order_.size() || ring_of_[std::size_t(l)] >= 0)
        throw Error("a ring layout's order is not a permutation of its " + std::to_string(order_.size()) + " lights");
      ring_of_[std::size_t(l)] = r;
      place_of_[std::size_t(l)] = a;
      in_order_ = in_order_ && l == start(r) + a;
    }
}

const BtfRingLayout& BtfRingLayout::ubo2003() {
  static const BtfRingLayout layout = [] {
    std::vector<int> order(kBtfDirectionCount);
    std::iota(order.begin(), order.end(), 0);
    return BtfRingLayout(std::vector<int>(kBtfRingSizes.begin(), kBtfRingSizes.end()), std::move(order));
  }();
  return layout;
}

BtfRingLayout BtfRingLayout::of(const BtfDirectionSet& set, const std::string& what) {
  const BtfDirectionSet& reference = set.nominal() ? *set.nominal() : set;
  if (reference.isUbo2003()) return ubo2003();
  for (int v = 1; v < set.viewCount(); ++v)
    if (set.lightCount(v) != set.lightCount(0))
      throw Error(what + " needs the same number of lights in every view; " + set.describe() + " has " +
                  std::to_string(set.lightCount(v)) + " in view " + std::to_string(v) + " (" + set.describeView(v) +
                  ") and " + std::to_string(set.lightCount(0)) + " in view 0");
  std::vector<int> sizes, order;
  for (const std::vector<int>& ring : ringsOf(reference.lights(0))) {
    sizes.push_back(int(ring.size()));
    order.insert(order.end(), ring.begin(), ring.end());
  }
  return BtfRingLayout(std::move(sizes), std::move(order));
}

std::string BtfRingLayout::describe() const {
  std::string text = std::to_string(ringCount()) + (ringCount() == 1 ? " ring of " : " rings of ");
  for (int r = 0; r < ringCount(); ++r) text += (r ? ", " : "") + std::to_string(size(r));
  return text + " lights";
}

}  // namespace btf
