// Material datasets in one .btfz with shared codebooks, as BTFBASE's database holds its BTFs
// (Havran, Filip and Myszkowski 2010): the level-1 (1D functions over light azimuth),
// chromaticity and level-2 (light slice) codebooks are shared by all materials; each material has
// its own level-3 codebook (its texels over its views) and top stream.
//
// Why shared: the 1D functions and light slices of different materials repeat across materials
// (the same fibres, the same lobes); a shared codebook stores each once. The tolerances and bounds
// of vq_btf.h hold for every material as if it were compressed alone: each reuse is checked
// against that material's own data.
//
// Making one: compressVqDatabase compresses the materials in order into growing shared codebooks
// (material k reuses entries of materials 0..k-1). mergeVqDatabases joins databases (or
// single-material files) compressed apart, e.g. on different machines: it is lossless (every
// material decodes to exactly what it decoded to before) and stores each distinct codebook entry
// once; it does not re-quantize, so entries that are close but not equal stay apart.
//
// Materials on direction sets with other light rings (the 81-direction set and the Bonn dome,
// core/btf_ring_layout.h) cannot share codebooks, which are per ring; a database holds one group
// of shared codebooks per ring layout, and each material belongs to the group of its layout.
// Compression and merges group the materials by layout in order of first appearance.
//
// A material's stats() give its own codebook sizes and the whole database's bytes and ratios.
// In memory, each material is a complete VqBtf (it holds its own decoded copy of the shared
// codebooks), so everything that takes a VqBtf (BtfMaterial, comparisons, decompression) takes a
// material of a database.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "btf/compress/vq_btf.h"

namespace btf {

class VqDatabase {
 public:
  // Materials that share their codebooks (as compressVqDatabase, read and mergeVqDatabases make
  // them), with distinct, non-empty names; throws btf::Error otherwise. One VqBtf alone is a
  // database of one.
  explicit VqDatabase(std::vector<VqBtf> materials);

  std::size_t size() const { return materials_.size(); }
  const std::vector<VqBtf>& materials() const { return materials_; }
  std::vector<std::string> names() const;
  // Throws btf::Error naming the materials there are.
  const VqBtf& material(std::string_view name) const;
  const VqOptions& options() const { return materials_.front().options(); }
  // Entries of the shared codebooks (summed over the ring-layout groups): level 1 (rings of more
  // than one light) and, with levels >= 2, level 2.
  std::vector<std::size_t> sharedEntries() const;
  // Raw size of all materials as 8-bit RGB (the numerator of ratio_u8, docs/design-notes.md#measures).
  double rawBytesU8() const;

  // Bytes the .btfz file holds (as written or read, else as the writer would make it).
  std::uint64_t compressedBytes() const;
  // Compression wall time (the sum of the parts' for a merge; 0 for a database read from a file).
  double seconds() const { return seconds_; }
  void setSeconds(double seconds) { seconds_ = seconds; }

  // .btfz database (atomically written); read() takes a database or a single-material file.
  // Throws FileError.
  void write(const std::filesystem::path& path);
  static VqDatabase read(const std::filesystem::path& path);

 private:
  std::vector<VqBtf> materials_;
  mutable std::uint64_t bytes_ = 0;
  double seconds_ = 0;
};

// Compresses the sources in order into one database (names: one per source, distinct). Throws
// btf::Error for invalid options, data or names (compressVq's checks per material).
VqDatabase compressVqDatabase(std::span<const BtfSource* const> sources, const std::vector<std::string>& names,
                              const VqOptions& options = {});

// The union of databases compressed apart: the same levels and tolerances, distinct material
// names; lossless. Throws btf::Error naming what differs, and the parts by `labels` (e.g. their
// files; by position when empty).
VqDatabase mergeVqDatabases(std::span<const VqDatabase> parts, std::span<const std::string> labels = {});

}  // namespace btf
