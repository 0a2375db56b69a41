// BilinearWarp2D::Fixed's queries for eight points at once in AVX2 lanes, each step the scalar
// code's (bilinear_warp2d.cpp) operation for operation, so that a lane returns the scalar query's
// bits (see core/internal/avx2_lanes.h). For stream calls built on the warps: an RGL file's evalMany.
//
// The points are clamped to [0, 1]^2 as the scalar queries clamp them; a NaN coordinate reads cell
// 0 at a NaN position, as the scalar cellOf does.
#pragma once

#include <cstdint>
#include <limits>

#include "avx2_lanes.h"
#include "btf/core/bilinear_warp2d.h"

namespace btf {

struct BilinearWarp2DLanes {
  using Fixed = BilinearWarp2D::Fixed;
  using SliceBlend = BilinearWarp2D::SliceBlend;

  // Whether the lanes can address the warp: a slice's indices must fit a gather's int32.
  static bool fits(const Fixed& f) {
    const BilinearWarp2D& w = *f.warp_;
    return static_cast<std::uint64_t>(w.width_) * static_cast<std::uint64_t>(w.height_) <
           static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max());
  }

  // invert(p).p.
  BTF_AVX2 static void invert(const Fixed& f, __m256 px, __m256 py, __m256& ux, __m256& uy) {
    using namespace avx2;
    const BilinearWarp2D& w = *f.warp_;
    const int width = w.width_, height = w.height_;
    const std::size_t slice_size = static_cast<std::size_t>(width) * height;
    const float dx = 1.0f / (width - 1), dy = 1.0f / (height - 1);
    const Cell c = cellOf(w, stdClamp(px, 0.0f, 1.0f), stdClamp(py, 0.0f, 1.0f));
    const __m256i row0 = _mm256_mullo_epi32(c.row, _mm256_set1_epi32(width));
    const __m256i row1 = _mm256_add_epi32(row0, _mm256_set1_epi32(width));
    const __m256i one = _mm256_set1_epi32(1), last = _mm256_set1_epi32(width - 1);
    const float* values = w.values_.data();
    const float* row_cdf = w.row_cdf_.data();
    const SliceBlend& b = f.blend_;

    const __m256i at0 = _mm256_add_epi32(row0, c.col), at1 = _mm256_add_epi32(row1, c.col);
    const __m256 c0 = lerp(blended(values, slice_size, at0, b), blended(values, slice_size, at1, b), c.ty);
    const __m256 c1 = lerp(blended(values, slice_size, _mm256_add_epi32(at0, one), b),
                           blended(values, slice_size, _mm256_add_epi32(at1, one), b), c.ty);
    const __m256 cdf_col = lerp(blended(row_cdf, slice_size, at0, b), blended(row_cdf, slice_size, at1, b), c.ty);
    const __m256 r0 = blended(row_cdf, slice_size, _mm256_add_epi32(row0, last), b);
    const __m256 r1 = blended(row_cdf, slice_size, _mm256_add_epi32(row1, last), b);
    const __m256 row_mass = lerp(r0, r1, c.ty);

    const __m256 half = _mm256_set1_ps(0.5f), ones = _mm256_set1_ps(1.0f);
    // cdf_col + dx * tx * (c0 + 0.5f * (c1 - c0) * tx)
    const __m256 mass_x = _mm256_add_ps(
        cdf_col, _mm256_mul_ps(_mm256_mul_ps(_mm256_set1_ps(dx), c.tx),
                               _mm256_add_ps(c0, _mm256_mul_ps(_mm256_mul_ps(half, _mm256_sub_ps(c1, c0)), c.tx))));
    // row_mass > 0 ? std::min(mass_x / row_mass, 1) : 0
    ux = _mm256_and_ps(stdMin(_mm256_div_ps(mass_x, row_mass), ones),
                       _mm256_cmp_ps(row_mass, _mm256_setzero_ps(), _CMP_GT_OQ));
    // marginal(row) + dy * ty * (r0 + 0.5f * (r1 - r0) * ty)
    uy = _mm256_add_ps(blended(w.marginal_cdf_.data(), static_cast<std::size_t>(height), c.row, b),
                       _mm256_mul_ps(_mm256_mul_ps(_mm256_set1_ps(dy), c.ty),
                                     _mm256_add_ps(r0, _mm256_mul_ps(_mm256_mul_ps(half, _mm256_sub_ps(r1, r0)), c.ty))));
    ux = stdMin(ux, ones);  // glm::min(u, vec2(1))
    uy = stdMin(uy, ones);
  }

  // eval(p).
  BTF_AVX2 static __m256 eval(const Fixed& f, __m256 px, __m256 py) { return evalSlices(f, px, py, 0); }

  // evalAtEveryLastValue(p, out), out holding `count` vectors (the last parameter's value count).
  BTF_AVX2 static void evalAtEveryLastValue(const Fixed& f, __m256 px, __m256 py, __m256* out, int count) {
    const BilinearWarp2D& w = *f.warp_;
    const std::uint32_t last_stride = w.param_strides_[w.param_values_.size() - 1];
    for (int k = 0; k < count; ++k) out[k] = evalSlices(f, px, py, static_cast<std::uint32_t>(k) * last_stride);
  }

 private:
  struct Cell {
    __m256i col, row;
    __m256 tx, ty;
  };

  // cellOf (bilinear_warp2d.cpp), for p in [0, 1]^2.
  BTF_AVX2 static Cell cellOf(const BilinearWarp2D& w, __m256 px, __m256 py) {
    const __m256 sx = _mm256_mul_ps(px, _mm256_set1_ps(static_cast<float>(w.width_ - 1)));
    const __m256 sy = _mm256_mul_ps(py, _mm256_set1_ps(static_cast<float>(w.height_ - 1)));
    const __m256i zero = _mm256_setzero_si256();
    const __m256i col = _mm256_max_epi32(_mm256_min_epi32(_mm256_cvttps_epi32(sx), _mm256_set1_epi32(w.width_ - 2)), zero);
    const __m256i row = _mm256_max_epi32(_mm256_min_epi32(_mm256_cvttps_epi32(sy), _mm256_set1_epi32(w.height_ - 2)), zero);
    return {col, row, _mm256_sub_ps(sx, _mm256_cvtepi32_ps(col)), _mm256_sub_ps(sy, _mm256_cvtepi32_ps(row))};
  }

  // lerp (bilinear_warp2d.cpp): (1 - t) a + t b.
  BTF_AVX2 static __m256 lerp(__m256 a, __m256 b, __m256 t) {
    return _mm256_add_ps(_mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(1.0f), t), a), _mm256_mul_ps(t, b));
  }

  // BilinearWarp2D::blended with every slice `offset` slices further on: the sum from 0 of
  // weight_k * values[(slice_k + offset) * stride + index].
  BTF_AVX2 static __m256 blended(const float* values, std::size_t stride, __m256i index, const SliceBlend& b,
                                 std::uint32_t offset = 0) {
    __m256 sum = _mm256_setzero_ps();
    for (int k = 0; k < b.count; ++k) {
      const float* slice = values + static_cast<std::size_t>(b.slice[k] + offset) * stride;
      sum = _mm256_add_ps(sum, _mm256_mul_ps(_mm256_set1_ps(b.weight[k]), _mm256_i32gather_ps(slice, index, 4)));
    }
    return sum;
  }

  // Fixed::eval (offset 0) and one value of Fixed::evalAtEveryLastValue.
  BTF_AVX2 static __m256 evalSlices(const Fixed& f, __m256 px, __m256 py, std::uint32_t offset) {
    using namespace avx2;
    const BilinearWarp2D& w = *f.warp_;
    const std::size_t slice_size = static_cast<std::size_t>(w.width_) * w.height_;
    const Cell c = cellOf(w, stdClamp(px, 0.0f, 1.0f), stdClamp(py, 0.0f, 1.0f));
    const __m256i i00 = _mm256_add_epi32(_mm256_mullo_epi32(c.row, _mm256_set1_epi32(w.width_)), c.col);
    const __m256i i01 = _mm256_add_epi32(i00, _mm256_set1_epi32(w.width_));
    const __m256i one = _mm256_set1_epi32(1);
    const float* values = w.values_.data();
    const SliceBlend& b = f.blend_;
    const __m256 v0 = lerp(blended(values, slice_size, i00, b, offset),
                           blended(values, slice_size, _mm256_add_epi32(i00, one), b, offset), c.tx);
    const __m256 v1 = lerp(blended(values, slice_size, i01, b, offset),
                           blended(values, slice_size, _mm256_add_epi32(i01, one), b, offset), c.tx);
    return lerp(v0, v1, c.ty);
  }
};

}  // namespace btf
