// A material dataset compressed in parts, on several processes or machines, into one database of
// shared codebooks (compress/vq_database.h) of the same format as compressVqDatabase makes on one
// machine: map, reduce, re-code, join.
//
// 1. Map: each part (some materials, or a texel tile of one BTF, vqTiles) is compressed alone,
//    compressVqDatabase; only its shared codebooks go on (VqCodebooks::of).
// 2. Reduce: mergeVqCodebooks inserts the parts' shared entries one by one, in part order, into new
//    codebooks (per ring layout: level 1 per ring, chromaticity per ring, level 2), searched with
//    FLANN (compress/codebook.h) in bounded searches, as the compressor's below level 3: an entry
//    within the tolerance of one already inserted maps to it, else it is added (a missed match
//    costs an entry, never accuracy). Level 1 uses the compressor's relative rule at epsilon, chromaticity an
//    absolute L2 distance <= chroma_epsilon (which bounds the compressor's luminance-weighted
//    error for any luminance), level 2 the relative rule on its reconstruction from the merged
//    level-1 entries, with the same merged chromaticity per ring. The merged set is only a
//    starting point: nothing in it is trusted without the check of step 3.
// 3. Re-code: compressVqDatabase with a seed compresses a part again, its shared codebooks starting
//    from the merged ones instead of empty. Every reuse of a merged entry is checked against the
//    part's own data by the compressor's rules, so every material keeps the tolerance and bound
//    it has alone (vq_btf.h); vectors no merged entry fits add entries of their own; merged
//    entries the part does not use are dropped (vq_prune.h).
// 4. Join: mergeVqDatabases of the re-coded parts (lossless). The merged entries the parts use
//    have the same bytes in every part, so the join stores each once; only what a part added is
//    its own. Tiles of one BTF are joined into one material by joinVqTiles.
//
// Everything is a function of the inputs, the options and the partition (the part order): the
// same parts in the same order give the same bytes on any machines and thread counts; another
// partition gives another database of the same bounds.
//
// Between processes the steps pass byte strings (toBytes / fromBytes: .btfz containers), so
// workers need no shared folder; only the inputs must be readable where each part runs.
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "btf/compress/vq_database.h"
#include "btf/io/btf_subset.h"

namespace btf {

// The shared codebooks of a database (level 1, chromaticity, level 2; one group per ring layout),
// without its materials: what the map step passes to the reduce and the reduce to the re-code.
class VqCodebooks {
 public:
  // The shared codebooks of `database` (its options; level1_cut databases are refused: each part
  // learns its own level-1 bases, which merged entries could not share).
  static VqCodebooks of(const VqDatabase& database);

  const VqOptions& options() const;
  std::size_t groupCount() const;
  // Entries summed over the groups, as VqDatabase::sharedEntries counts them.
  std::vector<std::size_t> entries() const;

  // A .btfz container (format "libbtf-vq-codebooks", at a fast zstd level) as bytes, and back; fromBytes throws
  // FileError naming `label` for bytes that are not one.
  std::vector<std::byte> toBytes() const;
  static VqCodebooks fromBytes(std::span<const std::byte> bytes, const std::string& label = "codebooks");

  struct Impl;
  explicit VqCodebooks(std::shared_ptr<const Impl> impl);
  const Impl& impl() const { return *impl_; }

 private:
  std::shared_ptr<const Impl> impl_;
};

// The reduce (above): the parts' codebooks merged within the tolerance, in part order. The parts
// must have the same options (btf::Error naming the part by `labels`, or by position).
VqCodebooks mergeVqCodebooks(std::span<const VqCodebooks> parts, std::span<const std::string> labels = {});

// The re-code (above): compressVqDatabase with shared codebooks that start from `seed` (the group
// of each material's ring layout; layouts the seed lacks start empty). The seed's options must be
// `options` (levels, epsilon, chroma_epsilon, energy_floor; btf::Error otherwise) and level1_cut off.
VqDatabase compressVqDatabase(std::span<const BtfSource* const> sources, const std::vector<std::string>& names,
                              const VqOptions& options, const VqCodebooks& seed);

// A database as the bytes of a .btfz file (the sections of its file, compressed at a fast zstd
// level: bytes between processes, not for storage), and back (throws FileError naming `label`).
std::vector<std::byte> vqDatabaseBytes(const VqDatabase& database);
VqDatabase vqDatabaseFromBytes(std::span<const std::byte> bytes, const std::string& label = "database");

// Tiles of a width x height BTF for `parts` parts: a grid of about equal rectangles, row by row
// (at most width x height of them), every texel in exactly one.
std::vector<BtfRect> vqTiles(int width, int height, int parts);

// One material of `width` x `height` texels, named `name`, from its tiles: `tiles` holds one
// material per rectangle of `rects` (in that order) that share their codebooks (a database made by
// mergeVqDatabases of tiles re-coded from one seed), on the same views. The level-3 codebooks are
// concatenated (a texel reuses level-3 entries of its own tile only: a tiled BTF holds more of
// them than one compressed whole) and the top streams placed by texel: every texel
// decodes exactly as it did in its tile, so each tile's bound holds for its texels, and the
// whole's since the tiles' squared errors add. Throws btf::Error when the rectangles do not
// cover the texels once, or the tiles differ in size, views or codebooks.
VqDatabase joinVqTiles(const VqDatabase& tiles, std::span<const BtfRect> rects, int width, int height,
                       const std::string& name);

}  // namespace btf
