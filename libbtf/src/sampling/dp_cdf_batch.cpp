// The vector path of DpCdfSampler::sampleDirections and pdfs (dp_cdf_sampler.h): 32 queries per
// step in AVX2 lanes (four vectors of eight), with the searches done by gathers.
//
// Written with intrinsics by hand: GCC's vectorizer emits no gathers for generic tuning, and the
// arithmetic has to be the scalar path's, operation for operation, so that a query gives the same
// bits on every CPU (and sample's pdf stays pdf()'s). The functions are compiled for "avx2" alone,
// not "fma": with FMA enabled the compiler would fuse a multiply and an add into one rounding.
// Each step below names the scalar code it mirrors (binned_sampler.h, dp_cdf_sampler.cpp).
// The searches bisect all the way down to one entry (the scalar path stops at 32 and compares a
// block): both count the entries <= the key, so they find the same segment.
#include <immintrin.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "btf/core/error.h"
#include "btf/sampling/dp_cdf_sampler.h"

// Compiles one function for AVX2 and not FMA, so that no multiply-add is fused and the lanes
// round as the scalar code does.
#define BTF_AVX2 __attribute__((target("avx2")))

namespace btf {
namespace {

bool cpuHasAvx2() {
  static const bool has = __builtin_cpu_supports("avx2");
  return has;
}

// Queries per step: four vectors of eight, interleaved step by step, so that one vector's gathers
// run while another waits for its own (the searches are chains of dependent gathers; eight
// vectors measured no faster than four).
constexpr int kVectors = 4;
constexpr int kLanes = 8 * kVectors;
static_assert(kLanes <= 64, "lane masks are 64-bit");

struct Tables {
  const std::uint16_t* keys;
  const std::uint16_t* nodes16;  // one of the two is null
  const std::uint8_t* nodes8;
  const std::uint32_t* starts;
  const float* theta_edges;
  const std::uint16_t* theta_guide;
  int theta_last_cell, theta_edge_count;
  int nu, nv, steps;
  float pdf_scale;
};

// One block of queries, structure of arrays.
struct Lanes {
  alignas(32) float ox[kLanes], oy[kLanes], oz[kLanes];  // wo
  alignas(32) float a0[kLanes], a1[kLanes], a2[kLanes];  // u (a2 unused) or wi
  alignas(32) float wx[kLanes], wy[kLanes], wz[kLanes], pdf[kLanes];  // results
  alignas(32) int bin[kLanes];
};

BTF_AVX2 inline __m256i gather16(const std::uint16_t* base, __m256i index) {
  // 32-bit loads at 16-bit steps, low half kept (the tables are padded past their end).
  return _mm256_and_si256(_mm256_i32gather_epi32(reinterpret_cast<const int*>(base), index, 2),
                          _mm256_set1_epi32(0xffff));
}

BTF_AVX2 inline __m256i gather8(const std::uint8_t* base, __m256i index) {
  return _mm256_and_si256(_mm256_i32gather_epi32(reinterpret_cast<const int*>(base), index, 1),
                          _mm256_set1_epi32(0xff));
}

// The gathers of CDF values and of node indices (8 or 16 bits; the choice is the same for every call).
struct KeyGather {
  const std::uint16_t* keys;
  BTF_AVX2 __m256i operator()(__m256i index) const { return gather16(keys, index); }
};
struct NodeGather {
  const std::uint16_t* nodes16;
  const std::uint8_t* nodes8;
  BTF_AVX2 __m256i operator()(__m256i index) const {
    return nodes8 ? gather8(nodes8, index) : gather16(nodes16, index);
  }
};

BTF_AVX2 inline __m256 select(__m256 if_false, __m256 if_true, __m256 mask) {
  return _mm256_blendv_ps(if_false, if_true, mask);
}

// binOf (isotropic): the guide's lower bound, two steps, then single steps while any lane needs one.
BTF_AVX2 inline void thetaBins(const Tables& t, const __m256 (&z)[kVectors], __m256i (&bin)[kVectors]) {
  const __m256 last = _mm256_set1_ps(float(t.theta_last_cell));
  const __m256i edge_count = _mm256_set1_epi32(t.theta_edge_count);
  for (int j = 0; j < kVectors; ++j) {
    const __m256 scaled = _mm256_mul_ps(z[j], last);
    __m256i g = _mm256_cvttps_epi32(scaled);
    g = _mm256_castps_si256(select(_mm256_castsi256_ps(g), _mm256_castsi256_ps(_mm256_set1_epi32(t.theta_last_cell)),
                                   _mm256_cmp_ps(scaled, last, _CMP_NLT_UQ)));
    g = _mm256_and_si256(g, _mm256_castps_si256(_mm256_cmp_ps(scaled, _mm256_setzero_ps(), _CMP_GT_OQ)));
    bin[j] = gather16(t.theta_guide, g);
  }
  for (int step = 0;; ++step) {
    __m256i any = _mm256_setzero_si256();
    for (int j = 0; j < kVectors; ++j) {
      const __m256 e = _mm256_i32gather_ps(t.theta_edges, bin[j], 4);
      __m256i more = _mm256_castps_si256(_mm256_cmp_ps(e, z[j], _CMP_GE_OQ));
      if (step >= 2) more = _mm256_and_si256(more, _mm256_cmpgt_epi32(edge_count, bin[j]));
      bin[j] = _mm256_sub_epi32(bin[j], more);  // a true lane is -1
      any = _mm256_or_si256(any, more);
    }
    if (step >= 2 && _mm256_testz_si256(any, any)) break;
  }
  for (int j = 0; j < kVectors; ++j) bin[j] = _mm256_min_epi32(bin[j], edge_count);
}

// countLe: entries <= key among p[start .. start + n) per lane, bisecting to one entry.
template <class Gather>
BTF_AVX2 inline void countLe(Gather gather, const __m256i (&start)[kVectors], __m256i (&n)[kVectors],
                             const __m256i (&key)[kVectors], int steps, __m256i (&base)[kVectors]) {
  const __m256i one = _mm256_set1_epi32(1);
  for (int j = 0; j < kVectors; ++j) base[j] = _mm256_setzero_si256();
  for (int i = 0; i < steps; ++i)
    for (int j = 0; j < kVectors; ++j) {
      const __m256i half = _mm256_srli_epi32(n[j], 1);
      const __m256i v = gather(_mm256_sub_epi32(_mm256_add_epi32(start[j], _mm256_add_epi32(base[j], half)), one));
      base[j] = _mm256_add_epi32(base[j], _mm256_andnot_si256(_mm256_cmpgt_epi32(v, key[j]), half));
      n[j] = _mm256_sub_epi32(n[j], half);
    }
  for (int j = 0; j < kVectors; ++j) {
    const __m256i v = gather(_mm256_add_epi32(start[j], base[j]));
    const __m256i le_last = _mm256_andnot_si256(_mm256_cmpgt_epi32(v, key[j]), _mm256_cmpeq_epi32(n[j], one));
    base[j] = _mm256_sub_epi32(base[j], le_last);
  }
}

struct Segment {
  __m256 q0, dq, x0, dx;
};

// segmentAt (16-bit keys): segment k of a CDF with m interior vertices and n grid cells.
BTF_AVX2 inline Segment segmentAt(const Tables& t, __m256i start, __m256i k, __m256i m, int n) {
  const __m256i zero = _mm256_setzero_si256();
  const __m256i first = _mm256_cmpeq_epi32(k, zero), last = _mm256_cmpeq_epi32(k, m);
  const __m256i at = _mm256_add_epi32(start, k), before = _mm256_sub_epi32(at, _mm256_set1_epi32(1));
  const NodeGather nodes{t.nodes16, t.nodes8};
  const __m256i xa = _mm256_andnot_si256(first, nodes(before));
  const __m256i xb = _mm256_blendv_epi8(nodes(at), _mm256_set1_epi32(n), last);
  const __m256i qa_bits = _mm256_andnot_si256(first, gather16(t.keys, before));
  const __m256i qb_bits = _mm256_or_si256(gather16(t.keys, at), _mm256_and_si256(last, _mm256_set1_epi32(0xffff)));
  const __m256 qa = _mm256_cvtepi32_ps(qa_bits), qb = _mm256_cvtepi32_ps(qb_bits);
  return {qa, _mm256_sub_ps(qb, qa), _mm256_cvtepi32_ps(xa), _mm256_cvtepi32_ps(_mm256_sub_epi32(xb, xa))};
}

// invert: the position in grid units, below the segment's end node.
BTF_AVX2 inline __m256 invert(const Segment& s, __m256 uq) {
  const __m256 t = _mm256_div_ps(_mm256_sub_ps(uq, s.q0), s.dq);
  const __m256 g = _mm256_add_ps(s.x0, _mm256_mul_ps(t, s.dx));
  const __m256 end = _mm256_add_ps(s.x0, s.dx);
  const __m256 below = _mm256_castsi256_ps(_mm256_sub_epi32(_mm256_castps_si256(end), _mm256_set1_epi32(1)));
  return _mm256_min_ps(g, below);
}

// wellInside.
BTF_AVX2 inline __m256 wellInside(__m256 g, float margin) {
  const __m256 frac = _mm256_sub_ps(g, _mm256_cvtepi32_ps(_mm256_cvttps_epi32(g)));
  return _mm256_and_ps(_mm256_cmp_ps(frac, _mm256_set1_ps(margin), _CMP_GE_OQ),
                       _mm256_cmp_ps(frac, _mm256_set1_ps(1.0f - margin), _CMP_LE_OQ));
}

BTF_AVX2 inline __m256 mul(__m256 x, __m256 y) { return _mm256_mul_ps(x, y); }
BTF_AVX2 inline __m256 add(__m256 x, float y) { return _mm256_add_ps(_mm256_set1_ps(y), x); }
// c0 - c1 z.
BTF_AVX2 inline __m256 linear(float c0, float c1, __m256 z) {
  return _mm256_sub_ps(_mm256_set1_ps(c0), _mm256_mul_ps(_mm256_set1_ps(c1), z));
}

// cosSinTurns (core/fast_trig.h).
BTF_AVX2 inline void cosSinTurns(__m256 t, __m256& c, __m256& s) {
  const __m256i quarter = _mm256_cvttps_epi32(_mm256_add_ps(_mm256_mul_ps(_mm256_set1_ps(4.0f), t), _mm256_set1_ps(0.5f)));
  const __m256 a = _mm256_mul_ps(_mm256_set1_ps(6.28318531f),
                                 _mm256_sub_ps(t, _mm256_mul_ps(_mm256_set1_ps(0.25f), _mm256_cvtepi32_ps(quarter))));
  const __m256 a2 = _mm256_mul_ps(a, a);
  const __m256 sin_a =
      mul(a, add(mul(a2, add(mul(a2, add(mul(a2, add(mul(a2, _mm256_set1_ps(1.0f / 362880)), -1.0f / 5040)), 1.0f / 120)),
                         -1.0f / 6)),
                 1.0f));
  const __m256 cos_a =
      add(mul(a2, add(mul(a2, add(mul(a2, add(mul(a2, _mm256_set1_ps(1.0f / 40320)), -1.0f / 720)), 1.0f / 24)), -0.5f)),
          1.0f);
  const __m256i swap = _mm256_sub_epi32(_mm256_setzero_si256(), _mm256_and_si256(quarter, _mm256_set1_epi32(1)));
  const __m256i negate = _mm256_slli_epi32(_mm256_and_si256(quarter, _mm256_set1_epi32(2)), 30);
  const __m256i cb = _mm256_castps_si256(cos_a), sb = _mm256_castps_si256(sin_a);
  const __m256i sign = _mm256_set1_epi32(int(0x80000000u));
  c = _mm256_castsi256_ps(_mm256_xor_si256(
      _mm256_or_si256(_mm256_andnot_si256(swap, cb), _mm256_and_si256(_mm256_xor_si256(sb, sign), swap)), negate));
  s = _mm256_castsi256_ps(
      _mm256_xor_si256(_mm256_or_si256(_mm256_andnot_si256(swap, sb), _mm256_and_si256(cb, swap)), negate));
}

// fastAtan2Turns.
BTF_AVX2 inline __m256 atan2Turns(__m256 y, __m256 x) {
  const __m256 abs_mask = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
  const __m256 ax = _mm256_and_ps(x, abs_mask), ay = _mm256_and_ps(y, abs_mask);
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
  return _mm256_and_ps(r, _mm256_cmp_ps(hi, _mm256_setzero_ps(), _CMP_GT_OQ));  // hi == 0: 0
}

// query(wo) for an isotropic sampler: the rotation by -phi_o.
BTF_AVX2 inline void binRotation(__m256 x, __m256 y, __m256& c, __m256& s) {
  const __m256 r2 = _mm256_add_ps(_mm256_mul_ps(x, x), _mm256_mul_ps(y, y));
  const __m256 inv = _mm256_div_ps(_mm256_set1_ps(1.0f), _mm256_sqrt_ps(r2));
  const __m256 off_pole = _mm256_cmp_ps(r2, _mm256_setzero_ps(), _CMP_GT_OQ);
  c = select(_mm256_set1_ps(1.0f), _mm256_mul_ps(x, inv), off_pole);
  s = _mm256_and_ps(_mm256_mul_ps(y, inv), off_pole);
}

// Returns the lanes whose pdf must come from the scalar pdf() (draw too close to a cell border).
BTF_AVX2 std::uint64_t sampleLanes(const Tables& t, Lanes& l) {
  constexpr int V = kVectors;
  const __m256i one = _mm256_set1_epi32(1);
  const __m256 top = _mm256_set1_ps(65535.0f), fnu = _mm256_set1_ps(float(t.nu)), fnv = _mm256_set1_ps(float(t.nv));
  const int* starts = reinterpret_cast<const int*>(t.starts);
  __m256 oz[V], us[V], ut[V];
  __m256i bin[V], bin_base[V], ms[V], ns[V], mt[V], nt[V], key[V], ks[V], kt[V];
  for (int j = 0; j < V; ++j) oz[j] = _mm256_load_ps(l.oz + 8 * j);
  thetaBins(t, oz, bin);
  // Marginal.
  for (int j = 0; j < V; ++j) {
    _mm256_store_si256(reinterpret_cast<__m256i*>(l.bin + 8 * j), bin[j]);
    bin_base[j] = _mm256_mullo_epi32(bin[j], _mm256_set1_epi32(t.nu + 1));
    us[j] = _mm256_mul_ps(_mm256_load_ps(l.a0 + 8 * j), top);
    ut[j] = _mm256_mul_ps(_mm256_load_ps(l.a1 + 8 * j), top);
    ms[j] = _mm256_i32gather_epi32(starts, bin_base[j], 4);
    ns[j] = _mm256_sub_epi32(_mm256_i32gather_epi32(starts, _mm256_add_epi32(bin_base[j], one), 4), ms[j]);
    key[j] = _mm256_cvttps_epi32(us[j]);
  }
  __m256i n[V];
  for (int j = 0; j < V; ++j) n[j] = ns[j];
  countLe(KeyGather{t.keys}, ms, n, key, t.steps, ks);
  Segment seg_s[V];
  __m256 gs[V], s[V];
  for (int j = 0; j < V; ++j) {
    seg_s[j] = segmentAt(t, ms[j], ks[j], ns[j], t.nu);
    gs[j] = invert(seg_s[j], us[j]);
    s[j] = _mm256_div_ps(gs[j], fnu);
    const __m256i row = _mm256_min_epi32(_mm256_cvttps_epi32(_mm256_mul_ps(s[j], fnu)), _mm256_set1_epi32(t.nu - 1));
    // The row's conditional.
    const __m256i row_index = _mm256_add_epi32(bin_base[j], _mm256_add_epi32(row, one));
    mt[j] = _mm256_i32gather_epi32(starts, row_index, 4);
    nt[j] = _mm256_sub_epi32(_mm256_i32gather_epi32(starts, _mm256_add_epi32(row_index, one), 4), mt[j]);
    key[j] = _mm256_cvttps_epi32(ut[j]);
    n[j] = nt[j];
  }
  countLe(KeyGather{t.keys}, mt, n, key, t.steps, kt);
  std::uint64_t near_border = 0;
  for (int j = 0; j < V; ++j) {
    const Segment seg_t = segmentAt(t, mt[j], kt[j], nt[j], t.nv);
    const __m256 gt = invert(seg_t, ut[j]);
    const __m256 tt = _mm256_div_ps(gt, fnv);
    // squareToDirection, fromBinFrame, normalize.
    __m256 cos_phi, sin_phi;
    binRotation(_mm256_load_ps(l.ox + 8 * j), _mm256_load_ps(l.oy + 8 * j), cos_phi, sin_phi);
    const __m256 r =
        _mm256_sqrt_ps(_mm256_max_ps(_mm256_sub_ps(_mm256_set1_ps(1.0f), _mm256_mul_ps(s[j], s[j])), _mm256_setzero_ps()));
    __m256 c, sn;
    cosSinTurns(tt, c, sn);
    const __m256 bx = _mm256_mul_ps(r, c), by = _mm256_mul_ps(r, sn);
    const __m256 x = _mm256_sub_ps(_mm256_mul_ps(cos_phi, bx), _mm256_mul_ps(sin_phi, by));
    const __m256 y = _mm256_add_ps(_mm256_mul_ps(sin_phi, bx), _mm256_mul_ps(cos_phi, by));
    const __m256 len2 =
        _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(x, x), _mm256_mul_ps(y, y)), _mm256_mul_ps(s[j], s[j]));
    const __m256 inv = _mm256_div_ps(_mm256_set1_ps(1.0f), _mm256_sqrt_ps(len2));
    _mm256_store_ps(l.wx + 8 * j, _mm256_mul_ps(x, inv));
    _mm256_store_ps(l.wy + 8 * j, _mm256_mul_ps(y, inv));
    _mm256_store_ps(l.wz + 8 * j, _mm256_mul_ps(s[j], inv));
    // pdfOf from the segments just drawn.
    const __m256 p = _mm256_mul_ps(
        _mm256_mul_ps(_mm256_div_ps(seg_s[j].dq, seg_s[j].dx), _mm256_div_ps(seg_t.dq, seg_t.dx)),
        _mm256_set1_ps(t.pdf_scale));
    _mm256_store_ps(l.pdf + 8 * j, p);
    const __m256 inside = _mm256_and_ps(wellInside(gs[j], DpCdfSampler::kCellMargin * float(t.nu)),
                                        wellInside(gt, DpCdfSampler::kCellMargin * float(t.nv)));
    near_border |= std::uint64_t(~_mm256_movemask_ps(inside) & 0xff) << (8 * j);
  }
  return near_border;
}

// pdfQuery + pdfImpl for wi = (a0, a1, a2); lanes outside the domain get 0.
BTF_AVX2 void pdfLanes(const Tables& t, Lanes& l) {
  constexpr int V = kVectors;
  const __m256i one = _mm256_set1_epi32(1);
  const int* starts = reinterpret_cast<const int*>(t.starts);
  __m256 oz[V], in_domain[V];
  __m256i bin[V], ms[V], ns[V], mt[V], nt[V], row[V], col[V], ks[V], kt[V], n[V];
  for (int j = 0; j < V; ++j) oz[j] = _mm256_load_ps(l.oz + 8 * j);
  thetaBins(t, oz, bin);
  for (int j = 0; j < V; ++j) {
    _mm256_store_si256(reinterpret_cast<__m256i*>(l.bin + 8 * j), bin[j]);
    const __m256 ix = _mm256_load_ps(l.a0 + 8 * j), iy = _mm256_load_ps(l.a1 + 8 * j), iz = _mm256_load_ps(l.a2 + 8 * j);
    __m256 c, s;
    binRotation(_mm256_load_ps(l.ox + 8 * j), _mm256_load_ps(l.oy + 8 * j), c, s);
    // toBinFrame and directionToSquare.
    const __m256 bx = _mm256_add_ps(_mm256_mul_ps(c, ix), _mm256_mul_ps(s, iy));
    const __m256 by = _mm256_add_ps(_mm256_mul_ps(_mm256_xor_ps(s, _mm256_set1_ps(-0.0f)), ix), _mm256_mul_ps(c, iy));
    const __m256 phi = atan2Turns(by, bx);
    const __m256 sum = _mm256_add_ps(phi, _mm256_set1_ps(1.0f));
    const __m256i at_one = _mm256_castps_si256(_mm256_cmp_ps(sum, _mm256_set1_ps(1.0f), _CMP_GE_OQ));
    const __m256 wrapped = _mm256_castsi256_ps(_mm256_add_epi32(_mm256_castps_si256(sum), at_one));
    const __m256 st_y = select(phi, wrapped, _mm256_cmp_ps(phi, _mm256_setzero_ps(), _CMP_LT_OQ));
    const __m256 st_x = iz;
    in_domain[j] = _mm256_and_ps(_mm256_cmp_ps(iz, _mm256_setzero_ps(), _CMP_GT_OQ),
                                 _mm256_cmp_ps(st_x, _mm256_set1_ps(1.0f), _CMP_LT_OQ));
    // pdfImpl; lanes outside the domain (whose result is dropped) search row and column 0.
    const __m256i keep = _mm256_castps_si256(in_domain[j]);
    row[j] = _mm256_and_si256(keep, _mm256_min_epi32(_mm256_cvttps_epi32(_mm256_mul_ps(st_x, _mm256_set1_ps(float(t.nu)))),
                                                     _mm256_set1_epi32(t.nu - 1)));
    col[j] = _mm256_and_si256(keep, _mm256_min_epi32(_mm256_cvttps_epi32(_mm256_mul_ps(st_y, _mm256_set1_ps(float(t.nv)))),
                                                     _mm256_set1_epi32(t.nv - 1)));
    const __m256i bin_base = _mm256_mullo_epi32(bin[j], _mm256_set1_epi32(t.nu + 1));
    ms[j] = _mm256_i32gather_epi32(starts, bin_base, 4);
    ns[j] = _mm256_sub_epi32(_mm256_i32gather_epi32(starts, _mm256_add_epi32(bin_base, one), 4), ms[j]);
    const __m256i row_index = _mm256_add_epi32(bin_base, _mm256_add_epi32(row[j], one));
    mt[j] = _mm256_i32gather_epi32(starts, row_index, 4);
    nt[j] = _mm256_sub_epi32(_mm256_i32gather_epi32(starts, _mm256_add_epi32(row_index, one), 4), mt[j]);
  }
  for (int j = 0; j < V; ++j) n[j] = ns[j];
  countLe(NodeGather{t.nodes16, t.nodes8}, ms, n, row, t.steps, ks);
  for (int j = 0; j < V; ++j) n[j] = nt[j];
  countLe(NodeGather{t.nodes16, t.nodes8}, mt, n, col, t.steps, kt);
  for (int j = 0; j < V; ++j) {
    const Segment seg_s = segmentAt(t, ms[j], ks[j], ns[j], t.nu);
    const Segment seg_t = segmentAt(t, mt[j], kt[j], nt[j], t.nv);
    const __m256 p = _mm256_mul_ps(_mm256_mul_ps(_mm256_div_ps(seg_s.dq, seg_s.dx), _mm256_div_ps(seg_t.dq, seg_t.dx)),
                                   _mm256_set1_ps(t.pdf_scale));
    _mm256_store_ps(l.pdf + 8 * j, _mm256_and_ps(p, in_domain[j]));
  }
}

bool finite(float v) { return std::isfinite(v); }
bool finite(const glm::vec3& v) { return finite(v.x) && finite(v.y) && finite(v.z); }

// A wo the vector path takes as the scalar path does; others (below the horizon, NaN, infinite)
// go to the scalar path, which rejects them quickly.
bool regularWo(const glm::vec3& wo) { return wo.z > 0.0f && finite(wo); }

// Runs the lanes over n queries, kLanes at a time: load(k, i) fills lane k from query i and says
// whether the lanes may take it (else the lane gets a harmless default and store hears false);
// run() computes the block and returns the lanes needing the scalar pdf; store(k, i, taken, near)
// writes query i's result.
template <class Load, class Run, class Store>
void forEachBlock(std::size_t n, Lanes& l, Load load, Run run, Store store) {
  for (std::size_t i0 = 0; i0 < n; i0 += kLanes) {
    const int lanes = int(std::min<std::size_t>(kLanes, n - i0));
    std::uint64_t taken = 0;
    for (int k = 0; k < kLanes; ++k) {
      if (k < lanes && load(k, i0 + std::size_t(k))) {
        taken |= std::uint64_t(1) << k;
      } else {
        l.ox[k] = 0.0f, l.oy[k] = 0.0f, l.oz[k] = 1.0f, l.a0[k] = 0.5f, l.a1[k] = 0.5f, l.a2[k] = 0.5f;
      }
    }
    const std::uint64_t near_border = run();
    for (int k = 0; k < lanes; ++k) store(k, i0 + std::size_t(k), (taken >> k & 1) != 0, (near_border >> k & 1) != 0);
  }
}

}  // namespace

struct DpCdfSampler::LaneTables : Tables {};

DpCdfSampler::LaneTables DpCdfSampler::laneTables() const {
  const ThetaBinTable theta = thetaBinTable();
  return {{cdf16_.data(), byte_nodes_ ? nullptr : nodes16_.data(), byte_nodes_ ? nodes8_.data() : nullptr,
           starts_.data(), theta.edges, theta.guide, theta.last_cell, theta.edge_count, nu_, nv_,
           full_search_steps_, pdf_scale_}};
}

bool DpCdfSampler::vectorized() const {
  return narrow_ && !isAnisotropic() && parameterization() == Parameterization::Incident && cpuHasAvx2() &&
         std::max(nodes16_.size(), nodes8_.size()) < (std::size_t(1) << 30) && starts_.size() < (std::size_t(1) << 30);
}

void DpCdfSampler::sampleDirections(std::span<const glm::vec3> wo, std::span<const glm::vec2> u,
                                    std::span<DirectionSample> out) const {
  if (u.size() != wo.size() || out.size() != wo.size()) throw Error("sampleDirections: spans of different sizes");
  if (!vectorized()) return BinnedSampler::sampleDirections(wo, u, out);
  const LaneTables t = laneTables();
  Lanes l;
  auto load = [&](int k, std::size_t i) {
    // u in [0, 1): outside it the 16-bit keys of the scalar path wrap (unsigned) where lanes do not.
    if (!(regularWo(wo[i]) && u[i].x >= 0.0f && u[i].x < 1.0f && u[i].y >= 0.0f && u[i].y < 1.0f)) return false;
    l.ox[k] = wo[i].x, l.oy[k] = wo[i].y, l.oz[k] = wo[i].z, l.a0[k] = u[i].x, l.a1[k] = u[i].y;
    return true;
  };
  auto store = [&](int k, std::size_t i, bool taken, bool near_border) {
    if (!taken || empty_[std::size_t(l.bin[k])]) {
      int tries = 0;
      out[i] = sampleDirection(wo[i], u[i], tries).value_or(DirectionSample{glm::vec3(0.0f), 0.0f});
      return;
    }
    const glm::vec3 wi(l.wx[k], l.wy[k], l.wz[k]);
    const float p = near_border ? DpCdfSampler::pdfQuery(query(wo[i]), wi) : l.pdf[k];
    out[i] = p > 0.0f ? DirectionSample{wi, p} : DirectionSample{glm::vec3(0.0f), 0.0f};
  };
  forEachBlock(wo.size(), l, load, [&] { return sampleLanes(t, l); }, store);
}

void DpCdfSampler::pdfs(std::span<const glm::vec3> wi, std::span<const glm::vec3> wo, std::span<float> out) const {
  if (wo.size() != wi.size() || out.size() != wi.size()) throw Error("pdfs: spans of different sizes");
  if (!vectorized()) return BinnedSampler::pdfs(wi, wo, out);
  const LaneTables t = laneTables();
  Lanes l;
  auto load = [&](int k, std::size_t i) {
    if (!(regularWo(wo[i]) && finite(wi[i]))) return false;
    l.ox[k] = wo[i].x, l.oy[k] = wo[i].y, l.oz[k] = wo[i].z, l.a0[k] = wi[i].x, l.a1[k] = wi[i].y, l.a2[k] = wi[i].z;
    return true;
  };
  auto store = [&](int k, std::size_t i, bool taken, bool) {
    out[i] = !taken ? pdf(wi[i], wo[i]) : empty_[std::size_t(l.bin[k])] ? 0.0f : l.pdf[k];
  };
  forEachBlock(wo.size(), l, load, [&] { pdfLanes(t, l); return std::uint64_t(0); }, store);
}

}  // namespace btf
