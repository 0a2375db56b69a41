// Dropping codebook entries nothing references (private to src/compress/).
#pragma once

#include <span>

#include "vq_impl.h"

namespace btf {

// After the last level of every material is known, removes the level-2, level-1 and chromaticity
// entries of `books` that no material's codes reach (entry 0 of each codebook, the seed, stays),
// renumbering the rest in their order and every index that points at them. Level 3 is why they
// exist: a texel that reuses another texel's level-3 entry leaves its own 81 light slices' level-2
// entries, and the level-1 and chroma entries only they used, behind. `books` may be one of the
// materials (a single-material file). The decoded data does not change.
void pruneVqCodebooks(VqBtf::Impl& books, std::span<VqBtf::Impl* const> materials);

}  // namespace btf
