#include "btf/core/btf_direction_set.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "btf/core/btf_directions.h"
#include "btf/core/error.h"
#include "btf/core/math.h"

namespace btf {
namespace {

void checkAngles(const std::string& set, const std::vector<BtfAngles>& list, const char* what) {
  if (list.empty()) throw Error(set + ": the " + std::string(what) + " list is empty");
  if (list.size() > std::size_t(BtfDirectionSet::kMaxDirections))
    throw Error(set + ": " + std::to_string(list.size()) + " " + what + " directions, more than the " +
                std::to_string(BtfDirectionSet::kMaxDirections) + " any measurement records");
  for (std::size_t i = 0; i < list.size(); ++i) {
    const BtfAngles& a = list[i];
    if (!std::isfinite(a.theta_deg) || !std::isfinite(a.phi_deg) || a.theta_deg < 0.0f || a.theta_deg >= 90.0f) {
      char text[160];
      std::snprintf(text, sizeof text, "%s direction %zu has theta %g, phi %g (theta must lie in [0, 90) degrees)", what,
                    i, double(a.theta_deg), double(a.phi_deg));
      throw Error(set + ": " + text);
    }
  }
}

std::vector<glm::vec3> vectorsOf(const std::vector<BtfAngles>& list) {
  std::vector<glm::vec3> out;
  out.reserve(list.size());
  for (const BtfAngles& a : list) out.push_back(btfDirectionVector(a));
  return out;
}

std::string angleText(const BtfAngles& a) {
  char text[64];
  std::snprintf(text, sizeof text, "theta %g, phi %g", double(a.theta_deg), double(a.phi_deg));
  return text;
}

}  // namespace

glm::vec3 btfDirectionVector(const BtfAngles& angles) {
  // Rounded as btfDirections() rounds, so that the UBO2003 set's vectors are bit for bit its.
  return sphericalDirection(angles.theta_deg * kPi / 180.0f, angles.phi_deg * kPi / 180.0f);
}

BtfDirectionSet::BtfDirectionSet(std::string name, std::vector<BtfAngles> views,
                                 std::vector<std::vector<BtfAngles>> lights, std::shared_ptr<const BtfDirectionSet> nominal)
    : name_(std::move(name)), nominal_(std::move(nominal)), views_(std::move(views)), lights_(std::move(lights)) {
  checkAngles(name_, views_, "view");
  if (lights_.size() != views_.size())
    throw Error(name_ + ": " + std::to_string(lights_.size()) + " light lists for " + std::to_string(views_.size()) +
                " views");
  for (const std::vector<BtfAngles>& list : lights_) checkAngles(name_, list, "light");
  // One list when every view has the same: the common case, and what consumers that need a
  // tensor-product sampling ask for.
  if (std::all_of(lights_.begin(), lights_.end(), [&](const std::vector<BtfAngles>& l) { return l == lights_[0]; }))
    lights_.resize(1);
  finish();
  if (nominal_) {
    bool same_shape = nominal_->viewCount() == viewCount();
    for (int v = 0; same_shape && v < viewCount(); ++v) same_shape = nominal_->lightCount(v) == lightCount(v);
    if (!same_shape)
      throw Error(name_ + ": its nominal set (" + nominal_->describe() + ") has another number of views or lights");
  }
}

BtfDirectionSet::BtfDirectionSet(std::string name, std::vector<BtfAngles> views, std::vector<BtfAngles> shared_lights)
    : name_(std::move(name)), views_(std::move(views)) {
  checkAngles(name_, views_, "view");
  checkAngles(name_, shared_lights, "light");
  lights_.push_back(std::move(shared_lights));
  finish();
}

void BtfDirectionSet::finish() {
  shared_lights_ = lights_.size() == 1;
  view_dirs_ = vectorsOf(views_);
  light_dirs_.clear();
  for (const std::vector<BtfAngles>& list : lights_) light_dirs_.push_back(vectorsOf(list));
  max_lights_ = 0;
  pair_count_ = 0;
  for (int v = 0; v < viewCount(); ++v) {
    max_lights_ = std::max(max_lights_, lightCount(v));
    pair_count_ += std::size_t(lightCount(v));
  }
  // The UBO2003 set by content, whatever its name: a file that declares exactly these angles gets
  // the codecs built on its rings.
  ubo2003_ = false;
  if (shared_lights_ && viewCount() == kBtfDirectionCount && lightCount(0) == kBtfDirectionCount) {
    ubo2003_ = true;
    for (int i = 0; i < kBtfDirectionCount && ubo2003_; ++i) {
      ubo2003_ = findBtfDirection(views_[std::size_t(i)].theta_deg, views_[std::size_t(i)].phi_deg) == i &&
                 findBtfDirection(lights_[0][std::size_t(i)].theta_deg, lights_[0][std::size_t(i)].phi_deg) == i;
    }
  }
}

std::span<const BtfAngles> BtfDirectionSet::lights(int view) const {
  return shared_lights_ ? std::span<const BtfAngles>(lights_[0]) : std::span<const BtfAngles>(lights_[std::size_t(view)]);
}

std::span<const glm::vec3> BtfDirectionSet::lightDirections(int view) const {
  return shared_lights_ ? std::span<const glm::vec3>(light_dirs_[0])
                        : std::span<const glm::vec3>(light_dirs_[std::size_t(view)]);
}

const std::shared_ptr<const BtfDirectionSet>& BtfDirectionSet::ubo2003() {
  static const std::shared_ptr<const BtfDirectionSet> set = [] {
    std::vector<BtfAngles> angles;
    for (const BtfDirection& d : btfDirections()) angles.push_back({d.theta_deg, d.phi_deg});
    return std::make_shared<const BtfDirectionSet>("UBO2003", angles, angles);
  }();
  return set;
}

const std::shared_ptr<const BtfDirectionSet>& BtfDirectionSet::uboDome1() {
  static const std::shared_ptr<const BtfDirectionSet> set = [] {
    constexpr float kTheta[] = {0, 11, 23.5f, 30, 37.5f, 45, 52.5f, 60, 67.5f, 75};
    constexpr int kCount[] = {1, 6, 12, 12, 12, 18, 18, 24, 24, 24};
    constexpr float kOffset[] = {0, 15, 0, 15, 0, 0, 7.5f, 0, 7.5f, 0};
    std::vector<BtfAngles> angles;
    for (std::size_t r = 0; r < std::size(kTheta); ++r)
      for (int j = 0; j < kCount[r]; ++j) {
        float phi = kOffset[r] + 360.0f * float(j) / float(kCount[r]);
        if (phi >= 180.0f) phi = std::fmod(phi, 180.0f) - 180.0f;
        angles.push_back({kTheta[r], phi});
      }
    return std::make_shared<const BtfDirectionSet>("Bonn dome 1", angles, angles);
  }();
  return set;
}

std::string BtfDirectionSet::describeLights() const {
  if (shared_lights_) return std::to_string(lightCount(0)) + " lights";
  int min_lights = max_lights_;
  for (int v = 0; v < viewCount(); ++v) min_lights = std::min(min_lights, lightCount(v));
  return (min_lights == max_lights_ ? std::to_string(max_lights_)
                                    : std::to_string(min_lights) + " to " + std::to_string(max_lights_)) +
         " lights per view, view-dependent";
}

std::string BtfDirectionSet::describe() const {
  std::string text = std::to_string(viewCount()) + " views x " + describeLights();
  if (!name_.empty()) text += " (" + name_ + ")";
  return text;
}

std::string BtfDirectionSet::describeView(int view) const { return angleText(views_.at(std::size_t(view))); }

namespace {

// Files store radians or degrees, as float: the same direction read from two formats differs in
// the last bits. A thousandth of a degree is far below any gantry's accuracy and far above float
// rounding of an angle.
constexpr float kSameAngleDeg = 1e-3f;

bool sameDirection(const BtfAngles& a, const BtfAngles& b) {
  if (std::abs(a.theta_deg - b.theta_deg) > kSameAngleDeg) return false;
  if (a.theta_deg < kSameAngleDeg) return true;  // any phi at the pole
  const float d = std::abs(std::remainder(a.phi_deg - b.phi_deg, 360.0f));
  return d <= kSameAngleDeg;
}

bool sameList(const std::vector<BtfAngles>& a, const std::vector<BtfAngles>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (!sameDirection(a[i], b[i])) return false;
  return true;
}

}  // namespace

bool BtfDirectionSet::operator==(const BtfDirectionSet& other) const {
  if (this == &other) return true;
  if (!sameList(views_, other.views_) || shared_lights_ != other.shared_lights_ || lights_.size() != other.lights_.size())
    return false;
  for (std::size_t i = 0; i < lights_.size(); ++i)
    if (!sameList(lights_[i], other.lights_[i])) return false;
  return true;
}

BtfDirectionSetPtr BtfDirectionSet::known(BtfDirectionSetPtr set) {
  for (const BtfDirectionSetPtr& k : {ubo2003(), uboDome1()})
    if (*set == *k) return k;
  return set;
}

}  // namespace btf
