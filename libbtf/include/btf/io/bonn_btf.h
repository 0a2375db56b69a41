// Bonn University's binary BTF files (the BTF database Bonn: UBO2014, ATRIUM; docs/formats.md):
// one `.btf` file per material, its values stored factorised. Read as described by the group's own
// btflib (MATLAB) and the btf.hh header behind the btf-extractor package; all integers and floats
// little-endian.
//
//   signature      "!DFMF08FCR" (decorrelated full matrix factorisation), "!FMF12FCER" (full
//                  matrix factorisation, extended header), "!FMF06FCR" / "!FMF06FC", "!PVF06FCR" /
//                  "!PVF06FC" (per-view factorisation); a trailing R: rotations are stored
//   meta data      u32 size (bytes of the block, this field included), u32 version, three 80-byte
//                  strings (measurement set-up, image sensor, light source), f32 pixels per mm,
//                  3 f32 RGB scale; version > 1: u32 cosine flag (the data hold f * cos(theta_l));
//                  > 2: u32 length + XML; > 3: u32 channel count, per channel u32 length + name
//   sampling       u32 views; per view f32 theta, f32 phi (radians), u32 lights, lights x (f32
//                  theta, f32 phi)
//   size           u32 width, u32 height (texels)
//   rotations      with R: u32 count, count x 3 x 3 f32
//   DFMF           u32 components, i32 colour model, 3 f32 mean, 3 x 3 f32 transform; per channel:
//                  u8 scalar size (2 half, 4 float, 8 double), u32 components, u32 rows, u32
//                  columns, the singular values S, U (rows x components), S.V (columns x
//                  components), row-major
//   FMF            with E: u8 header version; >= 1: u32 dynamic-range reduction (values are
//                  log(x + 1e-5)); >= 2: u32 width, u32 height, a half-float height map; then u32
//                  components, u8 scalar size, u32 components, u32 rows, u32 columns, S, U, S.V
//   PVF            u32 components, u32 view slots; per slot: u8 scalar size, u32 components,
//                  u32 weights, u32 dimension, eigenvalues, mean (dimension), components
//                  (dimension x components), weights (weights x components). The legacy PVF
//                  (i32 301074 after the signature) stores u32 components, width, height, slots
//                  and the sampling, without meta data.
//
// The matrices stand one way or the other: DFMF U holds (view, light) pairs (light fastest) and S.V
// texels (x fastest), or the reverse; FMF the same with channel fastest on the side that is not
// the other's; PVF per view the (channel, light) or (channel, texel) side. The reader accepts both,
// as btflib does. Decoding (btflib's order): the product of the factors, then the colour model
// (0 RGB, 1 YUV, 2 CIE Lab, 3 PCA, 4 YCoCg, 9 log-Y UV, 10 log-Y log-U log-V, 11 log-Y U/Y V/Y,
// 12 log-RGB), then the dynamic-range reduction, then division by cos(theta_l) where the cosine
// flag is set. SVD truncation rings slightly below zero; those values are clamped to 0 (a
// reflectance is not negative). Lab (model 2) is taken as D65 Lab of linear Rec.709 values, so
// that every model decodes to the linear values libbtf works in. Multispectral files (not 3
// channels; models 5 and 6) are refused with a clear error: libbtf is RGB.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "btf/io/btf_data.h"

namespace btf {

enum class BonnBtfLayout { Dfmf, Fmf, Pvf };
std::string bonnBtfLayoutName(BonnBtfLayout layout);  // "DFMF", "FMF", "PVF"
std::string bonnColorModelName(int model);            // "RGB", "log-Y, U/Y, V/Y", ...

// One stored factorisation: a DFMF channel, the FMF, or one PVF view slot. `rows` x `components`
// is U (PVF: the dimension side, the principal components), `columns` x `components` is S.V (PVF:
// the weights).
struct BonnBtfFactor {
  int scalar_bytes = 0;
  std::uint32_t components = 0, rows = 0, columns = 0;
  std::uint64_t offset = 0;  // file offset of the singular values (PVF: eigenvalues)
  std::uint64_t bytes() const;
};

struct BonnBtfHeader {
  std::string signature;
  BonnBtfLayout layout = BonnBtfLayout::Dfmf;
  bool rotations_flag = false, legacy_pvf = false;
  std::uint32_t meta_version = 0;
  std::string measurement_setup, image_sensor, light_source, xml;
  float pixels_per_mm = 0;
  std::array<float, 3> rgb_scale{};
  bool cosine_flag = false;
  std::vector<std::string> channel_names;
  BtfDirectionSetPtr directions;
  int width = 0, height = 0;
  std::uint32_t rotation_count = 0;
  // DFMF
  std::uint32_t max_components = 0;
  std::int32_t color_model = 0;
  std::array<float, 3> color_mean{};
  std::array<float, 9> color_transform{};  // row-major
  // FMF
  int fmf_header_version = 0;
  std::uint32_t dynamic_range_reduction = 0;
  std::uint32_t height_map_width = 0, height_map_height = 0;
  std::vector<BonnBtfFactor> factors;
  std::uint64_t file_bytes = 0;
};

// Reads and checks the headers and every factor's dimensions, seeking over the factor data: what
// `btf info` shows, without decoding. FileError naming the file and the section for a wrong or
// unknown signature, a truncated section, a meta-data size that disagrees with what was read,
// factor dimensions that disagree with the sampling or the size, a scalar size other than 2, 4 or
// 8, an unsupported colour model or channel count, or bytes left over at the end.
BonnBtfHeader readBonnBtfHeader(const std::filesystem::path& path);

// True when the bytes start with one of the signatures above (for the registry's sniffer), or the
// file does.
bool isBonnBtfSignature(const unsigned char* head, std::size_t size);
bool isBonnBtfFile(const std::filesystem::path& path);

// A Bonn .btf file as a BtfSource: loadView decodes one view (every light, every texel) from the
// factors. DFMF and FMF factors are read into memory (as float) on the first decoding; PVF reads
// one view slot per loadView. NaN or infinite factors are a FileError naming the section.
// And as a BtfLookup: value() decodes one entry from the factors (k multiply-adds per channel),
// so that a renderer reads the file without a copy of its values; PVF view slots are then kept
// once read. value() agrees with loadView to float rounding (one is a matrix product, the other a
// dot product), and throws FileError for an entry that decodes to a non-finite value or one
// beyond 1e10.
class BonnBtf final : public BtfSource, public BtfLookup {
 public:
  static BonnBtf open(const std::filesystem::path& path);

  int width() const override { return header_->width; }
  int height() const override { return header_->height; }
  const BtfViewSet& views() const override { return views_; }
  std::string name() const override;
  void loadView(int view, std::vector<Rgb>& out) const override;

  int lookupWidth() const override { return header_->width; }
  int lookupHeight() const override { return header_->height; }
  const BtfViewSet& lookupViews() const override { return views_; }
  Rgb value(int x, int y, int view, int light) const override;

  // A DFMF file's stored factorisations, one per stored channel, as float: the decorrelated
  // channel c at (pair p, texel t) is the dot product of pair_side[p * k ...] and
  // texel_side[t * k ...] (k = components; the singular values folded in as the file stores them),
  // whichever way the file stands. Throws FileError for a layout other than DFMF.
  struct ChannelFactors {
    std::uint32_t components = 0;
    std::vector<float> pair_side, texel_side;  // pairs x k, texels x k, row-major
  };
  std::vector<ChannelFactors> dfmfFactors() const;

  const BonnBtfHeader& header() const { return *header_; }
  const std::filesystem::path& path() const { return path_; }

  struct Cache;  // the factors read so far (bonn_btf.cpp)

 private:
  BonnBtf() = default;

  std::filesystem::path path_;
  std::shared_ptr<const BonnBtfHeader> header_;
  BtfViewSet views_;
  std::shared_ptr<Cache> cache_;
};

// Writing: the DFMF or FMF layout by a truncated SVD of the BTF matrix, in bounded memory (a
// randomised SVD, Halko, Martinsson and Tropp 2011: a few passes over the source, one view at a
// time; memory ~ (texels + pairs) x rank, never the whole matrix). The signatures written are
// !DFMF08FCR and !FMF12FCER, whose trailing R says rotations follow: a count of 0.
struct BonnBtfWriteOptions {
  BonnBtfLayout layout = BonnBtfLayout::Dfmf;
  // Components kept per channel (DFMF) or in all (FMF): the rank, at most, and fewer when
  // `relative_error` is met with fewer (the Frobenius error of the truncation over that of the
  // matrix, in the stored (decorrelated) values).
  int max_components = 64;
  std::optional<double> relative_error;
  int scalar_bytes = 2;  // 2 (half, as the database ships), 4 or 8
  // DFMF: 11 (log-Y, U/Y, V/Y, as UBO2014) or 0 (RGB). FMF: the dynamic-range reduction, 1
  // (log(x + 1e-5)) or 0.
  int color_model = 11;
  int dynamic_range_reduction = 0;
  // Of the randomised SVD: each adds two passes over the source and brings the kept components
  // closer to the optimal ones (one suffices for the fast-decaying spectra of BTFs).
  int power_iterations = 1;
  std::uint64_t seed = 1;      // of its random test matrix: same input and seed, same file
  std::string measurement_setup = "libbtf", image_sensor, light_source;
};

struct BonnBtfWriteReport {
  std::vector<std::uint32_t> components;  // per stored factorisation
  std::vector<double> relative_error;     // of the truncation, per factorisation (stored values)
  std::uint64_t bytes = 0;
};

// Writes `source` (any direction set; every view of the set held) to `path` atomically. Throws
// btf::Error for options out of range, a source missing views, a value that the scalar size cannot
// hold, or negative, NaN or infinite values (naming the view).
BonnBtfWriteReport writeBonnBtf(const BtfSource& source, const std::filesystem::path& path,
                                const BonnBtfWriteOptions& options = {});

// The per-view (PVF) layout, for tests and generated data (btflib writes none): per view, the
// mean and a PCA of the (channel, light) vectors of the texels, `components` kept.
void writeBonnBtfPvf(const BtfSource& source, const std::filesystem::path& path, int components, int scalar_bytes = 4);

}  // namespace btf
