// libbtf runtime: eval, sample and pdf of a compressed BTF inside an engine, with nothing but the
// C++17 standard library (target libbtf::runtime, docs/renderers.md#embedding-the-runtime).
//
// It reads the flat file `btf export --runtime` writes from a .btfz (layout: docs/formats.md#runtime-file-btfrt-from-btf-export---runtime,
// little-endian flat arrays, so a GPU port reads the same bytes) and gives the results of the full
// library's BtfMaterial on the same file, bit for bit (tests/unit/test_runtime.cpp compares every
// call): the same interpolation over texels and measured directions, and the same sampler (ring,
// then azimuth, then a point in the light cell). Today: VQ codebooks (1, 2 or 3 levels) on the
// 81-direction set (views of whole rings from the pole); other direction sets (the Bonn dome) are
// refused when the file is written.
//
// Thread safety: a Material is immutable once opened; every call is const, keeps its scratch on the
// stack (fixed-size arrays) and allocates nothing, so any number of threads may call it at once.
// Build the runtime with -ffp-contract=off (its CMake target does), as the library is: a fused
// multiply-add would round differently from the library's results.
#pragma once

#include <cstddef>
#include <memory>
#include <string>

namespace btfrt {

// Directions in the local shading frame (z the normal), unit length, pointing away from the surface.
struct Vec3 {
  float x = 0, y = 0, z = 0;
};
// Linear RGB.
struct Rgb {
  float r = 0, g = 0, b = 0;
};

enum class TexelFilter { Bilinear, Nearest };

// A sampled incident direction: weight = f * cos(theta_i) / pdf, pdf in solid angle.
struct Sample {
  Vec3 wi;
  Rgb weight;
  float pdf = 0;
};

class Codec;  // one per payload kind (src/vq_codec.cpp for VQ codebooks)

class Material {
 public:
  // Opens a runtime file. Throws std::runtime_error naming the file and the problem (missing,
  // truncated, not a runtime file, an index outside its table, ...).
  static Material open(const std::string& path, TexelFilter filter = TexelFilter::Bilinear);
  // The same from bytes in memory (`what` names them in errors). The bytes are copied.
  static Material fromBytes(const unsigned char* data, std::size_t size, const std::string& what,
                            TexelFilter filter = TexelFilter::Bilinear);

  int width() const { return width_; }
  int height() const { return height_; }
  // The stored sample of texel (x, y), measured view and light (81-direction indices; a view the
  // file holds). Not checked, as VqBtf::value: the caller keeps them in range.
  Rgb value(int x, int y, int view, int light) const;
  // BRDF value f(wi, wo) at texture coordinates (u, v) in [0, 1)^2 (wrapping); 0 below the surface.
  Rgb eval(const Vec3& wi, const Vec3& wo, float u, float v) const;
  // Draws wi for wo at (u, v) from two uniform numbers u1, u2 in [0, 1). Returns false when
  // nothing can be drawn (wo below the surface, a black light slice).
  bool sample(const Vec3& wo, float u, float v, float u1, float u2, Sample& out) const;
  // The density (solid angle) of what sample draws.
  float pdf(const Vec3& wi, const Vec3& wo, float u, float v) const;

 private:
  Material(std::shared_ptr<const Codec> codec, TexelFilter filter);
  bool sampleDirection(const Vec3& wo, float u, float v, float u1, float u2, Vec3& wi, float& pdf) const;
  Rgb interpolate(const int* views, const int* lights, const float* weights, int count, float u, float v) const;

  std::shared_ptr<const Codec> codec_;
  TexelFilter filter_;
  int width_ = 0, height_ = 0;
  int view_rings_ = 0;
};

}  // namespace btfrt
