// The directions of a BTF whose set has no rings of 15 degrees (the Bonn dome, scattered or
// view-dependent lists), as BtfMaterial interpolates and samples them (private to material/).
//
// Why triangulations: on such sets the ring-wise linear interpolation of the 81-direction set has
// no rings to follow. Barycentric weights on a spherical Delaunay triangulation
// (core/hemisphere_triangulation.h) work on any directions, weigh the three measured directions
// around a query, and are exact at measured directions: the views held are triangulated once, and
// the lights of each view (once for all views when they share one list).
#pragma once

#include <memory>
#include <vector>

#include "btf/core/btf_view_set.h"
#include "btf/core/hemisphere_triangulation.h"

namespace btf {

class BtfScatteredDirections {
 public:
  // Throws btf::Error when a triangulation fails.
  explicit BtfScatteredDirections(const BtfViewSet& views);

  // The held views around wo and their interpolation weights (as view indices).
  HemisphereTriangulation::Stencil viewStencil(const glm::vec3& wo) const;
  // The view sampling draws from: the view stencil's of largest weight (the first among equals),
  // the held view nearest wo but for points near the middle of a triangle of views.
  static int samplingView(const HemisphereTriangulation::Stencil& view);
  // The (view, light, weight) triples whose weighted sum interpolates the pair (wi, wo), from wo's
  // view stencil: at most 9, weights summing to 1. Returns their count. light_triangle >= 0 is
  // wi's triangle in the shared light triangulation when the caller knows it (it must then be
  // sharedLights()->locate(wi)), -1 to locate it.
  static constexpr int kMaxStencil = 9;
  int stencil(const HemisphereTriangulation::Stencil& view, const glm::vec3& wi, int light_triangle, int* views,
              int* lights, float* weights) const;
  const HemisphereTriangulation& lights(int view) const { return *lights_[std::size_t(view)]; }
  // The light triangulation of every view when the set's views share one light list, else null.
  const HemisphereTriangulation* sharedLights() const { return shared_.get(); }

 private:
  HemisphereTriangulation views_;  // of the held views, in slot order
  std::vector<int> held_;          // view index of each slot
  std::vector<std::shared_ptr<const HemisphereTriangulation>> lights_;  // per view index (null: not held)
  std::shared_ptr<const HemisphereTriangulation> shared_;  // the one of all views when they share their lights, else null
};

}  // namespace btf
