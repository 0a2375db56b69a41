#include "fuzz_support.h"

#include <unistd.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "btf/core/btf_directions.h"
#include "btf/core/value_limits.h"
#include "btf/io/btf_data.h"
#include "btf/io/btf_images.h"
#include "btf/io/image.h"
#include "btf/material/material.h"
#include "btf/render/integrator.h"
#include "btf/render/scene.h"

namespace btf::fuzz {
namespace fs = std::filesystem;

namespace {

const fs::path& privateFolder() {
  static const fs::path folder = [] {
    // Image size limits of a fuzzing session (1 megapixel, 4096 per side), set before the first
    // input as OSS-Fuzz's image targets limit theirs: within libbtf's default limits (2^26
    // pixels) a valid input of the fuzzer's 16 KB decodes to millions of pixels (deflate reaches
    // about 1000:1), seconds under the sanitizers, which the 2 s timeout would report as a hang.
    // What is tested is that the limit holds and that everything within it is read quickly.
    setImageSizeLimits({4096, std::uint64_t(1) << 20});
    std::error_code ec;
    const fs::path base = fs::is_directory("/dev/shm", ec) ? fs::path("/dev/shm") : fs::temp_directory_path();
    fs::path dir = base / ("libbtf-fuzz-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    std::atexit([] {
      std::error_code ignored;
      fs::remove_all(privateFolder(), ignored);
    });
    return dir;
  }();
  return folder;
}

[[noreturn]] void finding(const char* what) {
  std::fprintf(stderr, "fuzz finding: %s\n", what);
  std::abort();
}

bool usable(const Rgb& v) {
  for (int c = 0; c < 3; ++c)
    if (!std::isfinite(v[c]) || v[c] < 0) return false;
  return true;
}

glm::vec3 direction(float theta_deg, float phi_deg) {
  const float t = glm::radians(theta_deg), p = glm::radians(phi_deg);
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

}  // namespace

void writeFile(const fs::path& path, std::span<const std::uint8_t> bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  if (!out) finding("cannot write the input file (is the temporary folder full?)");
}

fs::path writeInput(std::span<const std::uint8_t> bytes, std::string_view file_name) {
  const fs::path path = privateFolder() / file_name;
  writeFile(path, bytes);
  return path;
}

fs::path emptyFolder(std::string_view name) {
  const fs::path folder = privateFolder() / name;
  std::error_code ec;
  fs::remove_all(folder, ec);
  fs::create_directories(folder);
  return folder;
}

namespace {

fs::path writeSmallFolder(const BtfImageWriteOptions& options, const std::string& name) {
  const fs::path folder = emptyFolder(name);
  BtfData data(2, 2, "fuzz", BtfViewSet({0}));
  for (int light = 0; light < kBtfDirectionCount; ++light)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x) data.at(x, y, 0, light) = Rgb(0.1f * float(1 + x + 2 * y), 0.2f, 0.3f);
  writeBtfImageFolder(data, folder, options);
  return folder;
}

}  // namespace

fs::path writeSmallBtfFolder(bool exr) {
  BtfImageWriteOptions options;
  options.format = exr ? BtfImageFormat::Exr : BtfImageFormat::Png8;
  return writeSmallFolder(options, "btf-" + btfImageFormatName(options.format));
}

fs::path writeSmallUtiaFolder() {
  BtfImageWriteOptions options;
  options.layout = BtfImageLayout::Utia;
  return writeSmallFolder(options, "btf-utia");
}

void exerciseMaterial(const Material& material) {
  // Normal incidence, the measured range and grazing angles (89.9 degrees: where tables' last bins
  // and 1 / cos factors live), in several azimuths so that anisotropic tables are read everywhere.
  const float thetas[] = {0.f, 30.f, 60.f, 80.f, 89.9f};
  const float phis[] = {0.f, 95.f, 180.f, 300.f};
  const glm::vec2 us[] = {{0.5f, 0.5f}, {0.01f, 0.99f}, {0.999f, 0.001f}};
  for (float to : thetas)
    for (float po : phis) {
      const glm::vec3 wo = direction(to, po);
      for (float ti : thetas) {
        const glm::vec3 wi = direction(ti, po + 170.f);
        if (!usable(material.eval(wi, wo))) finding("eval() is negative or not finite");
        const float pdf = material.pdf(wi, wo);
        if (!std::isfinite(pdf) || pdf < 0) finding("pdf() is negative or not finite");
      }
      // The stream eval (eight wi per step in AVX2 lanes for RGL files) must give eval()'s bits.
      std::vector<glm::vec3> wis;
      for (float ti : thetas)
        for (float pi : phis) wis.push_back(direction(ti, pi + 10.f));
      std::vector<Rgb> many(wis.size());
      material.evalMany(wo, wis, many);
      for (std::size_t k = 0; k < wis.size(); ++k) {
        const Rgb one = material.eval(wis[k], wo);
        for (int c = 0; c < 3; ++c)
          if (std::bit_cast<std::uint32_t>(one[c]) != std::bit_cast<std::uint32_t>(many[k][c]))
            finding("evalMany() differs from eval()");
      }
      for (glm::vec2 u : us) {
        const auto s = material.sample(wo, {0.5f, 0.5f}, u);
        if (!s) continue;
        if (!usable(s->weight) || !std::isfinite(s->pdf) || s->pdf < 0) finding("sample() weight or pdf unusable");
        if (!std::isfinite(s->wi.x) || std::abs(glm::length(s->wi) - 1.f) > 1e-3f) finding("sample() wi not a unit vector");
      }
    }
}

void exerciseLookup(const BtfLookup& btf) {
  const int w = btf.lookupWidth(), h = btf.lookupHeight();
  if (w < 1 || h < 1) finding("a BTF of no texels loaded");
  const int xs[] = {0, w / 2, w - 1}, ys[] = {0, h / 2, h - 1};
  const int lights[] = {0, 1, 40, kBtfDirectionCount - 1};
  std::vector<BtfSampleIndex> samples;
  for (int view : btf.lookupViews().views())
    for (int light : lights)
      for (int y : ys)
        for (int x : xs) samples.push_back({x, y, view, light});
  std::vector<Rgb> streamed(samples.size());
  btf.values(samples, streamed);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Rgb one = btf.value(samples[i].x, samples[i].y, samples[i].view, samples[i].light);
    for (int c = 0; c < 3; ++c) {
      if (!std::isfinite(one[c])) finding("value() is not finite");
      if (one[c] != streamed[i][c]) finding("values() differs from value()");
    }
  }
}

void exerciseDecode(const BtfSource& btf) {
  std::vector<Rgb> values;
  for (const int view : btf.views().views()) {
    btf.loadView(view, values);
    for (const Rgb& v : values)
      if (!v.isFinite() || v.minComponent() < 0.0f || v.maxComponent() > kMaxReflectance)
        finding("a decoded value is not finite, negative or beyond kMaxReflectance");
  }
}

void exerciseScene(const render::SceneDescription& description) {
  for (const render::SceneMaterial& m : description.materials) exerciseMaterial(*m.material);
  for (const render::PointLight& light : description.point_lights)
    if (!light.intensity.isFinite()) finding("a light's intensity is not finite");
  if (!description.environment_radiance.isFinite()) finding("the environment's radiance is not finite");
  // A tiny render: whatever loaded renders to finite pixels.
  render::SceneDescription tiny = description;
  tiny.camera.width = std::min(tiny.camera.width, 4);
  tiny.camera.height = std::min(tiny.camera.height, 4);
  const render::Scene scene(std::move(tiny));
  render::RenderSettings settings;
  settings.spp = 1;
  settings.max_depth = 3;
  if (nonFinitePixel(render::makePathTracer()->render(scene, settings).color)) finding("a render is not finite");
}

}  // namespace btf::fuzz
