// Helpers for AVX2 lanes that repeat scalar code operation for operation (the DP sampler's stream
// calls, dp_cdf_batch.cpp; an RGL file's evalMany, rgl_eval_lanes.cpp): each mirrors one scalar
// operation of the library, including what it returns for NaN and for -0 against +0, so that a
// lane gives the scalar path's bits.
//
// No multiply and add may fuse into one rounding, or the lanes would no longer round as the scalar
// code does: the intrinsics name each operation, the functions enable "avx2" alone (not "fma"),
// and the library is built with -ffp-contract=off, which also holds where -march enables FMA.
// Callers check cpuHasAvx2() before entering a BTF_AVX2 function.
#pragma once

#include <immintrin.h>

// Compiles one function for AVX2 and not FMA, so that no multiply-add is fused and the lanes
// round as the scalar code does.
#define BTF_AVX2 __attribute__((target("avx2")))

namespace btf::avx2 {

inline bool cpuHasAvx2() {
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
}

BTF_AVX2 inline __m256 select(__m256 if_false, __m256 if_true, __m256 mask) {
  return _mm256_blendv_ps(if_false, if_true, mask);
}

// std::min(a, b) and std::max(a, b) of floats. libstdc++ computes them as b < a ? b : a and
// a < b ? b : a; MINPS / MAXPS return their second operand when the compare fails (a NaN, or
// equal values such as -0 and +0), so the operands go in swapped: minps(b, a) = b < a ? b : a.
BTF_AVX2 inline __m256 stdMin(__m256 a, __m256 b) { return _mm256_min_ps(b, a); }
BTF_AVX2 inline __m256 stdMax(__m256 a, __m256 b) { return _mm256_max_ps(b, a); }
// std::clamp(v, lo, hi), which libstdc++ computes as std::min(std::max(v, lo), hi) (a NaN stays NaN).
BTF_AVX2 inline __m256 stdClamp(__m256 v, float lo, float hi) {
  return stdMin(stdMax(v, _mm256_set1_ps(lo)), _mm256_set1_ps(hi));
}
// std::abs(float) clears the sign bit; unary minus flips it.
BTF_AVX2 inline __m256 stdAbs(__m256 v) { return _mm256_andnot_ps(_mm256_set1_ps(-0.0f), v); }
BTF_AVX2 inline __m256 flipSign(__m256 v) { return _mm256_xor_ps(v, _mm256_set1_ps(-0.0f)); }
// x op v as a scalar comparison: an ordered predicate (false for NaN) for <, <=, >, >=, ==.
template <int kOp>
BTF_AVX2 inline __m256 compare(__m256 x, float v) {
  return _mm256_cmp_ps(x, _mm256_set1_ps(v), kOp);
}

BTF_AVX2 inline __m256 mul(__m256 x, __m256 y) { return _mm256_mul_ps(x, y); }
BTF_AVX2 inline __m256 add(__m256 x, float y) { return _mm256_add_ps(_mm256_set1_ps(y), x); }
// c0 - c1 z.
BTF_AVX2 inline __m256 linear(float c0, float c1, __m256 z) {
  return _mm256_sub_ps(_mm256_set1_ps(c0), _mm256_mul_ps(_mm256_set1_ps(c1), z));
}

// fastAtan2Turns (core/fast_atan.h).
BTF_AVX2 inline __m256 atan2Turns(__m256 y, __m256 x) {
  const __m256 ax = stdAbs(x), ay = stdAbs(y);
  const __m256 x_wider = _mm256_cmp_ps(ax, ay, _CMP_GT_OQ);
  const __m256 hi = select(ay, ax, x_wider), lo = select(ax, ay, x_wider);
  const __m256 a = _mm256_div_ps(lo, hi), z = _mm256_mul_ps(a, a), z2 = _mm256_mul_ps(z, z), z4 = _mm256_mul_ps(z2, z2);
  const __m256 p01 = linear(0.159154937f, 0.0530511774f, z), p23 = linear(0.0318180509f, 0.0225964971f, z);
  const __m256 p45 = linear(0.0168996621f, 0.0118679535f, z), p67 = linear(0.00670641102f, 0.00250370614f, z);
  const __m256 p = _mm256_add_ps(
      _mm256_add_ps(p01, _mm256_mul_ps(p23, z2)),
      _mm256_mul_ps(z4, _mm256_add_ps(_mm256_add_ps(p45, _mm256_mul_ps(p67, z2)), _mm256_mul_ps(_mm256_set1_ps(0.0004402677f), z4))));
  __m256 r = _mm256_mul_ps(a, p);
  r = select(r, _mm256_sub_ps(_mm256_set1_ps(0.25f), r), _mm256_cmp_ps(ay, ax, _CMP_GT_OQ));
  r = select(r, _mm256_sub_ps(_mm256_set1_ps(0.5f), r), _mm256_cmp_ps(x, _mm256_setzero_ps(), _CMP_LT_OQ));
  r = _mm256_xor_ps(r, _mm256_and_ps(_mm256_cmp_ps(y, _mm256_setzero_ps(), _CMP_LT_OQ), _mm256_set1_ps(-0.0f)));
  return _mm256_and_ps(r, _mm256_cmp_ps(hi, _mm256_setzero_ps(), _CMP_GT_OQ));  // !(hi > 0) (NaN y too): 0
}

// A glm::vec3 per lane, and glm's operations on it in glm's order.
struct Vec3 {
  __m256 x, y, z;
};
BTF_AVX2 inline Vec3 loadVec3(const float* x, const float* y, const float* z) {
  return {_mm256_load_ps(x), _mm256_load_ps(y), _mm256_load_ps(z)};
}
// glm::dot for vec3: the products, then (x + y) + z.
BTF_AVX2 inline __m256 dot(const Vec3& a, const Vec3& b) {
  return _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(a.x, b.x), _mm256_mul_ps(a.y, b.y)), _mm256_mul_ps(a.z, b.z));
}
// glm::normalize: v * inversesqrt(dot(v, v)), and glm's inversesqrt(x) is 1 / sqrt(x) (a division,
// not an approximate reciprocal square root).
BTF_AVX2 inline Vec3 normalize(const Vec3& v) {
  const __m256 inv = _mm256_div_ps(_mm256_set1_ps(1.0f), _mm256_sqrt_ps(dot(v, v)));
  return {_mm256_mul_ps(v.x, inv), _mm256_mul_ps(v.y, inv), _mm256_mul_ps(v.z, inv)};
}

}  // namespace btf::avx2
