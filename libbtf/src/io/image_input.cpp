#include "image_input.h"

#include <OpenEXR/ImfHeader.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <map>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "btf/core/error.h"
#include "btf/io/atomic_file.h"
#include "btf/io/image.h"

namespace btf {
namespace fs = std::filesystem;

namespace {

std::atomic<int> g_max_side{ImageSizeLimits{}.max_side};
std::atomic<std::uint64_t> g_max_pixels{ImageSizeLimits{}.max_pixels};
std::mutex g_exr_limits_mutex;
int g_exr_limit_set = -1;  // the side OpenEXR was last given (under the mutex)

// OpenEXR's own limit is process-wide and static; it is (re)applied before each open so that it
// follows setImageSizeLimits. Tiles get the same bound as images.
void applyOpenExrLimit() {
  const int side = g_max_side.load();
  std::lock_guard lock(g_exr_limits_mutex);
  if (g_exr_limit_set == side) return;
  Imf::Header::setMaxImageSize(side, side);
  Imf::Header::setMaxTileSize(side, side);
  g_exr_limit_set = side;
}

// The variable-size values OpenEXR 3.1 reads by their own contents rather than by the attribute's declared size,
// checked to match it; else OpenEXR's position in the header and ours part, and the bytes after
// the attribute are read as another attribute (whose size may claim gigabytes):
// - chlist: entries of name, pixel type, pLinear, 3 reserved bytes and x, y sampling, ended by an
//   empty name. OpenEXR keeps any pixel type; OpenImageIO 2.4 aborts (an assertion) on one that is
//   not UINT, HALF or FLOAT.
// - preview: width, height, then width x height RGBA bytes (allocated by the header's numbers).
// - stringvector: strings of int32 length, each allocated by its length.
// The sizes of OpenEXR's fixed-size attribute types, which OpenEXR reads by their type whatever
// size the attribute declares.
int exrFixedTypeSize(const std::string& type) {
  static const std::map<std::string, int> sizes = {
      {"int", 4},          {"float", 4},      {"double", 8},   {"box2i", 16},       {"box2f", 16},
      {"v2i", 8},          {"v2f", 8},        {"v2d", 16},     {"v3i", 12},         {"v3f", 12},
      {"v3d", 24},         {"m33f", 36},      {"m33d", 72},    {"m44f", 64},        {"m44d", 128},
      {"compression", 1},  {"lineOrder", 1},  {"envmap", 1},   {"deepImageState", 1}, {"chromaticities", 32},
      {"keycode", 28},     {"timecode", 8},   {"rational", 8}, {"tiledesc", 9}};
  const auto it = sizes.find(type);
  return it == sizes.end() ? -1 : it->second;
}

void checkExrValue(const std::string& type, const std::string& value, const std::function<void(const std::string&)>& fail) {
  auto int32At = [&](std::size_t at) {
    std::int32_t v = 0;
    std::memcpy(&v, value.data() + at, 4);
    return v;
  };
  if (type == "chlist") {
    std::size_t at = 0;
    for (int channel = 0;; ++channel) {
      const std::size_t end = value.find('\0', at);
      if (end == std::string::npos) fail("the channel list is not terminated within its size");
      if (end == at) {
        if (channel == 0) fail("the channel list is empty");
        if (end + 1 != value.size()) fail("the channel list ends before its declared size");
        return;
      }
      const std::string name = value.substr(at, end - at);
      at = end + 1;
      if (value.size() - at < 16) fail("channel '" + name + "' is cut short");
      const std::int32_t pixel_type = int32At(at), x_sampling = int32At(at + 8), y_sampling = int32At(at + 12);
      at += 16;
      if (pixel_type < 0 || pixel_type > 2)
        fail("channel '" + name + "' has the unknown pixel type " + std::to_string(pixel_type));
      if (x_sampling < 1 || y_sampling < 1) fail("channel '" + name + "' has a sampling below 1");
    }
  }
  if (type == "preview") {
    if (value.size() < 8) fail("the preview image is cut short");
    std::uint32_t width = 0, height = 0;
    std::memcpy(&width, value.data(), 4);
    std::memcpy(&height, value.data() + 4, 4);
    if (std::uint64_t(width) * std::uint64_t(height) * 4 + 8 != value.size())
      fail("the preview image's " + std::to_string(width) + " x " + std::to_string(height) +
           " pixels do not match its size");
  }
  if (type == "stringvector") {
    for (std::size_t at = 0; at < value.size();) {
      if (value.size() - at < 4) fail("a string vector is cut short");
      const std::int32_t length = int32At(at);
      at += 4;
      if (length < 0 || std::size_t(length) > value.size() - at) fail("a string vector's string runs past its size");
      at += std::size_t(length);
    }
  }
}

// Walks the attribute lists of an OpenEXR file's header(s): every attribute's declared size must
// fit in the file, and the values OpenEXR reads by their contents must match it (checkExrValue). OpenEXR 3.1 (Debian 12)
// allocates an attribute's value by its declared size before it reads it, so a 600-byte file that
// claims a 2 GB string attribute costs 2 GB; no library in Debian checks either first, hence this
// walk (names, types, sizes and channel lists only; the rest is OpenEXR's to read).
void checkExrAttributeSizes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::error_code ec;
  const std::uint64_t file_size = fs::file_size(path, ec);
  if (!in || ec) return;  // openImageInput reports unreadable files
  unsigned char preamble[8];
  if (!in.read(reinterpret_cast<char*>(preamble), 8)) return;
  if (!(preamble[0] == 0x76 && preamble[1] == 0x2f && preamble[2] == 0x31 && preamble[3] == 0x01)) return;
  const bool long_names = preamble[5] & 0x04, multipart = preamble[5] & 0x10;
  const std::size_t max_name = long_names ? 255 : 31;
  auto fail = [&](const std::string& problem) { throw FileError(path, "corrupt OpenEXR header: " + problem); };
  auto readText = [&](const char* what) {
    std::string text;
    for (char c; in.get(c) && c != '\0';) {
      text.push_back(c);
      if (text.size() > max_name) fail(std::string(what) + " longer than " + std::to_string(max_name) + " characters");
    }
    if (!in) fail("the file ends inside the header");
    return text;
  };
  for (;;) {  // each part's header
    int attributes = 0;
    for (;; ++attributes) {
      const std::string name = readText("an attribute name");
      if (name.empty()) break;
      const std::string type = readText("an attribute type");
      std::int32_t size = 0;
      if (!in.read(reinterpret_cast<char*>(&size), 4)) fail("the file ends inside the header");
      const std::uint64_t at = std::uint64_t(in.tellg());
      if (size < 0 || std::uint64_t(size) > file_size - at)
        fail("attribute '" + name + "' (" + type + ") claims " + std::to_string(size) + " bytes, beyond the file's " +
             std::to_string(file_size) + " bytes");
      if (const int fixed = exrFixedTypeSize(type); fixed >= 0 && size != fixed)
        fail("attribute '" + name + "' (" + type + ") declares " + std::to_string(size) + " bytes, its type holds " +
             std::to_string(fixed));
      if (type == "chlist" || type == "preview" || type == "stringvector") {
        std::string value(std::size_t(size), '\0');
        if (!in.read(value.data(), size)) fail("the file ends inside the header");
        checkExrValue(type, value, [&](const std::string& problem) { fail("attribute '" + name + "': " + problem); });
      } else {
        in.seekg(size, std::ios::cur);
      }
    }
    // A multi-part file lists its headers one after another and ends the list with an empty one.
    if (!multipart || attributes == 0) return;
  }
}

// The OpenImageIO reader of an image by its first bytes, or empty when it is none of the five
// formats libbtf reads.
std::string readerByMagic(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  unsigned char b[8] = {};
  in.read(reinterpret_cast<char*>(b), sizeof b);
  const std::streamsize n = in.gcount();
  auto starts = [&](std::initializer_list<unsigned char> magic) {
    return n >= std::streamsize(magic.size()) && std::equal(magic.begin(), magic.end(), b);
  };
  if (starts({0x76, 0x2f, 0x31, 0x01})) return "openexr";
  if (starts({0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a})) return "png";
  if (starts({0xff, 0xd8, 0xff})) return "jpeg";
  if (starts({'I', 'I', 42, 0}) || starts({'M', 'M', 0, 42}) || starts({'I', 'I', 43, 0}) || starts({'M', 'M', 0, 43}))
    return "tiff";  // classic and BigTIFF, either byte order
  if (starts({'#', '?'})) return "hdr";  // "#?RADIANCE" or "#?RGBE"
  return {};
}

}  // namespace

void setImageSizeLimits(const ImageSizeLimits& limits) {
  if (limits.max_side < 1 || limits.max_pixels < 1) throw Error("image size limits must be at least 1");
  g_max_side = limits.max_side;
  g_max_pixels = limits.max_pixels;
}

ImageSizeLimits imageSizeLimits() { return {g_max_side.load(), g_max_pixels.load()}; }

void requireImageSizeWithinLimits(const fs::path& path, const image_backend::ImageHeader& spec) {
  const ImageSizeLimits limits = imageSizeLimits();
  const auto size = [&] { return std::to_string(spec.width) + " x " + std::to_string(spec.height); };
  if (spec.width <= 0 || spec.height <= 0 || spec.depth <= 0 || spec.channels <= 0)
    throw FileError(path, "image has no pixels (" + size() + ", " + std::to_string(spec.channels) + " channels)");
  if (spec.width > limits.max_side || spec.height > limits.max_side)
    throw FileError(path, "header claims " + size() + " pixels, beyond the limit of " +
                              std::to_string(limits.max_side) + " per side (corrupt? see setImageSizeLimits)");
  const std::uint64_t pixels = std::uint64_t(spec.width) * std::uint64_t(spec.height) * std::uint64_t(spec.depth);
  if (pixels > limits.max_pixels)
    throw FileError(path, "header claims " + size() + " pixels, beyond the limit of " +
                              std::to_string(limits.max_pixels) + " pixels (corrupt? see setImageSizeLimits)");
  if (spec.channels > 1024)
    throw FileError(path, "header claims " + std::to_string(spec.channels) + " channels (corrupt?)");
}

std::unique_ptr<image_backend::Reader> openImageInput(const fs::path& path) {
  requireReadableFile(path);
  std::error_code ec;
  if (fs::file_size(path, ec) == 0 && !ec) throw FileError(path, "empty file, expected an image");
  applyOpenExrLimit();
  checkExrAttributeSizes(path);
  // Only the reader of the file's own format is opened. ImageInput::open would try every reader
  // OpenImageIO has on a file its extension's reader refuses, and each is code a corrupt file can
  // reach: a 22-byte WebP decoded to hundreds of megapixels, and the RLA reader aborts (an
  // assertion) on a corrupt header. libbtf's data comes in five formats; any other is refused.
  const std::string format = readerByMagic(path);
  if (format.empty())
    throw FileError(path, "is not an OpenEXR, PNG, JPEG, TIFF or Radiance HDR image (by its first bytes), the formats libbtf reads");
  std::string error;
  auto in = imageBackend().openReader(format, path.string(), error);
  if (!in) throw FileError(path, error);
  requireImageSizeWithinLimits(path, in->header());
  return in;
}

}  // namespace btf
