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

BtfViewSet::BtfViewSet() : directions_(BtfDirectionSet::ubo2003()) { holdAll(); }

BtfViewSet BtfViewSet::all(BtfDirectionSetPtr directions) {
  BtfViewSet set;
  set.directions_ = std::move(directions);
  set.holdAll();
  return set;
}

void BtfViewSet::holdAll() {
  views_.resize(std::size_t(directions_->viewCount()));
  std::iota(views_.begin(), views_.end(), 0);
  slots_.assign(views_.begin(), views_.end());
}

BtfViewSet::BtfViewSet(std::vector<int> views, BtfDirectionSetPtr directions)
    : directions_(std::move(directions)), views_(std::move(views)) {
  if (views_.empty()) throw Error("a BTF needs at least one view");
  std::sort(views_.begin(), views_.end());
  const int total = directions_->viewCount();
  slots_.assign(std::size_t(total), -1);
  for (std::size_t i = 0; i < views_.size(); ++i) {
    const int v = views_[i];
    if (v < 0 || v >= total)
      throw Error("BTF view index " + std::to_string(v) + " is out of range (0 .. " + std::to_string(total - 1) + ")");
    if (slots_[std::size_t(v)] >= 0) throw Error("BTF view (" + directions_->describeView(v) + ") is listed twice");
    slots_[std::size_t(v)] = std::int32_t(i);
  }
}

BtfViewSet BtfViewSet::upToTheta(float max_theta_deg, BtfDirectionSetPtr directions) {
  float lowest = 90.0f;
  for (int v = 0; v < directions->viewCount(); ++v) lowest = std::min(lowest, directions->viewAngles(v).theta_deg);
  std::vector<int> views;
  for (int v = 0; v < directions->viewCount(); ++v) {
    const float theta = directions->viewAngles(v).theta_deg;
    if (theta <= lowest || theta <= max_theta_deg + 1e-3f) views.push_back(v);
  }
  return BtfViewSet(std::move(views), std::move(directions));
}

int BtfViewSet::completeRingsFromPole() const {
  if (!directions_->indexedAsUbo2003()) return 0;
  int rings = 0;
  for (int r = 0; r < kBtfRingCount; ++r) {
    for (int a = 0; a < btfRingSize(r); ++a)
      if (!contains(btfDirectionIndex(r, a))) return rings;
    ++rings;
  }
  return rings;
}

std::string BtfViewSet::describe() const {
  if (complete())
    return "all " + std::to_string(count()) + " views" +
           (directions_->isUbo2003() ? std::string() : " (" + directions_->name() + ")");
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
  for (int i = 0; i < std::min(n, kListed); ++i)
    text += (i ? ", (" : "(") + directions_->describeView(views_[std::size_t(i)]) + ")";
  if (n > kListed) text += ", ...";
  return text;
}

void BtfViewSet::requireUbo2003(const std::string& what) const {
  if (!directions_->indexedAsUbo2003())
    throw Error(what + " needs the 81-direction UBO2003 set; this BTF is on " + directions_->describe());
}

void BtfViewSet::require(int view, const std::string& what) const {
  const int total = directions_->viewCount();
  if (view < 0 || view >= total)
    throw Error(what + ": view index " + std::to_string(view) + " is out of range (0 .. " + std::to_string(total - 1) + ")");
  if (!contains(view))
    throw Error(what + ": view (" + directions_->describeView(view) + ") is not in this BTF (it holds " + describe() + ")");
}

}  // namespace btf
