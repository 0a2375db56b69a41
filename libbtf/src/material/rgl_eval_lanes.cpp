// RglBrdf::evalMany in AVX2 lanes: eight wi at a time through evalWith's steps (rgl_brdf.cpp), each
// the scalar code's operation for operation (see core/internal/avx2_lanes.h), so that evalMany returns
// eval's floats bit for bit on every CPU. The warps' lookups are gathers
// (core/internal/bilinear_warp2d_lanes.h); what depends on wo alone (Outgoing) is set up once by the
// caller, as for the scalar loop.
#include <cstddef>

#include "avx2_lanes.h"
#include "bilinear_warp2d_lanes.h"
#include "btf/material/rgl_brdf.h"

namespace btf {
namespace {

using namespace avx2;
using Lanes = BilinearWarp2DLanes;

struct EvalTables {
  const BilinearWarp2D::Fixed& vndf;
  const BilinearWarp2D::Fixed& rgb;
  const BilinearWarp2D::Fixed& ndf;
  bool jacobian;
  float four_sigma;  // 4.0f * sigma(wo)
  float phi_o_turns;
};

// evalWith(wi, wo, o) for wi[0 .. 8).
BTF_AVX2 void evalEight(const EvalTables& t, const glm::vec3& wo, const glm::vec3* wi, Rgb* out) {
  // glm::vec3 is three packed floats: lane k's components sit 3 k floats apart.
  static_assert(sizeof(glm::vec3) == 3 * sizeof(float));
  const __m256i at = _mm256_setr_epi32(0, 3, 6, 9, 12, 15, 18, 21);
  const float* first = &wi[0].x;
  const Vec3 w{_mm256_i32gather_ps(first, at, 4), _mm256_i32gather_ps(first + 1, at, 4),
               _mm256_i32gather_ps(first + 2, at, 4)};

  // halfVectorUnit(normalize(wi + wo)).
  const Vec3 m = normalize({_mm256_add_ps(w.x, _mm256_set1_ps(wo.x)), _mm256_add_ps(w.y, _mm256_set1_ps(wo.y)),
                            _mm256_add_ps(w.z, _mm256_set1_ps(wo.z))});
  const __m256 r = _mm256_sqrt_ps(_mm256_add_ps(_mm256_mul_ps(m.x, m.x), _mm256_mul_ps(m.y, m.y)));
  const __m256 theta_turns = atan2Turns(r, m.z);
  __m256 u_y = _mm256_add_ps(_mm256_sub_ps(atan2Turns(m.y, m.x), _mm256_set1_ps(t.phi_o_turns)), _mm256_set1_ps(0.5f));
  u_y = _mm256_sub_ps(u_y, _mm256_floor_ps(u_y));
  u_y = _mm256_and_ps(u_y, _mm256_cmp_ps(u_y, _mm256_setzero_ps(), _CMP_GE_OQ));  // !(u_y >= 0): 0
  const __m256 u_x = stdMax(_mm256_set1_ps(1e-4f), _mm256_sqrt_ps(_mm256_mul_ps(theta_turns, _mm256_set1_ps(4.0f))));

  // reflectanceTimesCos(vndf.invert(u_m).p, u_m) / wi.z.
  __m256 sx, sy;
  Lanes::invert(t.vndf, u_x, u_y, sx, sy);
  __m256 f[3];
  Lanes::evalAtEveryLastValue(t.rgb, sx, sy, f, 3);
  for (__m256& c : f) c = stdMax(c, _mm256_setzero_ps());
  if (t.jacobian) {
    const __m256 scale = _mm256_div_ps(Lanes::eval(t.ndf, u_x, u_y), _mm256_set1_ps(t.four_sigma));
    for (__m256& c : f) c = _mm256_mul_ps(c, scale);
  }
  const __m256 inv_cos = _mm256_div_ps(_mm256_set1_ps(1.0f), w.z);
  const __m256 below = _mm256_cmp_ps(w.z, _mm256_setzero_ps(), _CMP_LE_OQ);  // wi.z <= 0: {}
  alignas(32) float channel[3][8];
  for (int c = 0; c < 3; ++c) _mm256_store_ps(channel[c], _mm256_andnot_ps(below, _mm256_mul_ps(f[c], inv_cos)));
  for (int k = 0; k < 8; ++k) out[k] = Rgb(channel[0][k], channel[1][k], channel[2][k]);
}

}  // namespace

std::size_t RglBrdf::evalLanes(const glm::vec3& wo, const Outgoing& o, std::span<const glm::vec3> wi,
                               std::span<Rgb> out) const {
  if (!cpuHasAvx2()) return 0;
  const BilinearWarp2D::Fixed ndf = ndf_.fixed();
  if (!Lanes::fits(o.vndf) || !Lanes::fits(o.rgb) || !Lanes::fits(ndf)) return 0;
  const EvalTables tables{o.vndf, o.rgb, ndf, jacobian_, 4.0f * o.sigma, o.phi_o_turns};
  std::size_t k = 0;
  for (; k + 8 <= wi.size(); k += 8) evalEight(tables, wo, wi.data() + k, out.data() + k);
  return k;
}

}  // namespace btf
