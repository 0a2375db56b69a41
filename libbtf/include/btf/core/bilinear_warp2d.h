// A piecewise-bilinear function on the unit square, tabulated on a W x H grid of nodes that
// includes the square's edges, optionally depending on up to three parameters between whose
// tabulated values it is interpolated linearly. This is the building block of the adaptive
// parameterization of Dupuy & Jakob 2018 ("An Adaptive Parameterization for Efficient Material
// Acquisition and Rendering"): an RGL measured material stores its VNDF warp, luminance warp and
// RGB table as such grids, one per incident direction.
//
// Two modes:
// - Interpolant: eval() returns the plain bilinear (and multilinear-in-parameters) interpolation
//   of the stored values; sample()/invert() are not available.
// - Distribution: every parameter slice is normalized to integrate to 1 over [0,1]^2, and
//   sample() maps uniform numbers to points distributed with exactly that density by inversion:
//   the marginal over rows (y) first, then the conditional over columns (x). Within a cell the
//   marginal density is linear in y and the conditional density linear in x, so each step solves a
//   quadratic. Blending the slices of neighbouring parameter values blends their densities and
//   their CDFs with the same weights, and since CDFs are linear in the density, the blended CDFs
//   are exactly the CDFs of the blended density: the returned pdf is exact at any parameter value.
//   invert() is the inverse map of sample() (point -> uniform numbers), eval() the density.
//
// Data layout: parameter slices outermost (the last parameter fastest), then rows (y), then
// columns (x). Nothing is allocated after construction; all queries are thread-safe.
#pragma once

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace btf {

class BilinearWarp2D {
 public:
  static constexpr int kMaxParams = 3;
  enum class Mode { Interpolant, Distribution };

  struct Point {
    glm::vec2 p;  // in [0,1]^2
    float pdf;    // density with respect to area on [0,1]^2
  };

  BilinearWarp2D() = default;
  // width, height >= 2 nodes; data holds product(param sizes) * width * height values; each
  // param_values[d] lists the parameter's node values in strictly increasing order (size >= 1).
  // Throws btf::Error for inconsistent sizes, non-finite values and, in Distribution mode, for
  // negative values or a slice with no mass (the message names the slice).
  BilinearWarp2D(int width, int height, std::span<const float> data,
                 std::vector<std::vector<float>> param_values, Mode mode);

  // params: one value per parameter (extra entries ignored); values outside a parameter's range
  // clamp to its end. sample/invert require Distribution mode (throw btf::Error otherwise).
  Point sample(glm::vec2 u, std::span<const float> params = {}) const;
  Point invert(glm::vec2 p, std::span<const float> params = {}) const;
  float eval(glm::vec2 p, std::span<const float> params = {}) const;
  // eval(p, {leading..., v_k}) for every tabulated value v_k of the last parameter, into out (one
  // entry per value): the same floats, with the cell and the leading parameters' blend found once
  // (an RGL file's RGB table: its channels).
  void evalAtEveryLastValue(glm::vec2 p, std::span<const float> leading, std::span<float> out) const;

  int width() const { return width_; }
  int height() const { return height_; }
  Mode mode() const { return mode_; }

 private:
  // The (at most 2^kMaxParams) slices that a parameter value blends, with their weights.
  struct SliceBlend {
    int count = 0;
    std::array<std::uint32_t, 1 << kMaxParams> slice{};
    std::array<float, 1 << kMaxParams> weight{};
  };

 public:
  // The function at fixed parameter values, for many queries at them (an RGL file's warps for one
  // outgoing direction): the search for the parameter slices and their weights is done once. Its
  // queries are the warp's own queries at those parameters, the same floats bit for bit. It refers
  // to the warp, which must outlive it.
  class Fixed {
   public:
    Point sample(glm::vec2 u) const;
    Point invert(glm::vec2 p) const;
    float eval(glm::vec2 p) const;
    // Only on what fixedLeading() returns: evalAtEveryLastValue(p, leading, out) of the warp.
    void evalAtEveryLastValue(glm::vec2 p, std::span<float> out) const;

   private:
    friend class BilinearWarp2D;
    friend struct BilinearWarp2DLanes;  // the same queries in AVX2 lanes (src/sampling/)
    Fixed(const BilinearWarp2D& warp, const SliceBlend& blend) : warp_(&warp), blend_(blend) {}
    const BilinearWarp2D* warp_;
    SliceBlend blend_;
  };
  // params as for sample(); sample/invert of the result require Distribution mode (btf::Error).
  Fixed fixed(std::span<const float> params = {}) const;
  // The leading parameters of evalAtEveryLastValue, fixed (btf::Error for a wrong count).
  Fixed fixedLeading(std::span<const float> leading) const;

 private:
  SliceBlend blendFor(std::span<const float> params) const;
  // sum_k weight_k * values[slice_k * stride + index]
  static float blended(const std::vector<float>& values, std::size_t stride, std::size_t index,
                       const SliceBlend& blend);
  void buildDistribution(std::size_t slice);
  friend struct BilinearWarp2DLanes;

  int width_ = 0, height_ = 0;
  Mode mode_ = Mode::Interpolant;
  std::vector<std::vector<float>> param_values_;
  std::array<std::uint32_t, kMaxParams> param_strides_{};  // in slices
  std::vector<float> values_;       // interpolant values, or normalized density
  std::vector<float> row_cdf_;      // Distribution: integral along each row from x = 0 to each node
  std::vector<float> marginal_cdf_; // Distribution: integral over [0,1] x [0, y_row] per row node
};

}  // namespace btf
