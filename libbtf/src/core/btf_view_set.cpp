#include "btf/core/btf_view_set.h"

#include <algorithm>
#include <cstdio>
#include <numeric>

#include "btf/core/error.h"

namespace btf {

std::string describeBtfDirection(int index) {
  const BtfDirection& d = btfDirections().at(std::size_t(index));
  char text[64];
  std::snprintf(text, sizeof text, "theta %g, phi %g", double(d.theta_deg), double(d.phi_deg));
  return text;
}

BtfViewSet::BtfViewSet() : views_(kBtfDirectionCount) {
  std::iota(views_.begin(), views_.end(), 0);
  std::iota(slots_.begin(), slots_.end(), std::int16_t(0));
}

BtfViewSet::BtfViewSet(std::vector<int> views) : views_(std::move(views)) {
  if (views_.empty()) throw Error("a BTF needs at least one view");
  std::sort(views_.begin(), views_.end());
  slots_.fill(-1);
  for (std::size_t i = 0; i < views_.size(); ++i) {
    const int v = views_[i];
    if (v < 0 || v >= kBtfDirectionCount)
      throw Error("BTF view index " + std::to_string(v) + " is out of range (0 .. " +
                  std::to_string(kBtfDirectionCount - 1) + ")");
    if (slots_[std::size_t(v)] >= 0) throw Error("BTF view (" + describeBtfDirection(v) + ") is listed twice");
    slots_[std::size_t(v)] = std::int16_t(i);
  }
}

BtfViewSet BtfViewSet::upToTheta(float max_theta_deg) {
  std::vector<int> views;
  for (int v = 0; v < kBtfDirectionCount; ++v)
    if (v == 0 || btfDirections()[std::size_t(v)].theta_deg <= max_theta_deg + 1e-3f) views.push_back(v);
  return BtfViewSet(std::move(views));
}

int BtfViewSet::completeRingsFromPole() const {
  int rings = 0;
  for (int r = 0; r < kBtfRingCount; ++r) {
    for (int a = 0; a < btfRingSize(r); ++a)
      if (!contains(btfDirectionIndex(r, a))) return rings;
    ++rings;
  }
  return rings;
}

std::string BtfViewSet::describe() const {
  if (complete()) return "all 81 views";
  const int n = count();
  const std::string counted = std::to_string(n) + (n == 1 ? " view" : " views");
  const int rings = completeRingsFromPole();
  if (rings > 0 && n == btfRingStart(rings - 1) + btfRingSize(rings - 1)) {
    if (n == 1) return counted + " (" + describeBtfDirection(views_[0]) + ")";
    char text[64];
    std::snprintf(text, sizeof text, " (all up to theta %g)", double(btfRingThetaDeg(rings - 1)));
    return counted + text;
  }
  constexpr int kListed = 4;
  std::string text = counted + ": ";
  for (int i = 0; i < std::min(n, kListed); ++i) text += (i ? ", (" : "(") + describeBtfDirection(views_[std::size_t(i)]) + ")";
  if (n > kListed) text += ", ...";
  return text;
}

void BtfViewSet::require(int view, const std::string& what) const {
  if (view < 0 || view >= kBtfDirectionCount)
    throw Error(what + ": view index " + std::to_string(view) + " is out of range (0 .. " +
                std::to_string(kBtfDirectionCount - 1) + ")");
  if (!contains(view))
    throw Error(what + ": view (" + describeBtfDirection(view) + ") is not in this BTF (it holds " + describe() + ")");
}

}  // namespace btf
