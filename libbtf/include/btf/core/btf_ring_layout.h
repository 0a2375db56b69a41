// The lights of a BTF grouped into rings: the 1D functions the VQ codec's level 1 codes
// (compress/vq_btf.h) are a texel's values over one ring, at fixed view.
//
// A ring is a run of lights of (nearly) one elevation in azimuth order: on the UBO2003 set its six
// rings of 15 degrees (btf_directions.h), on the Bonn dome its ten rings. A set whose lights are
// scattered (rings of fewer than 4 lights on average: elevations nearly all distinct) is cut into
// bands instead: its lights in elevation order, at most kBandSize to a band. Level 1 needs no more than a fixed grouping of a view's
// lights; a ring's azimuth order only makes its functions smooth, so that they repeat across texels.
//
// The layout is one grouping of light indices for every view: light l of any view sits at the same
// place in its ring. Sets whose light lists differ between views (lights moved aside) are grouped
// by their nominal set's lights when they have one, else by view 0's; every view must have the same
// number of lights.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "btf/core/btf_direction_set.h"

namespace btf {

class BtfRingLayout {
 public:
  // Largest ring: a longer run of lights of one elevation is split, and scattered lights are cut
  // into bands of this many (the UBO2003 set's largest ring).
  static constexpr int kBandSize = 24;

  // The layout of a set (see above). Throws btf::Error, `what` first, when the views do not all
  // have the same number of lights.
  static BtfRingLayout of(const BtfDirectionSet& set, const std::string& what);
  // The UBO2003 layout: rings 0..5 of sizes 1, 6, 12, 18, 20, 24, lights in index order.
  static const BtfRingLayout& ubo2003();

  // A layout as stored (VQ files keep theirs): ring sizes and, ring after ring, the light at each
  // place. Throws btf::Error when a size is outside 1..kBandSize or `order` is not a permutation of 0..n-1 with
  // n the sizes' sum.
  BtfRingLayout(std::vector<int> sizes, std::vector<int> order);

  int ringCount() const { return int(sizes_.size()); }
  int lightCount() const { return int(order_.size()); }
  int size(int ring) const { return sizes_[std::size_t(ring)]; }
  int start(int ring) const { return starts_[std::size_t(ring)]; }
  int maxSize() const { return max_size_; }
  // The light at place `azimuth` of a ring, and the ring and place of a light.
  int light(int ring, int azimuth) const { return order_[std::size_t(start(ring) + azimuth)]; }
  int ringOf(int light) const { return ring_of_[std::size_t(light)]; }
  int placeOf(int light) const { return place_of_[std::size_t(light)]; }
  const std::vector<int>& sizes() const { return sizes_; }
  const std::vector<int>& order() const { return order_; }
  // True when the lights are stored ring after ring in index order (UBO2003 and the dome).
  bool inIndexOrder() const { return in_order_; }

  // "6 rings of 1, 6, 12, 18, 20, 24 lights".
  std::string describe() const;
  bool operator==(const BtfRingLayout& other) const { return sizes_ == other.sizes_ && order_ == other.order_; }

 private:
  std::vector<int> sizes_, starts_, order_, ring_of_, place_of_;
  int max_size_ = 0;
  bool in_order_ = true;
};

}  // namespace btf
