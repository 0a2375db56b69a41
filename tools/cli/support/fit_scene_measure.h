// What `btf fit-scene` measures of a candidate material: its speed, and its rendered error against
// the reference, with common random numbers (see fit_scene.cpp).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "btf/io/image.h"
#include "btf/material/material.h"
#include "btf/render/integrator.h"
#include "btf/render/scene.h"

namespace btf::cli {

struct FitSpeed {
  double eval_per_s = 0, samples_per_s = 0;
};

// Evaluations and draws of the material's own sampler per second on one thread, over 20,000 fixed
// direction pairs (a report, not a benchmark: btf_bench has those).
FitSpeed measureSpeed(const Material& m);

// The path tracer with fixed settings, rendering a scene description at a spp and seed: the
// whole result, or its image.
struct SceneRenderer {
  render::RenderSettings settings;
  std::unique_ptr<render::Integrator> integrator = render::makePathTracer();
  render::RenderResult result(render::SceneDescription d, int spp, std::uint64_t seed) const;
  Image operator()(render::SceneDescription d, int spp, std::uint64_t seed) const { return result(std::move(d), spp, seed).color; }
};

// Every material sampled by the cosine warp, whose directions do not depend on f (common random
// numbers between renders that differ in one material).
render::SceneDescription withCosineSampling(render::SceneDescription d);

// The material each pixel's centre sees first (-1: nothing, or a shape without a material).
std::vector<int> firstHitMaterials(const render::SceneDescription& d);

// A render's error against the reference: relmse over the whole image, and over the pixels where
// the material is seen first (the whole image's when it is seen nowhere). The budget applies to
// the first by default: a material seen small contributes little to the image, which is what lets
// it be modelled more cheaply. --measure seen applies it to the larger of the two, for a user who
// wants every object right on its own pixels (a material filling a tenth of the frame can lose its
// texture within an image-wide budget).
struct RenderedError {
  double image = 0, seen = 0;
  double judged(bool seen_too) const { return seen_too ? std::max(image, seen) : image; }
};
RenderedError renderedError(const Image& test, const Image& reference, const std::vector<int>& first_hit, int material);

}  // namespace btf::cli
