#include "btf/io/image.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <memory>

#include "btf/core/error.h"
#include "btf/io/atomic_file.h"
#include "image_backend.h"
#include "image_input.h"

namespace btf {
namespace fs = std::filesystem;
using image_backend::PixelType;
namespace {

std::string lowerExtension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

// Pixel type stored in the file for each extension writeImage accepts.
PixelType storedPixelType(const fs::path& path) {
  const std::string ext = lowerExtension(path);
  if (ext == ".png") return PixelType::UInt8;
  if (ext == ".exr" || ext == ".tif" || ext == ".tiff" || ext == ".hdr") return PixelType::Float;
  throw FileError(path, "unknown image extension '" + ext + "' (expected .exr, .png, .tif or .hdr)");
}

void requireConsistent(const fs::path& path, const Image& image) {
  if (image.width <= 0 || image.height <= 0 || image.channels <= 0)
    throw FileError(path, "cannot write an empty image (" + std::to_string(image.width) + "x" +
                              std::to_string(image.height) + "x" + std::to_string(image.channels) + ")");
  if (image.pixels.size() != std::size_t(image.width) * image.height * image.channels)
    throw FileError(path, "image data size does not match its dimensions");
  // Every value libbtf writes is finite: an image of inf is an error, not a picture.
  if (const std::optional<std::string> bad = nonFinitePixel(image))
    throw FileError(path, "not written: " + *bad + " (libbtf writes finite values only)");
}

// The attributes a stack layer carries besides OpenImageIO's and OpenEXR's own bookkeeping.
bool isUserAttribute(const std::string& name) {
  return name.rfind("oiio:", 0) != 0 && name.rfind("openexr:", 0) != 0 && name != "name" &&
         name != "compression" && name != "PixelAspectRatio" && name != "screenWindowCenter" &&
         name != "screenWindowWidth" && name != "XResolution" && name != "YResolution" &&
         name != "ResolutionUnit" && name != "DateTime" && name != "Software";
}

Image readCurrentSubimage(const fs::path& path, image_backend::Reader& in, int subimage) {
  const image_backend::ImageHeader& spec = in.header();
  requireImageSizeWithinLimits(path, spec);
  Image image;
  auto allocate = [&]() -> void* {
    image = Image(spec.width, spec.height, spec.channels);
    return image.pixels.data();
  };
  if (!in.readPixels(subimage, spec.channels, PixelType::Float, allocate))
    throw FileError(path, "pixel data cannot be read (truncated or corrupt?): " + in.error());
  return image;
}

// A writer for the path's extension (the temporary path keeps the destination's extension).
std::unique_ptr<image_backend::Writer> createWriter(const fs::path& destination, const fs::path& tmp) {
  std::string error;
  auto out = imageBackend().createWriter(tmp.string(), error);
  if (!out) throw FileError(destination, "no image writer for this extension: " + error);
  return out;
}

}  // namespace

void writeImage(const fs::path& path, const Image& image) {
  const PixelType stored = storedPixelType(path);
  requireConsistent(path, image);
  writeViaTemporaryPath(path, [&](const fs::path& tmp) {
    auto out = createWriter(path, tmp);
    image_backend::WriteSpec spec{image.width, image.height, image.channels, stored, {}};
    if (lowerExtension(path) == ".exr") spec.attributes.emplace_back("compression", std::string("zip"));
    if (!out->open(tmp.string(), spec)) throw FileError(path, "cannot be written: " + out->error());
    if (!out->write(PixelType::Float, image.pixels.data()) || !out->close())
      throw FileError(path, "cannot be written: " + out->error());
  });
}

std::optional<std::string> nonFinitePixel(const Image& image) {
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    const float v = image.pixels[i];
    if (std::isfinite(v)) continue;
    const std::size_t channels = std::size_t(std::max(image.channels, 1)), pixel = i / channels;
    const std::size_t width = std::size_t(std::max(image.width, 1));
    return "pixel (" + std::to_string(pixel % width) + ", " + std::to_string(pixel / width) + ") channel " +
           std::to_string(i % channels) + " is " + (std::isnan(v) ? "NaN" : v > 0 ? "inf" : "-inf");
  }
  return std::nullopt;
}

std::string imageFileFormat(const fs::path& path) {
  unsigned char head[10] = {};
  std::ifstream in(path, std::ios::binary);
  in.read(reinterpret_cast<char*>(head), sizeof head);
  const std::size_t n = std::size_t(in.gcount());
  auto starts = [&](std::initializer_list<unsigned char> magic) {
    return n >= magic.size() && std::equal(magic.begin(), magic.end(), head);
  };
  if (starts({0x76, 0x2f, 0x31, 0x01})) return "openexr";
  if (starts({0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'})) return "png";
  if (starts({0xff, 0xd8, 0xff})) return "jpeg";
  if (starts({'I', 'I', 0x2a, 0x00}) || starts({'M', 'M', 0x00, 0x2a})) return "tiff";
  if (starts({'#', '?'})) return "hdr";
  return {};
}

Image readImage(const fs::path& path) {
  auto in = openImageInput(path);
  return readCurrentSubimage(path, *in, 0);
}

std::optional<Image> renderTextMask(std::string_view text, int font_size, const std::string& font) {
  image_backend::TextMask mask;
  bool font_missing = false;
  std::string error;
  if (!imageBackend().renderText(std::string(text), font_size, font, mask, font_missing, error)) {
    if (font_missing) return std::nullopt;
    throw Error("cannot render the text '" + std::string(text) + "': " + error);
  }
  Image image(mask.width, mask.height, 1);
  image.pixels = std::move(mask.coverage);
  return image;
}

float srgbEncode(float linear) {
  const float x = std::clamp(linear, 0.0f, 1.0f);
  return x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
}

float srgbDecode(float encoded) {
  const float e = std::clamp(encoded, 0.0f, 1.0f);
  return e <= 0.04045f ? e / 12.92f : std::pow((e + 0.055f) / 1.055f, 2.4f);
}

Srgb8::Srgb8() {
  auto code = [](float x) { return std::lround(srgbEncode(x) * 255.0f); };
  // srgbEncode is non-decreasing over the floats, and non-negative floats order as their bit
  // patterns: the least x of code >= k is a bisection over the patterns of [0, 1].
  threshold_[0] = -std::numeric_limits<float>::infinity();
  for (int k = 1; k < 256; ++k) {
    std::uint32_t lo = 0, hi = std::bit_cast<std::uint32_t>(1.0f);  // code(lo) < k <= code(hi)
    while (hi - lo > 1) {
      const std::uint32_t mid = lo + (hi - lo) / 2;
      (code(std::bit_cast<float>(mid)) >= k ? hi : lo) = mid;
    }
    threshold_[std::size_t(k)] = std::bit_cast<float>(hi);
  }
  for (int k = 0; k < 256; ++k) decoded_[std::size_t(k)] = srgbDecode(float(k) / 255.0f);
}

const Srgb8& Srgb8::instance() {
  static const Srgb8 table;
  return table;
}

std::uint8_t Srgb8::encode(float linear) const {
  // The largest k with threshold_[k] <= linear, by eight halvings without a branch to mispredict.
  // NaN fails every comparison and stays at 0; values above 1 reach 255 (as the clamp does).
  std::size_t k = 0;
  for (std::size_t step = 128; step > 0; step /= 2)
    k += (threshold_[k + step] <= linear) ? step : 0;
  return std::uint8_t(k);
}

Image toneMapToSrgb(const Image& linear, float exposure_stops) {
  Image out = linear;
  const float scale = std::exp2(exposure_stops);
  for (std::size_t i = 0; i < out.pixels.size(); ++i) {
    const bool is_alpha = out.channels == 4 && i % 4 == 3;
    if (!is_alpha) out.pixels[i] = srgbEncode(out.pixels[i] * scale);
  }
  return out;
}

void writeImageStack(const fs::path& path, const std::vector<StackLayer>& layers) {
  if (lowerExtension(path) != ".exr")
    throw FileError(path, "an image stack must be written as .exr (multi-part OpenEXR)");
  if (layers.empty()) throw FileError(path, "cannot write an image stack without layers");
  std::vector<image_backend::WriteSpec> specs;
  for (const StackLayer& layer : layers) {
    requireConsistent(path, layer.image);
    image_backend::WriteSpec spec{layer.image.width, layer.image.height, layer.image.channels, PixelType::Float, {}};
    spec.attributes.emplace_back("compression", std::string("zip"));
    spec.attributes.emplace_back("name", layer.name);
    for (const auto& [name, value] : layer.attributes) spec.attributes.emplace_back(name, value);
    specs.push_back(std::move(spec));
  }
  writeViaTemporaryPath(path, [&](const fs::path& tmp) {
    std::string error;
    auto out = imageBackend().createWriter(tmp.string(), error);
    if (!out || !out->supportsMultiImage()) throw FileError(path, "no multi-part EXR writer available: " + error);
    if (!out->openSubimages(tmp.string(), specs)) throw FileError(path, "cannot be written: " + out->error());
    for (std::size_t i = 0; i < layers.size(); ++i) {
      if (i > 0 && !out->appendSubimage(tmp.string(), specs[i]))
        throw FileError(path, "cannot be written: " + out->error());
      if (!out->write(PixelType::Float, layers[i].image.pixels.data()))
        throw FileError(path, "cannot be written: " + out->error());
    }
    if (!out->close()) throw FileError(path, "cannot be written: " + out->error());
  });
}

std::vector<StackLayer> readImageStack(const fs::path& path) {
  auto in = openImageInput(path);
  const int count = in->header().subimages;
  std::vector<StackLayer> layers;
  for (int s = 0; s < count; ++s) {
    if (!in->seekSubimage(s)) throw FileError(path, "part " + std::to_string(s) + " cannot be read: " + in->error());
    const image_backend::ImageHeader& spec = in->header();
    StackLayer layer;
    layer.name = spec.name;
    for (const auto& [name, value] : spec.attributes)
      if (isUserAttribute(name)) layer.attributes[name] = value;
    layer.image = readCurrentSubimage(path, *in, s);
    layers.push_back(std::move(layer));
  }
  return layers;
}

}  // namespace btf
