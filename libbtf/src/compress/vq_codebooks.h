// VqCodebooks (compress/vq_dataset.h) as the compressor and the dataset steps see it (private to
// src/compress/).
#pragma once

#include <vector>

#include "btf/compress/vq_dataset.h"
#include "vq_impl.h"

namespace btf {

// One group of shared codebooks per ring layout: each group an Impl of which only the layout, the
// views (for the direction set they name), the options and the shared codebooks (l1, chroma, l2_*)
// are set; level-1 rings are stored value by value (no bases).
struct VqCodebooks::Impl {
  VqOptions options;
  std::vector<VqBtf::Impl> groups;
  const VqBtf::Impl* groupOf(const BtfRingLayout& layout) const {
    for (const VqBtf::Impl& g : groups)
      if (g.layout == layout) return &g;
    return nullptr;
  }
};

}  // namespace btf
