// The directions of a BTF whose set has no rings of 15 degrees (the Bonn dome, scattered or
// view-dependent lists), as BtfMaterial interpolates and samples them (private to material/).
//
// Why triangulations: on such sets the ring-wise linear interpolation of the 81-direction set has
// no rings to follow. Barycentric weights on a spherical Delaunay triangulation
// (core/hemisphere_triangulation.h) work on any directions, weigh the three measured directions
// around a query, and are exact at measured directions: the views held are triangulated once, and
// the lights of each view (once for all views when they share one list).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "btf/core/btf_view_set.h"
#include "btf/core/hemisphere_triangulation.h"

namespace btf {

class BtfScatteredDirections {
 public:
  // Throws btf::Error when a triangulation fails.
  explicit BtfScatteredDirections(const BtfViewSet& views);

  // The (view, light, weight) triples whose weighted sum interpolates the pair (wi, wo): at most
  // 9, weights summing to 1. Returns their count.
  static constexpr int kMaxStencil = 9;
  int stencil(const glm::vec3& wi, const glm::vec3& wo, int* views, int* lights, float* weights) const;
  // The held view nearest to wo (sampling draws from its light slice).
  int nearestView(const glm::vec3& wo) const;
  const HemisphereTriangulation& lights(int view) const { return *lights_[std::size_t(view)]; }

 private:
  HemisphereTriangulation views_;  // of the held views, in slot order
  std::vector<int> held_;          // view index of each slot
  std::vector<std::shared_ptr<const HemisphereTriangulation>> lights_;  // per view index (null: not held)
  std::uint64_t id_;  // for nearestView's per-thread memo
};

}  // namespace btf
