// The image backend over OpenImageIO (see ../image_backend.h): built as the module
// libbtf_image_oiio.so, loaded by libbtf on first use. It decodes, encodes and renders text, and
// decides nothing else: limits, checks and messages are libbtf's.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "image_backend.h"

namespace btf::image_backend {
namespace {

OIIO::TypeDesc toOiio(PixelType type) {
  switch (type) {
    case PixelType::UInt8: return OIIO::TypeDesc::UINT8;
    case PixelType::UInt16: return OIIO::TypeDesc::UINT16;
    case PixelType::Half: return OIIO::TypeDesc::HALF;
    case PixelType::Float: return OIIO::TypeDesc::FLOAT;
    case PixelType::Other: break;
  }
  return OIIO::TypeDesc::UNKNOWN;
}

PixelType fromOiio(const OIIO::TypeDesc& type) {
  switch (type.basetype) {
    case OIIO::TypeDesc::UINT8: return PixelType::UInt8;
    case OIIO::TypeDesc::UINT16: return PixelType::UInt16;
    case OIIO::TypeDesc::HALF: return PixelType::Half;
    case OIIO::TypeDesc::FLOAT: return PixelType::Float;
    default: return PixelType::Other;
  }
}

ImageHeader headerOf(const OIIO::ImageSpec& spec, int subimages) {
  ImageHeader header;
  header.width = spec.width;
  header.height = spec.height;
  header.depth = spec.depth;
  header.channels = spec.nchannels;
  header.stored = fromOiio(spec.format);
  header.floating_point = spec.format.is_floating_point();
  header.subimages = subimages;
  header.name = spec.get_string_attribute("name", spec.get_string_attribute("oiio:subimagename"));
  for (const OIIO::ParamValue& p : spec.extra_attribs) {
    const std::string name = p.name().string();
    if (p.type() == OIIO::TypeInt) header.attributes.emplace_back(name, p.get_int());
    else if (p.type() == OIIO::TypeFloat) header.attributes.emplace_back(name, p.get_float());
    else if (p.type() == OIIO::TypeString) header.attributes.emplace_back(name, p.get_string());
  }
  return header;
}

class OiioReader final : public Reader {
 public:
  explicit OiioReader(std::unique_ptr<OIIO::ImageInput> in)
      : in_(std::move(in)), subimages_(std::max(1, in_->spec().get_int_attribute("oiio:subimages", 1))),
        header_(headerOf(in_->spec(), subimages_)) {}

  const ImageHeader& header() const override { return header_; }

  bool seekSubimage(int subimage) override {
    if (!in_->seek_subimage(subimage, 0)) return false;
    header_ = headerOf(in_->spec(), subimages_);
    return true;
  }

  bool readPixels(int subimage, int channels, PixelType as, const std::function<void*()>& destination) override {
    const OIIO::TypeDesc format = toOiio(as);
    const OIIO::ImageSpec& spec = in_->spec();
    if (spec.tile_width > 0 || spec.depth > 1) {
      // Tiled: the first tile decodes before the image is allocated, then read_image reads it all.
      if (spec.tile_width > 0) {
        const std::size_t tile_values = std::size_t(spec.tile_width) * std::size_t(std::max(spec.tile_height, 1)) *
                                        std::size_t(std::max(spec.tile_depth, 1)) * std::size_t(spec.nchannels);
        std::vector<std::byte> tile(tile_values * format.size());
        if (!in_->read_tile(spec.x, spec.y, spec.z, format, tile.data())) return false;  // of the current subimage
      }
      return in_->read_image(subimage, 0, 0, channels, format, destination());
    }
    const std::size_t value_bytes = format.size();
    const std::size_t row_values = std::size_t(spec.width) * std::size_t(spec.nchannels);
    std::vector<std::byte> row(row_values * value_bytes);
    std::byte* out = nullptr;
    for (int y = 0; y < spec.height; ++y) {
      // read_scanline reads every channel; the first `channels` of each pixel are kept.
      if (!in_->read_scanline(spec.y + y, spec.z, format, row.data())) return false;
      if (!out) out = static_cast<std::byte*>(destination());
      for (int x = 0; x < spec.width; ++x)
        std::memcpy(out + (std::size_t(y) * std::size_t(spec.width) + std::size_t(x)) * std::size_t(channels) * value_bytes,
                    row.data() + std::size_t(x) * std::size_t(spec.nchannels) * value_bytes,
                    std::size_t(channels) * value_bytes);
    }
    return true;
  }

  std::string error() override { return in_->geterror(); }

 private:
  std::unique_ptr<OIIO::ImageInput> in_;
  int subimages_;
  ImageHeader header_;
};

OIIO::ImageSpec specOf(const WriteSpec& w) {
  OIIO::ImageSpec spec(w.width, w.height, w.channels, toOiio(w.stored));
  // No capture time: OpenImageIO's EXR and TIFF writers stamp the current time when DateTime is
  // unset, and the same render must give the same file, byte for byte.
  spec.attribute("DateTime", "");
  for (const auto& attribute : w.attributes)  // (clang 14 cannot capture a structured binding)
    std::visit([&](const auto& v) { spec.attribute(attribute.first, v); }, attribute.second);
  return spec;
}

class OiioWriter final : public Writer {
 public:
  explicit OiioWriter(std::unique_ptr<OIIO::ImageOutput> out) : out_(std::move(out)) {}

  bool supportsMultiImage() override { return out_->supports("multiimage"); }

  bool open(const std::string& path, const WriteSpec& spec) override { return out_->open(path, specOf(spec)); }

  bool openSubimages(const std::string& path, const std::vector<WriteSpec>& subimages) override {
    std::vector<OIIO::ImageSpec> specs;
    for (const WriteSpec& w : subimages) specs.push_back(specOf(w));
    return out_->open(path, int(specs.size()), specs.data());
  }

  bool appendSubimage(const std::string& path, const WriteSpec& spec) override {
    return out_->open(path, specOf(spec), OIIO::ImageOutput::AppendSubimage);
  }

  bool write(PixelType as, const void* pixels) override { return out_->write_image(toOiio(as), pixels); }
  bool close() override { return out_->close(); }
  std::string error() override { return out_->geterror(); }

 private:
  std::unique_ptr<OIIO::ImageOutput> out_;
};

class OiioBackend final : public Backend {
 public:
  std::unique_ptr<Reader> openReader(const std::string& format, const std::string& path, std::string& error) override {
    // Only the reader of the file's own format is created: ImageInput::open would try every reader
    // OpenImageIO has on a file that its extension's reader refuses.
    auto in = OIIO::ImageInput::create(format);
    if (!in) {
      error = "OpenImageIO has no " + format + " reader: " + OIIO::geterror();
      return nullptr;
    }
    OIIO::ImageSpec opened;
    if (!in->open(path, opened)) {
      error = "cannot be read as an image (corrupt?): " + in->geterror();
      return nullptr;
    }
    return std::make_unique<OiioReader>(std::move(in));
  }

  std::unique_ptr<Writer> createWriter(const std::string& path, std::string& error) override {
    auto out = OIIO::ImageOutput::create(path);
    if (!out) {
      error = OIIO::geterror();
      return nullptr;
    }
    return std::make_unique<OiioWriter>(std::move(out));
  }

  void decodeExrInCallingThreads() override { OIIO::attribute("exr_threads", -1); }

  bool renderText(const std::string& text, int font_size, const std::string& font, TextMask& mask,
                  bool& font_missing, std::string& error) override {
    font_missing = false;
    const OIIO::ROI box = OIIO::ImageBufAlgo::text_size(text, font_size, font);
    if (!box.defined()) {
      font_missing = true;
      return false;
    }
    OIIO::ImageBuf buffer(OIIO::ImageSpec(box.width(), box.height(), 1, OIIO::TypeDesc::FLOAT));
    OIIO::ImageBufAlgo::zero(buffer);
    const float white = 1.0f;
    // render_text places the baseline at y; the box's ybegin is the (negative) ascent above it.
    if (!OIIO::ImageBufAlgo::render_text(buffer, -box.xbegin, -box.ybegin, text, font_size, font, {&white, 1})) {
      error = buffer.geterror();
      return false;
    }
    mask.width = box.width();
    mask.height = box.height();
    mask.coverage.assign(std::size_t(mask.width) * std::size_t(mask.height), 0.0f);
    if (!buffer.get_pixels(OIIO::ROI(0, mask.width, 0, mask.height, 0, 1, 0, 1), OIIO::TypeDesc::FLOAT,
                           mask.coverage.data())) {
      error = buffer.geterror();
      return false;
    }
    return true;
  }
};

}  // namespace
}  // namespace btf::image_backend

extern "C" __attribute__((visibility("default"))) btf::image_backend::Backend* btf_image_backend(int abi_version) {
  if (abi_version != btf::image_backend::kAbiVersion) return nullptr;
  static btf::image_backend::OiioBackend backend;
  return &backend;
}
