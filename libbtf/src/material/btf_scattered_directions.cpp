#include "btf_scattered_directions.h"


namespace btf {
namespace {

std::vector<glm::vec3> heldViewDirections(const BtfViewSet& views) {
  std::vector<glm::vec3> out;
  for (const int v : views.views()) out.push_back(views.directions().view(v));
  return out;
}

}  // namespace

BtfScatteredDirections::BtfScatteredDirections(const BtfViewSet& views)
    : views_(heldViewDirections(views)), held_(views.views()) {
  const BtfDirectionSet& set = views.directions();
  lights_.resize(std::size_t(set.viewCount()));
  std::shared_ptr<const HemisphereTriangulation> shared;
  for (const int v : held_) {
    if (set.sharedLights() && shared) {
      lights_[std::size_t(v)] = shared;
      continue;
    }
    lights_[std::size_t(v)] = std::make_shared<const HemisphereTriangulation>(set.lightDirections(v));
    if (set.sharedLights()) shared = lights_[std::size_t(v)];
  }
  shared_ = shared;
}

HemisphereTriangulation::Stencil BtfScatteredDirections::viewStencil(const glm::vec3& wo) const {
  HemisphereTriangulation::Stencil s = views_.stencil(wo);
  for (int k = 0; k < s.count; ++k) s.index[std::size_t(k)] = held_[std::size_t(s.index[std::size_t(k)])];
  return s;
}

int BtfScatteredDirections::samplingView(const HemisphereTriangulation::Stencil& view) {
  int best = 0;
  for (int k = 1; k < view.count; ++k)
    if (view.weight[std::size_t(k)] > view.weight[std::size_t(best)]) best = k;
  return view.index[std::size_t(best)];
}

int BtfScatteredDirections::stencil(const HemisphereTriangulation::Stencil& view, const glm::vec3& wi, int light_triangle,
                                    int* views, int* lights, float* weights) const {
  // Lights shared by all views: one location of wi serves the three views.
  HemisphereTriangulation::Stencil light;
  if (shared_) light = light_triangle >= 0 ? shared_->stencilIn(light_triangle, wi) : shared_->stencil(wi);
  int count = 0;
  for (int k = 0; k < view.count; ++k) {
    const int v = view.index[std::size_t(k)];
    if (!shared_) light = lights_[std::size_t(v)]->stencil(wi);
    for (int j = 0; j < light.count; ++j) {
      views[count] = v;
      lights[count] = light.index[std::size_t(j)];
      weights[count++] = view.weight[std::size_t(k)] * light.weight[std::size_t(j)];
    }
  }
  return count;
}

}  // namespace btf
