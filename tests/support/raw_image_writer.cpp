#include "support/raw_image_writer.h"

#include <OpenImageIO/imageio.h>

#include <stdexcept>
#include <variant>

namespace btf::test {
namespace {

OIIO::ImageSpec specOf(const Image& image) { return OIIO::ImageSpec(image.width, image.height, image.channels, OIIO::TypeDesc::FLOAT); }

void check(bool ok, const std::filesystem::path& path, const std::unique_ptr<OIIO::ImageOutput>& out) {
  if (!ok) throw std::runtime_error(path.string() + ": " + (out ? out->geterror() : OIIO::geterror()));
}

}  // namespace

void writeRawImage(const std::filesystem::path& path, const Image& image) {
  auto out = OIIO::ImageOutput::create(path.string());
  check(bool(out), path, out);
  check(out->open(path.string(), specOf(image)), path, out);
  check(out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data()), path, out);
  check(out->close(), path, out);
}

void writeRawImageStack(const std::filesystem::path& path, const std::vector<StackLayer>& layers) {
  std::vector<OIIO::ImageSpec> specs;
  for (const StackLayer& layer : layers) {
    OIIO::ImageSpec spec = specOf(layer.image);
    spec.attribute("name", layer.name);
    for (const auto& attribute : layer.attributes)
      std::visit([&](const auto& v) { spec.attribute(attribute.first, v); }, attribute.second);
    specs.push_back(spec);
  }
  auto out = OIIO::ImageOutput::create(path.string());
  check(bool(out), path, out);
  check(out->open(path.string(), int(specs.size()), specs.data()), path, out);
  for (std::size_t i = 0; i < layers.size(); ++i) {
    if (i > 0) check(out->open(path.string(), specs[i], OIIO::ImageOutput::AppendSubimage), path, out);
    check(out->write_image(OIIO::TypeDesc::FLOAT, layers[i].image.pixels.data()), path, out);
  }
  check(out->close(), path, out);
}

}  // namespace btf::test
