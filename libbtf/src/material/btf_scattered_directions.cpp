#include "btf_scattered_directions.h"

#include <atomic>

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
  static std::atomic<std::uint64_t> next_id{1};
  id_ = next_id++;
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
}

int BtfScatteredDirections::nearestView(const glm::vec3& wo) const {
  // A sample and the pdf() calls after it ask for the same wo (MIS, the chi-square quadrature): the
  // last answer on this thread is kept (a pure function of wo, so the memo changes no result).
  thread_local std::uint64_t memo_id = 0;
  thread_local glm::vec3 memo_wo(0.0f);
  thread_local int memo_view = 0;
  if (memo_id != id_ || memo_wo != wo) {
    memo_id = id_;
    memo_wo = wo;
    memo_view = held_[std::size_t(views_.nearest(wo))];
  }
  return memo_view;
}

int BtfScatteredDirections::stencil(const glm::vec3& wi, const glm::vec3& wo, int* views, int* lights,
                                    float* weights) const {
  const HemisphereTriangulation::Stencil view = views_.stencil(wo);
  int count = 0;
  for (int k = 0; k < view.count; ++k) {
    const int v = held_[std::size_t(view.index[std::size_t(k)])];
    const HemisphereTriangulation::Stencil light = lights_[std::size_t(v)]->stencil(wi);
    for (int j = 0; j < light.count; ++j) {
      views[count] = v;
      lights[count] = light.index[std::size_t(j)];
      weights[count++] = view.weight[std::size_t(k)] * light.weight[std::size_t(j)];
    }
  }
  return count;
}

}  // namespace btf
