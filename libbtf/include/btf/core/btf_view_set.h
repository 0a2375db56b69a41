// Which of the 81 view directions (btf_directions.h) a BTF holds. Measured datasets are often
// partial: one view of a sample (a slice), or the views up to some elevation. A view that is held
// has all 81 lights: image-based gantries record every light for each camera position, and the
// codecs (compress/) group a texel's data by view.
//
// Consumers loop over `views()` and store per-view data by slot (the view's position in that
// list), so a one-view BTF costs one view's memory and time, not 81.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "btf/core/btf_direction_set.h"
#include "btf/core/btf_directions.h"

namespace btf {

class BtfViewSet {
 public:
  // All 81 views of the UBO2003 set.
  BtfViewSet();
  // Every view of `directions`.
  static BtfViewSet all(BtfDirectionSetPtr directions);
  // The given view indices of `directions` (UBO2003 by default), in any order (kept ascending).
  // Throws btf::Error for an empty list, an index outside the set or a repeated one.
  explicit BtfViewSet(std::vector<int> views, BtfDirectionSetPtr directions = BtfDirectionSet::ubo2003());
  // Every view whose elevation is at most max_theta_deg (at least the lowest one).
  static BtfViewSet upToTheta(float max_theta_deg, BtfDirectionSetPtr directions = BtfDirectionSet::ubo2003());

  int count() const { return int(views_.size()); }
  bool complete() const { return count() == directions_->viewCount(); }
  bool contains(int view) const { return view >= 0 && view < int(slots_.size()) && slots_[std::size_t(view)] >= 0; }
  // The direction set the indices refer to.
  const BtfDirectionSet& directions() const { return *directions_; }
  const BtfDirectionSetPtr& directionSet() const { return directions_; }
  // The view at position `slot` (0 .. count() - 1), and the slot of a held view (-1 if not held).
  int view(int slot) const { return views_[std::size_t(slot)]; }
  int slot(int view) const { return slots_[std::size_t(view)]; }
  const std::vector<int>& views() const { return views_; }
  // Number of complete rings from the pole: rings 0 .. k - 1 are held whole (views up to some
  // elevation), 0 when the pole is missing. UBO2003 sets only (0 for others).
  int completeRingsFromPole() const;

  // For people: "all 81 views" ("all 151 views (Bonn dome 1)" on other sets), "1 view (theta 0, phi 0)", "37 views (all up to theta 45)",
  // "5 views: (theta 0, phi 0), (theta 15, phi 0), ..." (at most a few listed).
  std::string describe() const;
  // Throws btf::Error("<what>: view (theta .., phi ..) is not in this BTF (it holds ...)") unless
  // the view is held.
  void require(int view, const std::string& what) const;

  // Throws btf::Error("<what> needs the 81-direction UBO2003 set; this BTF is on <set>") unless the
  // views are on that set: for the parts of libbtf built on its rings of 15 degrees.
  void requireUbo2003(const std::string& what) const;

  bool operator==(const BtfViewSet& other) const {
    return views_ == other.views_ && (directions_ == other.directions_ || *directions_ == *other.directions_);
  }

 private:
  void holdAll();

  BtfDirectionSetPtr directions_;
  std::vector<int> views_;
  std::vector<std::int32_t> slots_;
};

// "theta 30, phi 60" of a UBO2003 direction, for messages.
std::string describeBtfDirection(int index);

}  // namespace btf
