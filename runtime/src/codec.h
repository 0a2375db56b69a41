// The interface behind which each payload kind of a runtime file decodes (one file per codec:
// vq_codec.cpp). Material (material.cpp) does the direction and texel interpolation and the
// sampling; a codec gives the stored values and, per light slice, its rings' tables.
#pragma once

#include <cstddef>
#include <memory>
#include <string>

#include "btf_runtime/material.h"
#include "numerics.h"

namespace btfrt {

class Codec {
 public:
  virtual ~Codec() = default;
  int width = 0, height = 0;
  int view_rings = 0;  // rings of views held, from the pole

  virtual Rgb value(int x, int y, int view, int light) const = 0;
  // Sum over k < count of weights[k] * value(x, y, views[k], lights[k]), summed in order.
  virtual Rgb weightedSum(int x, int y, const int* views, const int* lights, const float* weights, int count) const = 0;
  // The light slice (texel, view) as rings: ring r's CDF over its azimuths (ring size + 1 entries)
  // and its luminance total (sum over the ring of the luminance; what the ring marginal weighs by
  // the cell geometry). `storage` (kDirectionCount + kRingCount floats) is the caller's scratch for
  // codecs that build the CDFs; a codec with precomputed tables points into them.
  struct Rings {
    std::array<const float*, detail::kRingCount> cdf;
    std::array<float, detail::kRingCount> luminance;
  };
  virtual void lightRings(int x, int y, int view, Rings& rings, float* storage) const = 0;
};

// The reader of each codec (the file's codec field chooses); throws std::runtime_error.
std::shared_ptr<const Codec> readVqCodec(const unsigned char* data, std::size_t size, const std::string& what);

}  // namespace btfrt
