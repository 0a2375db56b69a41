// A BTF as a Material: eval, sample and pdf straight from any BtfLookup (the in-memory BtfData, a
// VqBtf evaluated from its codebooks, a PCA form), so nothing is decompressed as a whole. A BRDF
// is a one-texel BTF.
//
// On the 81-direction set (and sets indexed as it, whose lights were moved aside), eval
// interpolates between the measured directions within their ring structure, for wi and wo alike: linear in theta between the two enclosing rings (constant beyond the last ring, 75
// degrees, or for wo the last ring of views a partial BTF holds: it needs whole rings from the
// pole, e.g. one view at theta 0, which then serves every wo), linear in phi between the two
// enclosing azimuths of each ring (ring 0 has one);
// so a direction weighs at most 4 measured directions and a pair at most 16. Over the texture,
// bilinear between the 4 nearest texel centres (uv in [0,1)^2 wraps: texel x covers
// [x, x + 1) / width), or the nearest texel. At measured directions and texel centres eval returns
// the data.
//
// sample: twofold binary search on the light slice of the texel nearest uv and the measured view
// nearest wo (theta rounded to a ring, phi to an azimuth of that ring). The sphere of lights is cut
// into cells, one per measured light: ring bands theta in [15 r - 7.5, 15 r + 7.5] degrees (ring 0
// a cap up to 7.5, the last ring down to the horizon), each band cut into equal azimuth cells
// centred on the measured azimuths. With w = luminance x cos(theta_ring) x cell solid angle, a ring
// is chosen from its marginal (sum of w over the ring), then the azimuth from the ring's 1D CDF
// built on the fly (sampling/cdf1d.h), then a uniform point (in solid angle) in the cell. pdf is
// that piecewise-constant density, exactly what sample draws. On a VqBtf the rings come straight
// from the codebook (VqBtf::lightRings: precomputed prefix sums per level-1 entry), so sampling
// decodes nothing.
//
// On any other set (the Bonn dome, scattered or view-dependent lists) the rings are replaced by
// spherical Delaunay triangulations (core/hemisphere_triangulation.h), one of the views held and
// one of the lights of each view: eval weighs the three measured views around wo and, for each,
// the three measured lights around wi by their barycentric weights (at most 9 pairs; exact at
// measured directions; beyond the outermost directions constant along the elevation). sample
// draws from the light slice of the sampling view: of the (up to three) views interpolating wo,
// the one of largest weight (the held view nearest wo, but near the middle of a triangle of
// views). A light l of the slice is chosen with probability f_l W_l / sum (f the luminance, W_l
// the weight of the light triangulation's corners that l is: cos theta x solid angle / 3 of each
// triangle it is a corner of), then one of its triangles by that triangle's share of W_l, then a
// point uniform in the triangle's solid angle: triangle t is drawn with probability cos x solid
// angle x the mean luminance of its three corners / sum, and pdf is that piecewise-constant
// density, the sample's bit for bit (core/hemisphere_triangulation.h). From a VqBtf whose views
// share one light list, the choice of l reads precomputed tables, as the rings do: each level-1
// entry's values weighted by W (the prefix sums of one ring), and with two or three levels each
// level-2 entry's marginal over its rings (VqBtf::weightedRings), so a draw decodes nothing and
// builds no table; otherwise (a BtfData, view-dependent lights) the slice's f_l W_l are summed
// into a CDF, once per texel and view (per-thread cache). sample() interpolates the weight f on
// the draw's own view stencil and light triangle (what eval locates again). Why triangulations,
// not rings or a kernel: they work on any directions, need no bandwidth, and interpolate from
// the fewest measured values.
#pragma once

#include <cstdint>
#include <memory>

#include "btf/compress/vq_btf.h"
#include "btf/core/hemisphere_triangulation.h"
#include "btf/io/btf_data.h"
#include "btf/material/material.h"

namespace btf {

class BtfScatteredDirections;

enum class BtfTexelFilter { Bilinear, Nearest };

class BtfMaterial final : public Material {
 public:
  // Throws btf::Error for a null BTF, or one on the 81-direction set whose views are not whole
  // rings from the pole.
  explicit BtfMaterial(std::shared_ptr<const BtfLookup> btf, BtfTexelFilter filter = BtfTexelFilter::Bilinear,
                       std::string name = "btf");

  Rgb eval(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::optional<BsdfSample> sample(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const override;
  // The direction sample() draws and its pdf, without the eval() of the weight (the sampler's own
  // cost, as BinnedSampler::sampleDirection; for callers that evaluate f themselves, e.g. for MIS).
  struct DirectionSample {
    glm::vec3 wi;
    float pdf;
  };
  std::optional<DirectionSample> sampleDirection(const glm::vec3& wo, glm::vec2 uv, glm::vec2 u) const;
  float pdf(const glm::vec3& wi, const glm::vec3& wo, glm::vec2 uv = {}) const override;
  std::string name() const override { return name_; }
  bool isAnisotropic() const override { return true; }

  const BtfLookup& btf() const { return *btf_; }

 private:
  struct LightTables;
  // The tables of the light slice of a view at the texel nearest uv (cached per thread).
  const LightTables& lightTables(int view, glm::vec2 uv) const;
  // The sum over the triples of weight x value at uv (bilinear or nearest texel).
  Rgb interpolate(const int* views, const int* lights, const float* weights, int count, glm::vec2 uv) const;
  // On other sets: a draw from the slice of the view stencil's sampling view, with the triangle
  // of the light triangulation it lies in.
  struct ScatteredDraw {
    glm::vec3 wi;
    float pdf;
    int triangle;
  };
  std::optional<ScatteredDraw> drawScattered(const HemisphereTriangulation::Stencil& view, glm::vec2 uv, glm::vec2 u) const;
  // On other sets: the density of a draw in triangle t of the slice's light triangulation.
  float scatteredDensity(const LightTables& tables, int t) const;

  std::shared_ptr<const BtfLookup> btf_;
  const VqBtf* vq_;  // btf_ as a VqBtf, for the sampling fast path; else null
  BtfTexelFilter filter_;
  std::string name_;
  int width_, height_;
  int view_rings_;  // rings of views held, from the pole (6 for a full BTF); 0 on other sets
  std::shared_ptr<const BtfScatteredDirections> scattered_;  // on other sets, else null
  // On other sets from a VqBtf whose views share their lights: its entries weighted by the
  // lights' triangle weights (VqBtf::weightedRings), else null.
  std::shared_ptr<const VqBtf::WeightedRings> weighted_rings_;
  std::uint64_t id_;  // for the per-thread cache of the last light slice's tables
};

}  // namespace btf
