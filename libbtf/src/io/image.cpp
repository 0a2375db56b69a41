#include "btf/io/image.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <memory>

#include "btf/core/error.h"
#include "btf/io/atomic_file.h"
#include "image_input.h"

namespace btf {
namespace fs = std::filesystem;
namespace {

std::string lowerExtension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

// Pixel type stored in the file for each extension writeImage accepts.
OIIO::TypeDesc storedPixelType(const fs::path& path) {
  const std::string ext = lowerExtension(path);
  if (ext == ".png") return OIIO::TypeDesc::UINT8;
  if (ext == ".exr" || ext == ".tif" || ext == ".tiff" || ext == ".hdr") return OIIO::TypeDesc::FLOAT;
  throw FileError(path, "unknown image extension '" + ext + "' (expected .exr, .png, .tif or .hdr)");
}

void requireConsistent(const fs::path& path, const Image& image) {
  if (image.width <= 0 || image.height <= 0 || image.channels <= 0)
    throw FileError(path, "cannot write an empty image (" + std::to_string(image.width) + "x" +
                              std::to_string(image.height) + "x" + std::to_string(image.channels) + ")");
  if (image.pixels.size() != std::size_t(image.width) * image.height * image.channels)
    throw FileError(path, "image data size does not match its dimensions");
}

void setAttribute(OIIO::ImageSpec& spec, const std::string& name, const ImageAttribute& value) {
  std::visit([&](const auto& v) { spec.attribute(name, v); }, value);
}

// The attributes a stack layer carries besides OpenImageIO's and OpenEXR's own bookkeeping.
bool isUserAttribute(const std::string& name) {
  return name.rfind("oiio:", 0) != 0 && name.rfind("openexr:", 0) != 0 && name != "name" &&
         name != "compression" && name != "PixelAspectRatio" && name != "screenWindowCenter" &&
         name != "screenWindowWidth" && name != "XResolution" && name != "YResolution" &&
         name != "ResolutionUnit" && name != "DateTime" && name != "Software";
}

Image readCurrentSubimage(const fs::path& path, OIIO::ImageInput& in, int subimage) {
  const OIIO::ImageSpec& spec = in.spec();
  requireImageSizeWithinLimits(path, spec);
  Image image;
  auto allocate = [&]() -> void* {
    image = Image(spec.width, spec.height, spec.nchannels);
    return image.pixels.data();
  };
  if (!readPixels(in, subimage, spec.nchannels, OIIO::TypeDesc::FLOAT, allocate))
    throw FileError(path, "pixel data cannot be read (truncated or corrupt?): " + in.geterror());
  return image;
}

}  // namespace

void writeImage(const fs::path& path, const Image& image) {
  const OIIO::TypeDesc stored = storedPixelType(path);
  requireConsistent(path, image);
  writeViaTemporaryPath(path, [&](const fs::path& tmp) {
    auto out = OIIO::ImageOutput::create(tmp.string());
    if (!out) throw FileError(path, "no image writer for this extension: " + OIIO::geterror());
    OIIO::ImageSpec spec(image.width, image.height, image.channels, stored);
    if (lowerExtension(path) == ".exr") spec.attribute("compression", "zip");
    if (!out->open(tmp.string(), spec)) throw FileError(path, "cannot be written: " + out->geterror());
    if (!out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data()) || !out->close())
      throw FileError(path, "cannot be written: " + out->geterror());
  });
}

Image readImage(const fs::path& path) {
  auto in = openImageInput(path);
  return readCurrentSubimage(path, *in, 0);
}

float srgbEncode(float linear) {
  const float x = std::clamp(linear, 0.0f, 1.0f);
  return x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
}

float srgbDecode(float encoded) {
  const float e = std::clamp(encoded, 0.0f, 1.0f);
  return e <= 0.04045f ? e / 12.92f : std::pow((e + 0.055f) / 1.055f, 2.4f);
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
  std::vector<OIIO::ImageSpec> specs;
  for (const StackLayer& layer : layers) {
    requireConsistent(path, layer.image);
    OIIO::ImageSpec spec(layer.image.width, layer.image.height, layer.image.channels, OIIO::TypeDesc::FLOAT);
    spec.attribute("compression", "zip");
    spec.attribute("name", layer.name);
    for (const auto& [name, value] : layer.attributes) setAttribute(spec, name, value);
    specs.push_back(std::move(spec));
  }
  writeViaTemporaryPath(path, [&](const fs::path& tmp) {
    auto out = OIIO::ImageOutput::create(tmp.string());
    if (!out || !out->supports("multiimage"))
      throw FileError(path, "no multi-part EXR writer available: " + OIIO::geterror());
    if (!out->open(tmp.string(), int(specs.size()), specs.data()))
      throw FileError(path, "cannot be written: " + out->geterror());
    for (std::size_t i = 0; i < layers.size(); ++i) {
      if (i > 0 && !out->open(tmp.string(), specs[i], OIIO::ImageOutput::AppendSubimage))
        throw FileError(path, "cannot be written: " + out->geterror());
      if (!out->write_image(OIIO::TypeDesc::FLOAT, layers[i].image.pixels.data()))
        throw FileError(path, "cannot be written: " + out->geterror());
    }
    if (!out->close()) throw FileError(path, "cannot be written: " + out->geterror());
  });
}

std::vector<StackLayer> readImageStack(const fs::path& path) {
  auto in = openImageInput(path);
  const int count = std::max(1, in->spec().get_int_attribute("oiio:subimages", 1));
  std::vector<StackLayer> layers;
  for (int s = 0; s < count; ++s) {
    if (!in->seek_subimage(s, 0)) throw FileError(path, "part " + std::to_string(s) + " cannot be read: " + in->geterror());
    const OIIO::ImageSpec& spec = in->spec();
    StackLayer layer;
    layer.name = spec.get_string_attribute("name", spec.get_string_attribute("oiio:subimagename"));
    for (const OIIO::ParamValue& p : spec.extra_attribs) {
      const std::string name = p.name().string();
      if (!isUserAttribute(name)) continue;
      if (p.type() == OIIO::TypeInt) layer.attributes[name] = p.get_int();
      else if (p.type() == OIIO::TypeFloat) layer.attributes[name] = p.get_float();
      else if (p.type() == OIIO::TypeString) layer.attributes[name] = p.get_string();
    }
    layer.image = readCurrentSubimage(path, *in, s);
    layers.push_back(std::move(layer));
  }
  return layers;
}

}  // namespace btf
