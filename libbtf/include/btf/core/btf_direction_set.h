// The directions a BTF was measured on: a list of view directions and, per view, a list of light
// directions. A measured BTF holds, for every texel, one RGB value per (view, light) pair of its set.
//
// Sets met in practice:
//   - UBO2003 and the UTIA database: 81 directions on rings of 15 degrees (btf_directions.h), the
//     same for views and lights;
//   - Bonn dome 1 (UBO2014, ATRIUM): 151 directions on ten rings, the same for views and lights
//     (uboDome1(); the angles btflib's create_ubo_dome1_sampling describes);
//   - whatever a file declares: a Bonn .btf file stores its views and, per view, its lights, and
//     the lights may differ between views (a light moved aside where it would stand in front of
//     the camera).
// A set is immutable and shared (std::shared_ptr<const BtfDirectionSet>): every view set, source
// and compressed form of one BTF points at the same object.
//
// Index order is the order the set was given in (a file's order). Directions are unit vectors in
// the sample's local frame (z the normal) and keep the angles they were given by, so that names
// and reports show the file's own numbers.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace btf {

// A direction by its angles (degrees): theta from the normal, phi from +x.
struct BtfAngles {
  float theta_deg = 0, phi_deg = 0;
  bool operator==(const BtfAngles&) const = default;
};

class BtfDirectionSet {
 public:
  // `views` and one light list per view (`lights[v]`), or one list shared by all views. Throws
  // btf::Error for an empty list, a non-finite angle, theta outside [0, 90), or more than
  // kMaxDirections views or lights per view. `nominal`, when given, is the set whose indices these
  // directions stand for (a UTIA folder's files keep the nominal angles of a light that was moved
  // aside): it must have as many views and lights per view.
  BtfDirectionSet(std::string name, std::vector<BtfAngles> views, std::vector<std::vector<BtfAngles>> lights,
                  std::shared_ptr<const BtfDirectionSet> nominal = nullptr);
  BtfDirectionSet(std::string name, std::vector<BtfAngles> views, std::vector<BtfAngles> shared_lights);

  // The 81-direction UBO2003 set (btf_directions.h) for views and lights.
  static const std::shared_ptr<const BtfDirectionSet>& ubo2003();
  // Bonn dome 1: rings at theta 0, 11, 23.5, 30, 37.5, 45, 52.5, 60, 67.5, 75 degrees holding
  // 1, 6, 12, 12, 12, 18, 18, 24, 24, 24 directions, phi = offset + j * 360 / count with offsets
  // 0, 15, 0, 15, 0, 0, 7.5, 0, 7.5, 0 degrees (wrapped into [-180, 180)); 151 for views and lights.
  static const std::shared_ptr<const BtfDirectionSet>& uboDome1();

  // Far more than any gonioreflectometer or dome records; bounds what a corrupt file can ask for.
  static constexpr int kMaxDirections = 100000;

  const std::string& name() const { return name_; }
  int viewCount() const { return int(views_.size()); }
  int lightCount(int view) const { return int(lights(view).size()); }
  int maxLightCount() const { return max_lights_; }
  // True when every view has the same light list (a tensor-product sampling).
  bool sharedLights() const { return shared_lights_; }
  // True for the UBO2003 81-direction set, which the VQ codec's ring structure is built on.
  bool isUbo2003() const { return ubo2003_; }
  // True when the indices are those of the UBO2003 set: the set itself, or one whose lights were
  // moved aside from it (nominal()). What codecs that index by ring need; evaluation uses the
  // exact directions.
  bool indexedAsUbo2003() const { return ubo2003_ || (nominal_ && nominal_->isUbo2003()); }
  const BtfDirectionSet* nominal() const { return nominal_.get(); }

  const BtfAngles& viewAngles(int view) const { return views_[std::size_t(view)]; }
  const glm::vec3& view(int view) const { return view_dirs_[std::size_t(view)]; }
  std::span<const BtfAngles> lights(int view) const;
  std::span<const glm::vec3> lightDirections(int view) const;
  // Total (view, light) pairs.
  std::size_t pairCount() const { return pair_count_; }

  // "81 views x 81 lights (UBO2003)", "151 views x 151 lights (Bonn dome 1)",
  // "40 views x 60 lights per view, view-dependent (scattered)".
  std::string describe() const;
  // The lights alone: "151 lights", "60 lights per view, view-dependent".
  std::string describeLights() const;
  // "theta 30, phi 60" of a view, for messages.
  std::string describeView(int view) const;

  // The same directions, view by view and light by light, each within a thousandth of a degree
  // (files store degrees or radians as float; the same direction read from two of them differs in
  // the last bits).
  bool operator==(const BtfDirectionSet& other) const;

  // The shared UBO2003 or dome set when `set` holds the same directions (so that reports name it
  // and consumers share one object), else `set` itself.
  static std::shared_ptr<const BtfDirectionSet> known(std::shared_ptr<const BtfDirectionSet> set);

 private:
  void finish();

  std::string name_;
  std::shared_ptr<const BtfDirectionSet> nominal_;
  std::vector<BtfAngles> views_;
  std::vector<std::vector<BtfAngles>> lights_;  // one list when shared
  std::vector<glm::vec3> view_dirs_;
  std::vector<std::vector<glm::vec3>> light_dirs_;
  bool shared_lights_ = true, ubo2003_ = false;
  int max_lights_ = 0;
  std::size_t pair_count_ = 0;
};

using BtfDirectionSetPtr = std::shared_ptr<const BtfDirectionSet>;

// The unit vector of a direction given by its angles.
glm::vec3 btfDirectionVector(const BtfAngles& angles);

}  // namespace btf
