#include "btf/io/bonn_btf.h"

#include <Eigen/Core>
#include <Imath/half.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <mutex>

#include "bonn_btf_format.h"
#include "btf/core/error.h"
#include "btf/core/value_limits.h"

namespace btf {
namespace fs = std::filesystem;
namespace {

using RowMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Sequential reads of a Bonn file that name the section they are in when the file ends early.
class SectionReader {
 public:
  explicit SectionReader(const fs::path& path) : path_(path), in_(path, std::ios::binary) {
    if (!in_) throw FileError(path, "cannot be opened for reading");
    std::error_code ec;
    size_ = fs::file_size(path, ec);
    if (ec) throw FileError(path, "cannot read its size: " + ec.message());
  }
  void section(std::string name) { section_ = std::move(name); }
  const std::string& sectionName() const { return section_; }
  std::uint64_t position() const { return position_; }
  std::uint64_t size() const { return size_; }
  const fs::path& path() const { return path_; }

  [[noreturn]] void fail(const std::string& problem) const { throw FileError(path_, "the " + section_ + " " + problem); }

  void bytes(void* out, std::uint64_t n) {
    if (n > size_ - position_)
      fail("is truncated: it needs " + std::to_string(n) + " more bytes at byte " + std::to_string(position_) +
           ", the file has " + std::to_string(size_));
    in_.read(static_cast<char*>(out), std::streamsize(n));
    if (!in_) fail("could not be read at byte " + std::to_string(position_));
    position_ += n;
  }
  template <class T>
  T value() {
    T v;
    bytes(&v, sizeof v);  // little-endian, as the files are and as the hosts libbtf builds for
    return v;
  }
  std::string text(std::uint64_t n) {
    std::string s(std::size_t(n), '\0');
    bytes(s.data(), n);
    const std::size_t end = s.find('\0');
    if (end != std::string::npos) s.resize(end);
    return s;
  }
  void skip(std::uint64_t n) {
    if (n > size_ - position_)
      fail("is truncated: it needs " + std::to_string(n) + " more bytes at byte " + std::to_string(position_) +
           ", the file has " + std::to_string(size_));
    position_ += n;
    in_.seekg(std::streamoff(position_));
  }
  void seek(std::uint64_t at) {
    position_ = at;
    in_.seekg(std::streamoff(at));
  }

 private:
  fs::path path_;
  std::ifstream in_;
  std::uint64_t size_ = 0, position_ = 0;
  std::string section_ = "signature";
};

// A count read from the file, bounded so that a corrupt value cannot ask for absurd memory before
// the size checks against the file see it.
std::uint32_t boundedCount(SectionReader& in, const char* what, std::uint32_t max) {
  const std::uint32_t n = in.value<std::uint32_t>();
  if (n > max) in.fail("declares " + std::to_string(n) + " " + what + ", more than " + std::to_string(max));
  return n;
}

constexpr std::uint32_t kMaxTextLength = 64u << 20;  // an XML block or a channel name
constexpr std::uint32_t kMaxComponents = 1u << 20;

void readMetaData(SectionReader& in, BonnBtfHeader& h) {
  in.section("meta-data block");
  const std::uint64_t start = in.position();
  const std::uint32_t size = in.value<std::uint32_t>();
  h.meta_version = in.value<std::uint32_t>();
  h.measurement_setup = in.text(bonn::kMetaStringBytes);
  h.image_sensor = in.text(bonn::kMetaStringBytes);
  h.light_source = in.text(bonn::kMetaStringBytes);
  h.pixels_per_mm = in.value<float>();
  for (float& s : h.rgb_scale) s = in.value<float>();
  if (h.meta_version > 1) h.cosine_flag = in.value<std::uint32_t>() != 0;
  if (h.meta_version > 2) h.xml = in.text(boundedCount(in, "bytes of XML", kMaxTextLength));
  h.channel_names = {"R", "G", "B"};
  if (h.meta_version > 3) {
    const std::uint32_t channels = boundedCount(in, "channels", 4096);
    h.channel_names.clear();
    for (std::uint32_t c = 0; c < channels; ++c) h.channel_names.push_back(in.text(boundedCount(in, "bytes of a channel name", 4096)));
  }
  if (in.position() - start != size)
    in.fail("declares " + std::to_string(size) + " bytes, but its fields (version " + std::to_string(h.meta_version) +
            ") take " + std::to_string(in.position() - start));
  if (h.channel_names.size() != 3)
    in.fail("declares " + std::to_string(h.channel_names.size()) +
            " channels; libbtf reads RGB BTFs (3 channels), not multispectral ones");
}

constexpr float kDegreesPerRadian = 57.29577951308232f;

BtfAngles anglesOf(SectionReader& in) {
  const float theta = in.value<float>(), phi = in.value<float>();
  float theta_deg = theta * kDegreesPerRadian;
  // A pole computed from a calibrated position may come out a rounding below zero.
  if (theta_deg < 0.0f && theta_deg > -1e-3f) theta_deg = 0.0f;
  return {theta_deg, phi * kDegreesPerRadian};
}

void readSampling(SectionReader& in, BonnBtfHeader& h) {
  in.section("bidirectional sampling block");
  const std::uint32_t views = boundedCount(in, "views", BtfDirectionSet::kMaxDirections);
  if (views == 0) in.fail("declares no views");
  std::vector<BtfAngles> view_angles;
  std::vector<std::vector<BtfAngles>> light_angles;
  for (std::uint32_t v = 0; v < views; ++v) {
    view_angles.push_back(anglesOf(in));
    const std::uint32_t lights = boundedCount(in, "lights for a view", BtfDirectionSet::kMaxDirections);
    if (lights == 0) in.fail("declares no lights for view " + std::to_string(v));
    std::vector<BtfAngles> list;
    list.reserve(lights);
    for (std::uint32_t l = 0; l < lights; ++l) list.push_back(anglesOf(in));
    light_angles.push_back(std::move(list));
  }
  try {
    h.directions = BtfDirectionSet::known(
        std::make_shared<const BtfDirectionSet>("", std::move(view_angles), std::move(light_angles)));
  } catch (const FileError&) {
    throw;
  } catch (const Error& e) {
    in.fail(std::string("is invalid: ") + e.what());
  }
}

// Width and height, each 1 .. 65536 (far beyond any measured BTF; bounds a corrupt file).
void readTexelSize(SectionReader& in, BonnBtfHeader& h) {
  const std::uint32_t width = in.value<std::uint32_t>(), height = in.value<std::uint32_t>();
  constexpr std::uint32_t kMaxSide = 1u << 16;
  if (width == 0 || height == 0 || width > kMaxSide || height > kMaxSide)
    in.fail("declares " + std::to_string(width) + " x " + std::to_string(height) + " texels (each side must be 1 .. " +
            std::to_string(kMaxSide) + ")");
  h.width = int(width);
  h.height = int(height);
}

void readSizeAndRotations(SectionReader& in, BonnBtfHeader& h) {
  in.section("size block");
  readTexelSize(in, h);
  if (h.rotations_flag) {
    in.section("rotations block");
    h.rotation_count = in.value<std::uint32_t>();
    in.skip(std::uint64_t(h.rotation_count) * 9 * sizeof(float));
  }
}

BonnBtfFactor readFactorDims(SectionReader& in, int scalar_bytes) {
  BonnBtfFactor f;
  f.scalar_bytes = scalar_bytes;
  if (scalar_bytes != 2 && scalar_bytes != 4 && scalar_bytes != 8)
    in.fail("has scalar size " + std::to_string(scalar_bytes) + "; the format stores 2 (half), 4 (float) or 8 (double)");
  return f;
}

// Skips a factorisation's data after checking that the file holds it.
void skipFactorData(SectionReader& in, BonnBtfFactor& f, std::uint64_t leading_scalars) {
  f.offset = in.position();
  in.skip(f.bytes() + leading_scalars * std::uint64_t(f.scalar_bytes));
}

void checkComponents(SectionReader& in, std::uint32_t components) {
  if (components == 0 || components > kMaxComponents)
    in.fail("declares " + std::to_string(components) + " components (1 .. " + std::to_string(kMaxComponents) + ")");
}

std::string dims(std::uint64_t a, std::uint64_t b) { return std::to_string(a) + " x " + std::to_string(b); }

void readDfmf(SectionReader& in, BonnBtfHeader& h) {
  in.section("DFMF colour block");
  h.max_components = in.value<std::uint32_t>();
  h.color_model = in.value<std::int32_t>();
  for (float& m : h.color_mean) m = in.value<float>();
  for (float& m : h.color_transform) m = in.value<float>();
  if (bonn::spectralColorModel(h.color_model))
    in.fail("names colour model " + std::to_string(h.color_model) + " (multispectral); libbtf reads RGB BTFs");
  if (!bonn::knownColorModel(h.color_model))
    in.fail("names colour model " + std::to_string(h.color_model) +
            ", which the format does not define (0 to 4 and 9 to 12 are RGB models)");
  const std::uint64_t pairs = h.directions->pairCount(), texels = std::uint64_t(h.width) * std::uint64_t(h.height);
  for (std::size_t c = 0; c < h.channel_names.size(); ++c) {
    in.section("DFMF channel " + std::to_string(c) + " factors");
    BonnBtfFactor f = readFactorDims(in, in.value<std::uint8_t>());
    f.components = in.value<std::uint32_t>();
    f.rows = in.value<std::uint32_t>();
    f.columns = in.value<std::uint32_t>();
    checkComponents(in, f.components);
    const bool pairs_by_texels = f.rows == pairs && f.columns == texels;
    const bool texels_by_pairs = f.rows == texels && f.columns == pairs;
    if (!pairs_by_texels && !texels_by_pairs)
      in.fail("are " + dims(f.rows, f.columns) + ", but the sampling block has " + std::to_string(pairs) +
              " (view, light) pairs and the size block " + std::to_string(texels) + " texels");
    skipFactorData(in, f, f.components);
    h.factors.push_back(f);
  }
}

void readFmf(SectionReader& in, BonnBtfHeader& h, bool extended) {
  in.section("FMF header");
  if (extended) {
    h.fmf_header_version = in.value<std::uint8_t>();
    if (h.fmf_header_version >= 3)
      in.fail("has version " + std::to_string(h.fmf_header_version) + "; the format defines versions 0 to 2");
    if (h.fmf_header_version >= 1) h.dynamic_range_reduction = in.value<std::uint32_t>();
    if (h.fmf_header_version >= 2) {
      h.height_map_width = in.value<std::uint32_t>();
      h.height_map_height = in.value<std::uint32_t>();
      in.section("FMF height map");
      in.skip(std::uint64_t(h.height_map_width) * h.height_map_height * 2);
    }
  }
  in.section("FMF factors");
  h.max_components = in.value<std::uint32_t>();
  BonnBtfFactor f = readFactorDims(in, in.value<std::uint8_t>());
  f.components = in.value<std::uint32_t>();
  f.rows = in.value<std::uint32_t>();
  f.columns = in.value<std::uint32_t>();
  checkComponents(in, f.components);
  const std::uint64_t pairs = h.directions->pairCount(), texels = std::uint64_t(h.width) * std::uint64_t(h.height);
  const std::uint64_t channels = h.channel_names.size();
  if (!(f.rows == channels * pairs && f.columns == texels) && !(f.rows == channels * texels && f.columns == pairs))
    in.fail("are " + dims(f.rows, f.columns) + ", but the sampling block has " + std::to_string(pairs) +
            " (view, light) pairs and the size block " + std::to_string(texels) + " texels (" + std::to_string(channels) +
            " channels on one side)");
  skipFactorData(in, f, f.components);
  h.factors.push_back(f);
}

// The view slots of a PVF file: one factorisation per view, its (channel, light) vectors over the
// texels or the reverse.
void readPvfSlots(SectionReader& in, BonnBtfHeader& h, std::uint32_t slots) {
  const BtfDirectionSet& set = *h.directions;
  if (slots != std::uint32_t(set.viewCount()))
    in.fail("declares " + std::to_string(slots) + " view slots, but the sampling block has " +
            std::to_string(set.viewCount()) + " views");
  const std::uint64_t texels = std::uint64_t(h.width) * std::uint64_t(h.height), channels = h.channel_names.size();
  for (std::uint32_t v = 0; v < slots; ++v) {
    in.section("PVF view slot " + std::to_string(v));
    BonnBtfFactor f = readFactorDims(in, in.value<std::uint8_t>());
    f.components = in.value<std::uint32_t>();
    const std::uint32_t weights = in.value<std::uint32_t>(), dimension = in.value<std::uint32_t>();
    checkComponents(in, f.components);
    f.rows = dimension;
    f.columns = weights;
    const std::uint64_t lights = std::uint64_t(set.lightCount(int(v)));
    if (!(dimension == channels * lights && weights == texels) && !(dimension == channels * texels && weights == lights))
      in.fail("is " + dims(dimension, weights) + " (dimension x weights), but the view has " + std::to_string(lights) +
              " lights and the BTF " + std::to_string(texels) + " texels");
    // Eigenvalues and the mean come before the two matrices.
    f.offset = in.position();
    in.skip((std::uint64_t(f.components) + dimension) * std::uint64_t(f.scalar_bytes) + f.bytes());
    h.factors.push_back(f);
  }
}

void readPvf(SectionReader& in, BonnBtfHeader& h) {
  in.section("PVF header");
  const std::uint64_t after_signature = in.position();
  if (in.value<std::int32_t>() == bonn::kLegacyPvfMagic) {
    // The legacy layout: components, size and slot count, then the sampling; no meta data.
    h.legacy_pvf = true;
    h.channel_names = {"R", "G", "B"};
    h.max_components = in.value<std::uint32_t>();
    readTexelSize(in, h);
    const std::uint32_t slots = in.value<std::uint32_t>();
    readSampling(in, h);
    readPvfSlots(in, h, slots);
    return;
  }
  in.seek(after_signature);
  readMetaData(in, h);
  readSampling(in, h);
  readSizeAndRotations(in, h);
  in.section("PVF header");
  h.max_components = in.value<std::uint32_t>();
  readPvfSlots(in, h, in.value<std::uint32_t>());
}

}  // namespace

std::string bonnBtfLayoutName(BonnBtfLayout layout) {
  switch (layout) {
    case BonnBtfLayout::Dfmf: return "DFMF";
    case BonnBtfLayout::Fmf: return "FMF";
    case BonnBtfLayout::Pvf: return "PVF";
  }
  return "?";
}

std::uint64_t BonnBtfFactor::bytes() const {
  return (std::uint64_t(rows) + std::uint64_t(columns)) * std::uint64_t(components) * std::uint64_t(scalar_bytes);
}

std::string bonnColorModelName(int model) {
  switch (model) {
    case 0: return "RGB";
    case 1: return "YUV";
    case 2: return "CIE Lab";
    case 3: return "PCA colour transform";
    case 4: return "YCoCg";
    case 5: return "spectral";
    case 6: return "spectral (linear)";
    case 9: return "log-Y, U, V";
    case 10: return "log-Y, log-U, log-V";
    case 11: return "log-Y, U/Y, V/Y";
    case 12: return "log-RGB";
    default: return "unknown";
  }
}

bool isBonnBtfSignature(const unsigned char* head, std::size_t size) {
  for (const bonn::Signature& s : bonn::kSignatures)
    if (size >= s.text.size() && std::memcmp(head, s.text.data(), s.text.size()) == 0) return true;
  return false;
}

bool isBonnBtfFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  unsigned char head[bonn::kLongestSignature] = {};
  in.read(reinterpret_cast<char*>(head), sizeof head);
  return isBonnBtfSignature(head, std::size_t(in.gcount()));
}

BonnBtfHeader readBonnBtfHeader(const fs::path& path) {
  SectionReader in(path);
  BonnBtfHeader h;
  h.file_bytes = in.size();
  unsigned char head[bonn::kLongestSignature] = {};
  const std::size_t head_size = std::size_t(std::min<std::uint64_t>(in.size(), sizeof head));
  in.bytes(head, head_size);
  const bonn::Signature* match = nullptr;
  for (const bonn::Signature& s : bonn::kSignatures)
    if (head_size >= s.text.size() && std::memcmp(head, s.text.data(), s.text.size()) == 0) {
      match = &s;
      break;
    }
  if (!match) {
    std::string shown;
    for (std::size_t i = 0; i < head_size; ++i) shown += std::isprint(head[i]) ? char(head[i]) : '?';
    throw FileError(path, "does not start with a Bonn BTF signature (!DFMF08FCR, !FMF12FCER, !FMF06FC[R], "
                          "!PVF06FC[R]); it starts with \"" + shown + "\"");
  }
  h.signature = std::string(match->text);
  h.layout = match->layout;
  h.rotations_flag = h.signature.back() == 'R';
  in.seek(match->text.size());
  if (h.layout == BonnBtfLayout::Pvf) {
    readPvf(in, h);
  } else {
    readMetaData(in, h);
    readSampling(in, h);
    readSizeAndRotations(in, h);
    if (h.layout == BonnBtfLayout::Dfmf) readDfmf(in, h);
    else readFmf(in, h, match->extended_header);
  }
  in.section("end of the file");
  if (in.position() != in.size())
    in.fail("is not where the factors end: " + std::to_string(in.size() - in.position()) +
            " bytes follow the last factor (a file of another layout, or a corrupt one)");
  return h;
}

// --- decoding --------------------------------------------------------------------------------

namespace bonn {
// A stored factorisation as float: U (rows x k) and S.V (columns x k), row-major; for PVF also the
// mean (rows). Checked finite on reading.
struct FactorData {
  std::vector<float> u, sv, mean;
};
}  // namespace bonn

namespace {
using bonn::FactorData;

void convertScalars(const std::vector<unsigned char>& raw, int scalar_bytes, std::vector<float>& out) {
  const std::size_t n = raw.size() / std::size_t(scalar_bytes);
  out.resize(n);
  if (scalar_bytes == 2) {
    for (std::size_t i = 0; i < n; ++i) {
      Imath::half h;
      std::uint16_t bits;
      std::memcpy(&bits, raw.data() + 2 * i, 2);
      h.setBits(bits);
      out[i] = float(h);
    }
  } else if (scalar_bytes == 4) {
    std::memcpy(out.data(), raw.data(), n * 4);
  } else {
    for (std::size_t i = 0; i < n; ++i) {
      double d;
      std::memcpy(&d, raw.data() + 8 * i, 8);
      out[i] = float(d);
    }
  }
}

void readScalars(SectionReader& in, std::uint64_t count, int scalar_bytes, std::vector<float>& out, const char* what) {
  std::vector<unsigned char> raw(std::size_t(count) * std::size_t(scalar_bytes));
  in.bytes(raw.data(), raw.size());
  convertScalars(raw, scalar_bytes, out);
  for (std::size_t i = 0; i < out.size(); ++i)
    if (!std::isfinite(out[i]))
      in.fail("holds a " + std::string(std::isnan(out[i]) ? "NaN" : "non-finite (or beyond float range)") + " value in " +
              what + " (element " + std::to_string(i) + ")");
}

FactorData readFactor(SectionReader& in, const BonnBtfFactor& f, bool pvf_mean) {
  FactorData d;
  in.seek(f.offset);
  in.skip(std::uint64_t(f.components) * std::uint64_t(f.scalar_bytes));  // singular values / eigenvalues: unused
  if (pvf_mean) readScalars(in, f.rows, f.scalar_bytes, d.mean, "the mean");
  readScalars(in, std::uint64_t(f.rows) * f.components, f.scalar_bytes, d.u, pvf_mean ? "the components" : "U");
  readScalars(in, std::uint64_t(f.columns) * f.components, f.scalar_bytes, d.sv, pvf_mean ? "the weights" : "S.V");
  return d;
}

// out (m x n, row-major) = left rows [left_begin, left_begin + m) x right rows [right_begin,
// right_begin + n) transposed; both row-major with k columns.
void multiplyRows(const std::vector<float>& left, std::size_t left_begin, std::size_t m, const std::vector<float>& right,
                  std::size_t right_begin, std::size_t n, std::size_t k, float* out) {
  const Eigen::Map<const RowMatrix> a(left.data() + left_begin * k, Eigen::Index(m), Eigen::Index(k));
  const Eigen::Map<const RowMatrix> b(right.data() + right_begin * k, Eigen::Index(n), Eigen::Index(k));
  Eigen::Map<RowMatrix> c(out, Eigen::Index(m), Eigen::Index(n));
  c.noalias() = a * b.transpose();
}

// The texels of one decoding task: a fixed size, so that the work (and every float of it) is the
// same whatever the thread count.
constexpr std::size_t kTexelChunk = 2048;

}  // namespace

namespace bonn {
// Stored values -> linear RGB (btflib's undecorrelate, restore_dynamic_range, cosine removal).
struct ColorDecoder {
  int model = 0;
  bool log_range = false;
  std::array<float, 3> mean{};
  std::array<float, 9> transform{};

  Rgb operator()(float a, float b, float c) const {
    constexpr float eps = bonn::kLogEpsilon;
    Rgb rgb;
    switch (model) {
      case 0: rgb = Rgb(a, b, c); break;
      case 1: rgb = bonn::yuvToRgb(a, b, c); break;
      case 2: rgb = labToRgb(a, b, c); break;
      case 3:
        rgb = Rgb(a * transform[0] + b * transform[3] + c * transform[6] + mean[0],
                  a * transform[1] + b * transform[4] + c * transform[7] + mean[1],
                  a * transform[2] + b * transform[5] + c * transform[8] + mean[2]);
        break;
      case 4: rgb = Rgb(a + b - c, a + c, a - b - c); break;
      case 9: rgb = bonn::yuvToRgb(std::exp(a) - eps, b, c); break;
      case 10: {
        // btflib's sign(x) .* exp(|x| + log(eps)): 0 stays 0.
        const auto expand = [&](float x) { return x == 0.0f ? 0.0f : std::copysign(std::exp(std::abs(x)) * eps, x); };
        rgb = bonn::yuvToRgb(std::exp(a) - eps, expand(b), expand(c));
        break;
      }
      case 11: {
        const float y = std::exp(a) - eps;
        rgb = bonn::yuvToRgb(y, b * (y + eps), c * (y + eps));
        break;
      }
      case 12: rgb = Rgb(std::exp(a) - eps, std::exp(b) - eps, std::exp(c) - eps); break;
      default: rgb = Rgb(a, b, c);
    }
    if (log_range) rgb = Rgb(std::exp(rgb.r) - eps, std::exp(rgb.g) - eps, std::exp(rgb.b) - eps);
    return rgb;
  }

  // CIE Lab (D65 white, L in 0..100) -> linear Rec.709.
  static Rgb labToRgb(float l, float a, float b) {
    const auto finv = [](float t) { return t > 6.0f / 29.0f ? t * t * t : 3.0f * (6.0f / 29.0f) * (6.0f / 29.0f) * (t - 4.0f / 29.0f); };
    const float fy = (l + 16.0f) / 116.0f, fx = fy + a / 500.0f, fz = fy - b / 200.0f;
    return xyzToLinearRec709(Rgb(0.95047f * finv(fx), finv(fy), 1.08883f * finv(fz)));
  }
};
}  // namespace bonn

namespace {
using bonn::ColorDecoder;

}  // namespace

namespace {
ColorDecoder decoderOf(const BonnBtfHeader& h) {
  ColorDecoder decode;
  decode.model = h.layout == BonnBtfLayout::Dfmf ? h.color_model : 0;
  decode.log_range = h.layout == BonnBtfLayout::Fmf && h.dynamic_range_reduction != 0;
  decode.mean = h.color_mean;
  decode.transform = h.color_transform;
  return decode;
}

}  // namespace

struct BonnBtf::Cache {
  ColorDecoder decode;  // the header's colour model, built once
  std::once_flag once;
  std::vector<FactorData> factors;  // DFMF: per channel; FMF: one
  std::vector<std::size_t> view_pair_offset;
  // PVF view slots read by value(), each once.
  std::unique_ptr<std::once_flag[]> slot_once;
  std::vector<FactorData> slots;

  // DFMF and FMF factors, read on first use.
  const std::vector<FactorData>& matrixFactors(const fs::path& path, const BonnBtfHeader& h) {
    std::call_once(once, [&] {
      SectionReader in(path);
      for (std::size_t i = 0; i < h.factors.size(); ++i) {
        in.section(h.layout == BonnBtfLayout::Dfmf ? "DFMF channel " + std::to_string(i) + " factors" : "FMF factors");
        factors.push_back(readFactor(in, h.factors[i], false));
      }
    });
    return factors;
  }
  const FactorData& slot(const fs::path& path, const BonnBtfHeader& h, int view) {
    std::call_once(slot_once[std::size_t(view)], [&] {
      SectionReader in(path);
      in.section("PVF view slot " + std::to_string(view));
      slots[std::size_t(view)] = readFactor(in, h.factors[std::size_t(view)], true);
    });
    return slots[std::size_t(view)];
  }
};

namespace {

float rowDot(const float* a, const float* b, std::size_t k) {
  float sum = 0;
  for (std::size_t i = 0; i < k; ++i) sum += a[i] * b[i];
  return sum;
}

}  // namespace

BonnBtf BonnBtf::open(const fs::path& path) {
  BonnBtf btf;
  btf.path_ = path;
  btf.header_ = std::make_shared<const BonnBtfHeader>(readBonnBtfHeader(path));
  btf.views_ = BtfViewSet::all(btf.header_->directions);
  btf.cache_ = std::make_shared<Cache>();
  btf.cache_->decode = decoderOf(*btf.header_);
  if (btf.header_->layout == BonnBtfLayout::Pvf) {
    btf.cache_->slot_once = std::make_unique<std::once_flag[]>(btf.header_->factors.size());
    btf.cache_->slots.resize(btf.header_->factors.size());
  }
  std::size_t offset = 0;
  for (int v = 0; v < btf.header_->directions->viewCount(); ++v) {
    btf.cache_->view_pair_offset.push_back(offset);
    offset += std::size_t(btf.header_->directions->lightCount(v));
  }
  return btf;
}

std::string BonnBtf::name() const { return path_.filename().string(); }

void BonnBtf::loadView(int view, std::vector<Rgb>& out) const {
  views_.require(view, path_.string());
  const BonnBtfHeader& h = *header_;
  const BtfDirectionSet& set = *h.directions;
  const std::size_t texels = texelCount(), lights = std::size_t(set.lightCount(view)), channels = 3;
  const std::size_t pair0 = cache_->view_pair_offset[std::size_t(view)];

  std::vector<FactorData> slot;  // PVF: this view's factors
  const std::vector<FactorData>* factors = &slot;
  if (h.layout == BonnBtfLayout::Pvf) {
    SectionReader in(path_);
    in.section("PVF view slot " + std::to_string(view));
    slot.push_back(readFactor(in, h.factors[std::size_t(view)], true));
  } else {
    factors = &cache_->matrixFactors(path_, h);
  }

  const ColorDecoder& decode = cache_->decode;
  const std::span<const glm::vec3> light_dirs = set.lightDirections(view);

  out.resize(lights * texels);
  const std::size_t chunks = (texels + kTexelChunk - 1) / kTexelChunk;
  tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t chunk) {
    const std::size_t t0 = chunk * kTexelChunk, n = std::min(kTexelChunk, texels - t0);
    // The stored (decorrelated) channels, vals[(light * n + texel - t0) * 3 + channel].
    std::vector<float> vals(lights * n * channels), products(lights * n * channels);
    if (h.layout == BonnBtfLayout::Dfmf) {
      for (std::size_t c = 0; c < channels; ++c) {
        const BonnBtfFactor& f = h.factors[c];
        const FactorData& d = (*factors)[c];
        if (f.rows == set.pairCount() && f.columns == texels)  // U: pairs, S.V: texels
          multiplyRows(d.u, pair0, lights, d.sv, t0, n, f.components, products.data());
        else
          multiplyRows(d.sv, pair0, lights, d.u, t0, n, f.components, products.data());
        for (std::size_t i = 0; i < lights * n; ++i) vals[i * channels + c] = products[i];
      }
    } else if (h.layout == BonnBtfLayout::Fmf) {
      const BonnBtfFactor& f = h.factors[0];
      const FactorData& d = (*factors)[0];
      if (f.columns == texels) {  // U: (pair, channel) rows, channel fastest; S.V: texels
        multiplyRows(d.u, pair0 * channels, lights * channels, d.sv, t0, n, f.components, products.data());
        for (std::size_t l = 0; l < lights; ++l)
          for (std::size_t c = 0; c < channels; ++c)
            for (std::size_t t = 0; t < n; ++t) vals[(l * n + t) * channels + c] = products[(l * channels + c) * n + t];
      } else {  // U: (texel, channel) rows, channel fastest; S.V: pairs
        multiplyRows(d.sv, pair0, lights, d.u, t0 * channels, n * channels, f.components, vals.data());
      }
    } else {
      const BonnBtfFactor& f = h.factors[std::size_t(view)];
      const FactorData& d = slot[0];
      if (f.columns == texels) {  // components: (light, channel) rows; weights: texels
        multiplyRows(d.u, 0, lights * channels, d.sv, t0, n, f.components, products.data());
        for (std::size_t l = 0; l < lights; ++l)
          for (std::size_t c = 0; c < channels; ++c)
            for (std::size_t t = 0; t < n; ++t)
              vals[(l * n + t) * channels + c] = products[(l * channels + c) * n + t] + d.mean[l * channels + c];
      } else {  // components: (texel, channel) rows; weights: lights
        multiplyRows(d.sv, 0, lights, d.u, t0 * channels, n * channels, f.components, vals.data());
        for (std::size_t l = 0; l < lights; ++l)
          for (std::size_t i = 0; i < n * channels; ++i) vals[l * n * channels + i] += d.mean[t0 * channels + i];
      }
    }
    for (std::size_t l = 0; l < lights; ++l) {
      const float inv_cos = h.cosine_flag ? 1.0f / light_dirs[l].z : 1.0f;
      for (std::size_t t = 0; t < n; ++t) {
        const float* x = &vals[(l * n + t) * channels];
        Rgb v = decode(x[0], x[1], x[2]);
        v = Rgb(std::max(v.r * inv_cos, 0.0f), std::max(v.g * inv_cos, 0.0f), std::max(v.b * inv_cos, 0.0f));
        out[l * texels + t0 + t] = v;
      }
    }
  });
  // What libbtf loads it may write (core/value_limits.h): a value beyond the limit (an overflow of
  // the exponential of a log colour model, or wild factors) is the file's error.
  for (std::size_t i = 0; i < out.size(); ++i)
    if (!(out[i].r <= kMaxReflectance) || !(out[i].g <= kMaxReflectance) || !(out[i].b <= kMaxReflectance))
      throw FileError(path_, "view " + std::to_string(view) + " (" + set.describeView(view) + "), light " +
                                 std::to_string(i / texels) + ", texel " + std::to_string(i % texels) +
                                 " decodes to a value that is not finite or beyond 1e10 (colour model " +
                                 std::to_string(decode.model) + " on the stored factors)");
}

std::vector<BonnBtf::ChannelFactors> BonnBtf::dfmfFactors() const {
  const BonnBtfHeader& h = *header_;
  if (h.layout != BonnBtfLayout::Dfmf)
    throw FileError(path_, "is a Bonn " + bonnBtfLayoutName(h.layout) + " file; only DFMF stores one factorisation per channel");
  const std::vector<FactorData>& factors = cache_->matrixFactors(path_, h);
  std::vector<ChannelFactors> out;
  for (std::size_t c = 0; c < factors.size(); ++c) {
    const BonnBtfFactor& f = h.factors[c];
    const bool pairs_by_texels = f.rows == h.directions->pairCount() && f.columns == texelCount();
    ChannelFactors cf;
    cf.components = f.components;
    cf.pair_side = pairs_by_texels ? factors[c].u : factors[c].sv;
    cf.texel_side = pairs_by_texels ? factors[c].sv : factors[c].u;
    out.push_back(std::move(cf));
  }
  return out;
}

Rgb BonnBtf::value(int x, int y, int view, int light) const {
  const BonnBtfHeader& h = *header_;
  const std::size_t t = std::size_t(y) * std::size_t(h.width) + std::size_t(x), channels = 3;
  const std::size_t texels = texelCount(), l = std::size_t(light);
  const std::size_t pair = cache_->view_pair_offset[std::size_t(view)] + l;
  float s[3];
  if (h.layout == BonnBtfLayout::Dfmf) {
    const std::vector<FactorData>& factors = cache_->matrixFactors(path_, h);
    for (std::size_t c = 0; c < channels; ++c) {
      const BonnBtfFactor& f = h.factors[c];
      const FactorData& d = factors[c];
      const std::size_t k = f.components;
      s[c] = f.columns == texels && f.rows == h.directions->pairCount() ? rowDot(&d.u[pair * k], &d.sv[t * k], k)
                                                                          : rowDot(&d.sv[pair * k], &d.u[t * k], k);
    }
  } else if (h.layout == BonnBtfLayout::Fmf) {
    const BonnBtfFactor& f = h.factors[0];
    const FactorData& d = cache_->matrixFactors(path_, h)[0];
    const std::size_t k = f.components;
    for (std::size_t c = 0; c < channels; ++c)
      s[c] = f.columns == texels ? rowDot(&d.u[(pair * channels + c) * k], &d.sv[t * k], k)
                                 : rowDot(&d.sv[pair * k], &d.u[(t * channels + c) * k], k);
  } else {
    const BonnBtfFactor& f = h.factors[std::size_t(view)];
    const FactorData& d = cache_->slot(path_, h, view);
    const std::size_t k = f.components;
    for (std::size_t c = 0; c < channels; ++c)
      s[c] = f.columns == texels ? rowDot(&d.u[(l * channels + c) * k], &d.sv[t * k], k) + d.mean[l * channels + c]
                                 : rowDot(&d.sv[l * k], &d.u[(t * channels + c) * k], k) + d.mean[t * channels + c];
  }
  const float inv_cos = h.cosine_flag ? 1.0f / h.directions->lightDirections(view)[l].z : 1.0f;
  const Rgb v = cache_->decode(s[0], s[1], s[2]);
  const Rgb out(std::max(v.r * inv_cos, 0.0f), std::max(v.g * inv_cos, 0.0f), std::max(v.b * inv_cos, 0.0f));
  if (!(out.r <= kMaxReflectance) || !(out.g <= kMaxReflectance) || !(out.b <= kMaxReflectance))
    throw FileError(path_, "view " + std::to_string(view) + ", light " + std::to_string(light) + ", texel (" +
                               std::to_string(x) + ", " + std::to_string(y) +
                               ") decodes to a value that is not finite or beyond 1e10");
  return out;
}

}  // namespace btf
