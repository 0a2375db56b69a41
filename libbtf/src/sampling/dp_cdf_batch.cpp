// The vector path of DpCdfSampler::sampleDirections and pdfs (dp_cdf_sampler.h): 32 queries per
// step in AVX2 lanes (four vectors of eight), with the searches done by gathers.
//
// Written with intrinsics by hand: GCC's vectorizer emits no gathers for generic tuning, and the
// arithmetic has to be the scalar path's, operation for operation, so that a query gives the same
// bits on every CPU (and sample's pdf stays pdf()'s). The functions are compiled for "avx2" alone,
// not "fma": with FMA enabled the compiler would fuse a multiply and an add into one rounding.
// Each step below names the scalar code it mirrors (binned_sampler.h, parameterization.h,
// dp_cdf_sampler.cpp, core/fast_trig.h, core/fast_atan.h), down to the order of the operands of
// a sum and to what std::min / std::max / std::clamp return for NaN or for -0 against +0; scalar
// branches become selects (both sides computed, a side not taken may divide by 0 harmlessly).
// The searches bisect all the way down to one entry (the scalar path stops at 32 and compares a
// block): both count the entries <= the key, so they find the same segment.
// Both parameterizations. Incident draws take the pdf from the segments just drawn (the scalar
// pdf() for lanes near a cell border), as sampleImpl does. Half draws follow pdf()'s path in the
// lanes, as sampleImpl does (wi back onto the square through its half vector, the Jacobian), up
// to pdfImpl's searches: where wi's square point lies in the drawn row and segments, those
// searches would find the drawn segments, so the lanes take them (the rare others take the
// scalar pdf).
#include <immintrin.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "avx2_lanes.h"
#include "btf/core/error.h"
#include "btf/sampling/dp_cdf_sampler.h"

namespace btf {

// The tables as the lanes read them; named rather than file-local, since DpCdfSampler::LaneTables
// (declared in the public header) derives from it, and a base in an anonymous namespace is a
// -Wsubobject-linkage warning once the unity build includes this file into another.
namespace dp_cdf_lanes {
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
}  // namespace dp_cdf_lanes

namespace {

using namespace avx2;
using dp_cdf_lanes::Tables;

// Queries per step: four vectors of eight, interleaved step by step, so that one vector's gathers
// run while another waits for its own (the searches are chains of dependent gathers; eight
// vectors measured no faster than four).
constexpr int kVectors = 4;
constexpr int kLanes = 8 * kVectors;
static_assert(kLanes <= 64, "lane masks are 64-bit");

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

struct SegmentLanes {
  __m256 q0, dq, x0, dx;
};

// segmentAt (16-bit keys): segment k of a CDF with m interior vertices and n grid cells.
BTF_AVX2 inline SegmentLanes segmentAt(const Tables& t, __m256i start, __m256i k, __m256i m, int n) {
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
BTF_AVX2 inline __m256 invert(const SegmentLanes& s, __m256 uq) {
  const __m256 t = _mm256_div_ps(_mm256_sub_ps(uq, s.q0), s.dq);
  const __m256 g = _mm256_add_ps(s.x0, _mm256_mul_ps(t, s.dx));
  const __m256 end = _mm256_add_ps(s.x0, s.dx);
  const __m256 below = _mm256_castsi256_ps(_mm256_sub_epi32(_mm256_castps_si256(end), _mm256_set1_epi32(1)));
  return stdMin(g, below);
}

// wellInside.
BTF_AVX2 inline __m256 wellInside(__m256 g, float margin) {
  const __m256 frac = _mm256_sub_ps(g, _mm256_cvtepi32_ps(_mm256_cvttps_epi32(g)));
  return _mm256_and_ps(_mm256_cmp_ps(frac, _mm256_set1_ps(margin), _CMP_GE_OQ),
                       _mm256_cmp_ps(frac, _mm256_set1_ps(1.0f - margin), _CMP_LE_OQ));
}

// pdfOf: (dq_s / dx_s) (dq_t / dx_t) scale.
BTF_AVX2 inline __m256 pdfOf(const SegmentLanes& s, const SegmentLanes& t, float scale) {
  return _mm256_mul_ps(_mm256_mul_ps(_mm256_div_ps(s.dq, s.dx), _mm256_div_ps(t.dq, t.dx)), _mm256_set1_ps(scale));
}

// Whether the grid cell `cell` (a float of an int) lies in the segment: x0 <= cell < x0 + dx.
BTF_AVX2 inline __m256 inSegment(const SegmentLanes& s, __m256 cell) {
  return _mm256_and_ps(_mm256_cmp_ps(cell, s.x0, _CMP_GE_OQ), _mm256_cmp_ps(cell, _mm256_add_ps(s.x0, s.dx), _CMP_LT_OQ));
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

// query(wo) for an isotropic sampler: the rotation by -phi_o (BinQuery's cos_phi, sin_phi), and
// BinQuery's toBinFrame / fromBinFrame.
struct Rotation {
  __m256 c, s;
  // {cos_phi x + sin_phi y, -sin_phi x + cos_phi y, z}
  BTF_AVX2 Vec3 toBinFrame(const Vec3& w) const {
    return {_mm256_add_ps(_mm256_mul_ps(c, w.x), _mm256_mul_ps(s, w.y)),
            _mm256_add_ps(_mm256_mul_ps(flipSign(s), w.x), _mm256_mul_ps(c, w.y)), w.z};
  }
  // {cos_phi x - sin_phi y, sin_phi x + cos_phi y, z}
  BTF_AVX2 Vec3 fromBinFrame(const Vec3& w) const {
    return {_mm256_sub_ps(_mm256_mul_ps(c, w.x), _mm256_mul_ps(s, w.y)),
            _mm256_add_ps(_mm256_mul_ps(s, w.x), _mm256_mul_ps(c, w.y)), w.z};
  }
};
BTF_AVX2 inline Rotation binRotation(__m256 x, __m256 y) {
  const __m256 r2 = _mm256_add_ps(_mm256_mul_ps(x, x), _mm256_mul_ps(y, y));
  const __m256 inv = _mm256_div_ps(_mm256_set1_ps(1.0f), _mm256_sqrt_ps(r2));
  const __m256 off_pole = _mm256_cmp_ps(r2, _mm256_setzero_ps(), _CMP_GT_OQ);  // else the identity
  return {select(_mm256_set1_ps(1.0f), _mm256_mul_ps(x, inv), off_pole), _mm256_and_ps(_mm256_mul_ps(y, inv), off_pole)};
}

// squareToDirection (Incident).
BTF_AVX2 inline Vec3 squareToDirection(__m256 s, __m256 t) {
  const __m256 r = _mm256_sqrt_ps(stdMax(_mm256_sub_ps(_mm256_set1_ps(1.0f), _mm256_mul_ps(s, s)), _mm256_setzero_ps()));
  __m256 c, sn;
  cosSinTurns(t, c, sn);
  return {_mm256_mul_ps(r, c), _mm256_mul_ps(r, sn), s};
}

// squareToHalfVector (parameterization.h). Its three branches become selects: every lane computes
// both radii and turns (the one not taken may divide by 0, harmlessly), and the square's centre
// (|a| > |b| false and b == 0) gets the pole.
BTF_AVX2 inline Vec3 squareToHalfVector(__m256 s, __m256 t) {
  const __m256 one = _mm256_set1_ps(1.0f), two = _mm256_set1_ps(2.0f), eight = _mm256_set1_ps(8.0f);
  const __m256 a = _mm256_sub_ps(_mm256_mul_ps(two, s), one), b = _mm256_sub_ps(_mm256_mul_ps(two, t), one);
  const __m256 a_wider = _mm256_cmp_ps(stdAbs(a), stdAbs(b), _CMP_GT_OQ);
  const __m256 r = select(b, a, a_wider);
  const __m256 turns = select(_mm256_sub_ps(_mm256_set1_ps(0.25f), _mm256_div_ps(a, _mm256_mul_ps(eight, b))),
                              _mm256_div_ps(b, _mm256_mul_ps(eight, a)), a_wider);
  const __m256 centre = _mm256_andnot_ps(a_wider, _mm256_cmp_ps(b, _mm256_setzero_ps(), _CMP_EQ_OQ));  // !(b != 0)
  __m256 c, sn;
  cosSinTurns(turns, c, sn);
  const __m256 rho = _mm256_mul_ps(r, stdAbs(r));
  const __m256 rho2 = _mm256_mul_ps(rho, rho);
  const __m256 k = _mm256_mul_ps(rho, _mm256_sqrt_ps(stdMax(_mm256_sub_ps(two, rho2), _mm256_setzero_ps())));
  return {_mm256_andnot_ps(centre, _mm256_mul_ps(k, c)), _mm256_andnot_ps(centre, _mm256_mul_ps(k, sn)),
          select(_mm256_sub_ps(one, rho2), one, centre)};
}

// halfVectorToSquare (parameterization.h): (s, t) and the concentric radius r. The octant's four
// branches become selects applied in reverse order of the if-chain, so that the first branch whose
// test holds wins; a NaN turns fails every test and takes the last branch, as in the scalar code.
struct HalfSquare {
  __m256 s, t, r;
};
BTF_AVX2 inline HalfSquare halfVectorToSquare(const Vec3& h) {
  const __m256 half = _mm256_set1_ps(0.5f), one = _mm256_set1_ps(1.0f), two = _mm256_set1_ps(2.0f),
               eight = _mm256_set1_ps(8.0f);
  const __m256 rho2 = _mm256_add_ps(_mm256_mul_ps(h.x, h.x), _mm256_mul_ps(h.y, h.y));
  const __m256 r = _mm256_sqrt_ps(_mm256_sqrt_ps(_mm256_div_ps(rho2, _mm256_add_ps(one, stdMax(h.z, _mm256_setzero_ps())))));
  const __m256 turns = atan2Turns(h.y, h.x);
  // else: shifted = turns + 0.5, b = -r, a = b (2 - 8 shifted).
  __m256 b = flipSign(r);
  __m256 a = _mm256_mul_ps(b, _mm256_sub_ps(two, _mm256_mul_ps(eight, _mm256_add_ps(turns, half))));
  // turns >= 3/8 || turns <= -3/8: shifted = turns > 0 ? turns - 0.5 : turns + 0.5, a = -r, b = a (8 shifted).
  const __m256 shifted = select(_mm256_add_ps(turns, half), _mm256_sub_ps(turns, half), compare<_CMP_GT_OQ>(turns, 0.0f));
  const __m256 third = _mm256_or_ps(compare<_CMP_GE_OQ>(turns, 0.375f), compare<_CMP_LE_OQ>(turns, -0.375f));
  a = select(a, flipSign(r), third);
  b = select(b, _mm256_mul_ps(flipSign(r), _mm256_mul_ps(eight, shifted)), third);
  // 1/8 < turns < 3/8: b = r, a = r (2 - 8 turns).
  const __m256 second = _mm256_and_ps(compare<_CMP_GT_OQ>(turns, 0.125f), compare<_CMP_LT_OQ>(turns, 0.375f));
  a = select(a, _mm256_mul_ps(r, _mm256_sub_ps(two, _mm256_mul_ps(eight, turns))), second);
  b = select(b, r, second);
  // -1/8 <= turns <= 1/8: a = r, b = r (8 turns).
  const __m256 first = _mm256_and_ps(compare<_CMP_GE_OQ>(turns, -0.125f), compare<_CMP_LE_OQ>(turns, 0.125f));
  a = select(a, r, first);
  b = select(b, _mm256_mul_ps(r, _mm256_mul_ps(eight, turns)), first);
  return {stdClamp(_mm256_mul_ps(half, _mm256_add_ps(a, one)), 0.0f, 1.0f),
          stdClamp(_mm256_mul_ps(half, _mm256_add_ps(b, one)), 0.0f, 1.0f), r};
}

// Where pdfQuery takes each lane's wi on the square: the point (s, t), whether it gets there at
// all (else its pdf is 0: wi.z <= 0, outside the square, NaN) and, for Half, the factor it applies
// to pdfImpl's value (kTwoPi * to_solid_angle).
struct SquareLanes {
  __m256 s, t, ok, factor;
};

// incomingToSquare (Incident) behind pdfQuery's wi.z > 0 (wi_bin.z is wi.z): directionToSquare,
// nothing unless s < 1.
BTF_AVX2 inline SquareLanes incidentToSquare(const Vec3& wi_bin) {
  const __m256 phi = atan2Turns(wi_bin.y, wi_bin.x);
  // The wrap into [0, 1): t + 1, and exactly 1 becomes the float below it.
  const __m256 sum = _mm256_add_ps(phi, _mm256_set1_ps(1.0f));
  const __m256i at_one = _mm256_castps_si256(_mm256_cmp_ps(sum, _mm256_set1_ps(1.0f), _CMP_GE_OQ));
  const __m256 wrapped = _mm256_castsi256_ps(_mm256_add_epi32(_mm256_castps_si256(sum), at_one));
  const __m256 t = select(phi, wrapped, _mm256_cmp_ps(phi, _mm256_setzero_ps(), _CMP_LT_OQ));
  const __m256 ok = _mm256_and_ps(_mm256_cmp_ps(wi_bin.z, _mm256_setzero_ps(), _CMP_GT_OQ),
                                  _mm256_cmp_ps(wi_bin.z, _mm256_set1_ps(1.0f), _CMP_LT_OQ));
  return {wi_bin.z, t, ok, _mm256_set1_ps(1.0f)};
}

// incomingToSquare (Half) behind pdfQuery's wi.z > 0: h = normalize(wi + wo), d = wo.h, the
// square point of h, the Jacobian (16 pi) (r r) d, nothing unless it is > 0 and s, t >= 0; the
// factor kTwoPi * (1 / jacobian).
BTF_AVX2 inline SquareLanes halfToSquare(const Vec3& wi_bin, const Vec3& wo_bin) {
  const Vec3 h = normalize({_mm256_add_ps(wi_bin.x, wo_bin.x), _mm256_add_ps(wi_bin.y, wo_bin.y),
                            _mm256_add_ps(wi_bin.z, wo_bin.z)});
  const __m256 d = dot(wo_bin, h);
  const HalfSquare m = halfVectorToSquare(h);
  const __m256 jacobian = _mm256_mul_ps(_mm256_mul_ps(_mm256_set1_ps(16.0f * kPi), _mm256_mul_ps(m.r, m.r)), d);
  const __m256 zero = _mm256_setzero_ps();
  const __m256 ok = _mm256_and_ps(
      _mm256_and_ps(_mm256_cmp_ps(wi_bin.z, zero, _CMP_GT_OQ), _mm256_cmp_ps(jacobian, zero, _CMP_GT_OQ)),
      _mm256_and_ps(_mm256_cmp_ps(m.s, zero, _CMP_GE_OQ), _mm256_cmp_ps(m.t, zero, _CMP_GE_OQ)));
  const __m256 to_solid_angle = _mm256_div_ps(_mm256_set1_ps(1.0f), jacobian);
  return {m.s, m.t, ok, _mm256_mul_ps(_mm256_set1_ps(kTwoPi), to_solid_angle)};
}

// pdfImpl at each lane's square point, times the factor for Half (pdfQuery); lanes that are not
// ok search row and column 0 and get 0.
template <bool kHalf>
BTF_AVX2 inline void pdfOfSquare(const Tables& t, const __m256i (&bin)[kVectors], const SquareLanes (&sq)[kVectors],
                                 __m256 (&pdf)[kVectors]) {
  constexpr int V = kVectors;
  const __m256i one = _mm256_set1_epi32(1);
  const int* starts = reinterpret_cast<const int*>(t.starts);
  __m256i ms[V], ns[V], mt[V], nt[V], row[V], col[V], ks[V], kt[V], n[V];
  for (int j = 0; j < V; ++j) {
    const __m256i keep = _mm256_castps_si256(sq[j].ok);
    row[j] = _mm256_and_si256(keep, _mm256_min_epi32(_mm256_cvttps_epi32(_mm256_mul_ps(sq[j].s, _mm256_set1_ps(float(t.nu)))),
                                                     _mm256_set1_epi32(t.nu - 1)));
    col[j] = _mm256_and_si256(keep, _mm256_min_epi32(_mm256_cvttps_epi32(_mm256_mul_ps(sq[j].t, _mm256_set1_ps(float(t.nv)))),
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
    const SegmentLanes seg_s = segmentAt(t, ms[j], ks[j], ns[j], t.nu);
    const SegmentLanes seg_t = segmentAt(t, mt[j], kt[j], nt[j], t.nv);
    __m256 p = pdfOf(seg_s, seg_t, t.pdf_scale);
    if constexpr (kHalf) p = _mm256_mul_ps(p, sq[j].factor);
    pdf[j] = _mm256_and_ps(p, sq[j].ok);
  }
}

// sampleImpl for u = (a0, a1). Returns the lanes whose pdf must come from the scalar pdf(): an
// Incident draw too close to a cell border, a Half draw whose round trip through wi left its cell.
// A lane without a sample (Half: its reflection below the horizon, or pdf() 0) gets pdf 0.
template <bool kHalf>
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
  SegmentLanes seg_s[V];
  __m256 gs[V], s[V];
  __m256i row[V];
  for (int j = 0; j < V; ++j) {
    seg_s[j] = segmentAt(t, ms[j], ks[j], ns[j], t.nu);
    gs[j] = invert(seg_s[j], us[j]);
    s[j] = _mm256_div_ps(gs[j], fnu);
    row[j] = _mm256_min_epi32(_mm256_cvttps_epi32(_mm256_mul_ps(s[j], fnu)), _mm256_set1_epi32(t.nu - 1));
    // The row's conditional.
    const __m256i row_index = _mm256_add_epi32(bin_base[j], _mm256_add_epi32(row[j], one));
    mt[j] = _mm256_i32gather_epi32(starts, row_index, 4);
    nt[j] = _mm256_sub_epi32(_mm256_i32gather_epi32(starts, _mm256_add_epi32(row_index, one), 4), mt[j]);
    key[j] = _mm256_cvttps_epi32(ut[j]);
    n[j] = nt[j];
  }
  countLe(KeyGather{t.keys}, mt, n, key, t.steps, kt);
  std::uint64_t near_border = 0;
  for (int j = 0; j < V; ++j) {
    const SegmentLanes seg_t = segmentAt(t, mt[j], kt[j], nt[j], t.nv);
    const __m256 gt = invert(seg_t, ut[j]);
    const __m256 tt = _mm256_div_ps(gt, fnv);
    const Vec3 wo = loadVec3(l.ox + 8 * j, l.oy + 8 * j, l.oz + 8 * j);
    const Rotation rot = binRotation(wo.x, wo.y);
    if constexpr (kHalf) {
      // squareToIncoming (Half): h, d = wo.h with the query's wo in the bin frame (BinQuery::wo),
      // wi = (2 d) h - wo, nothing unless d > 0 and wi.z > 0, normalize; then fromBinFrame and
      // normalize.
      const Vec3 wo_bin = rot.toBinFrame(wo);
      const Vec3 h = squareToHalfVector(s[j], tt);
      const __m256 d = dot(wo_bin, h), d2 = _mm256_mul_ps(_mm256_set1_ps(2.0f), d);
      const Vec3 reflected = {_mm256_sub_ps(_mm256_mul_ps(d2, h.x), wo_bin.x),
                              _mm256_sub_ps(_mm256_mul_ps(d2, h.y), wo_bin.y),
                              _mm256_sub_ps(_mm256_mul_ps(d2, h.z), wo_bin.z)};
      const __m256 drawn = _mm256_and_ps(_mm256_cmp_ps(d, _mm256_setzero_ps(), _CMP_GT_OQ),
                                         _mm256_cmp_ps(reflected.z, _mm256_setzero_ps(), _CMP_GT_OQ));
      const Vec3 wi = normalize(rot.fromBinFrame(normalize(reflected)));
      _mm256_store_ps(l.wx + 8 * j, wi.x);
      _mm256_store_ps(l.wy + 8 * j, wi.y);
      _mm256_store_ps(l.wz + 8 * j, wi.z);
      // pdfQuery(q, wi): back into the bin frame and onto the square, then pdfImpl there without
      // its searches. When the point's row is the drawn row and its row and column lie in the
      // drawn segments, the searches would find those very segments (the nodes of a CDF increase
      // strictly, so a cell lies in one segment only) and pdfImpl's value is pdfOf of them, bit
      // for bit. Otherwise (the round trip crossed a cell border, or moved to another row) the
      // lane takes the scalar pdf, as an Incident draw near a border does.
      const SquareLanes sq = halfToSquare(rot.toBinFrame(wi), wo_bin);
      const __m256 ok = _mm256_and_ps(sq.ok, drawn);
      // pdfImpl's row and column.
      const __m256i row2 = _mm256_min_epi32(_mm256_cvttps_epi32(_mm256_mul_ps(sq.s, fnu)), _mm256_set1_epi32(t.nu - 1));
      const __m256i col2 = _mm256_min_epi32(_mm256_cvttps_epi32(_mm256_mul_ps(sq.t, fnv)), _mm256_set1_epi32(t.nv - 1));
      const __m256 same_row = _mm256_castsi256_ps(_mm256_cmpeq_epi32(row2, row[j]));
      const __m256 same = _mm256_and_ps(_mm256_and_ps(same_row, inSegment(seg_s[j], _mm256_cvtepi32_ps(row2))),
                                        inSegment(seg_t, _mm256_cvtepi32_ps(col2)));
      const __m256 p = _mm256_mul_ps(pdfOf(seg_s[j], seg_t, t.pdf_scale), sq.factor);  // v * (kTwoPi * to_solid_angle)
      _mm256_store_ps(l.pdf + 8 * j, _mm256_and_ps(p, ok));
      near_border |= std::uint64_t(_mm256_movemask_ps(_mm256_andnot_ps(same, ok))) << (8 * j);
    } else {
      // squareToDirection, fromBinFrame, normalize.
      const Vec3 wi = normalize(rot.fromBinFrame(squareToDirection(s[j], tt)));
      _mm256_store_ps(l.wx + 8 * j, wi.x);
      _mm256_store_ps(l.wy + 8 * j, wi.y);
      _mm256_store_ps(l.wz + 8 * j, wi.z);
      // pdfOf from the segments just drawn.
      _mm256_store_ps(l.pdf + 8 * j, pdfOf(seg_s[j], seg_t, t.pdf_scale));
      const __m256 inside = _mm256_and_ps(wellInside(gs[j], DpCdfSampler::kCellMargin * float(t.nu)),
                                          wellInside(gt, DpCdfSampler::kCellMargin * float(t.nv)));
      near_border |= std::uint64_t(~_mm256_movemask_ps(inside) & 0xff) << (8 * j);
    }
  }
  return near_border;
}

// pdfQuery + pdfImpl for wi = (a0, a1, a2); lanes outside the domain get 0.
template <bool kHalf>
BTF_AVX2 void pdfLanes(const Tables& t, Lanes& l) {
  constexpr int V = kVectors;
  __m256 oz[V], pdf[V];
  __m256i bin[V];
  SquareLanes sq[V];
  for (int j = 0; j < V; ++j) oz[j] = _mm256_load_ps(l.oz + 8 * j);
  thetaBins(t, oz, bin);
  for (int j = 0; j < V; ++j) {
    _mm256_store_si256(reinterpret_cast<__m256i*>(l.bin + 8 * j), bin[j]);
    const Vec3 wo = loadVec3(l.ox + 8 * j, l.oy + 8 * j, l.oz + 8 * j);
    const Rotation rot = binRotation(wo.x, wo.y);
    const Vec3 wi_bin = rot.toBinFrame(loadVec3(l.a0 + 8 * j, l.a1 + 8 * j, l.a2 + 8 * j));
    if constexpr (kHalf)
      sq[j] = halfToSquare(wi_bin, rot.toBinFrame(wo));
    else
      sq[j] = incidentToSquare(wi_bin);
  }
  pdfOfSquare<kHalf>(t, bin, sq, pdf);
  for (int j = 0; j < V; ++j) _mm256_store_ps(l.pdf + 8 * j, pdf[j]);
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

struct DpCdfSampler::LaneTables : dp_cdf_lanes::Tables {};

DpCdfSampler::LaneTables DpCdfSampler::laneTables() const {
  const ThetaBinTable theta = thetaBinTable();
  return {{cdf16_.data(), byte_nodes_ ? nullptr : nodes16_.data(), byte_nodes_ ? nodes8_.data() : nullptr,
           starts_.data(), theta.edges, theta.guide, theta.last_cell, theta.edge_count, nu_, nv_,
           full_search_steps_, pdf_scale_}};
}

bool DpCdfSampler::vectorized() const {
  return narrow_ && !isAnisotropic() && cpuHasAvx2() &&
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
  const bool half = parameterization() == Parameterization::Half;
  forEachBlock(wo.size(), l, load, [&] { return half ? sampleLanes<true>(t, l) : sampleLanes<false>(t, l); }, store);
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
  const bool half = parameterization() == Parameterization::Half;
  forEachBlock(
      wo.size(), l, load,
      [&] {
        half ? pdfLanes<true>(t, l) : pdfLanes<false>(t, l);
        return std::uint64_t(0);
      },
      store);
}

}  // namespace btf
