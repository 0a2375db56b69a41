// Render with the engine runtime alone (libbtf::runtime, docs/renderers.md#embedding-the-runtime):
// a BTF-textured square under a sun and a uniform white sky, seen from a camera above it at about
// 45 degrees, 64 x 64 pixels. Direct sun light by eval(); the sky by drawing sample() (its weight
// is f cos / pdf) and checking pdf() against the sample's own. Writes a binary PPM if asked.
// Usage: runtime_render MATERIAL.btfrt [OUT.ppm]   (btf export --runtime writes MATERIAL.btfrt)
// Links nothing but the runtime and the C++17 standard library; exit code 0 on success.
#include <btf_runtime/material.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace {
btfrt::Vec3 normalize(btfrt::Vec3 v) {
  const float n = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
  return {v.x / n, v.y / n, v.z / n};
}
}  // namespace

int main(int argc, char** argv) try {
  if (argc < 2) {
    std::fprintf(stderr, "usage: runtime_render MATERIAL.btfrt [OUT.ppm]\n");
    return 2;
  }
  // Thread-safe and allocation-free per call: one Material serves every pixel (and thread).
  const btfrt::Material material = btfrt::Material::open(argv[1]);
  const int size = 64, samples = 16;
  const btfrt::Vec3 sun = normalize({0.4f, 0.2f, 0.9f});
  const float sun_radiance = 3.0f, sky_radiance = 0.5f;
  std::vector<float> image(std::size_t(size) * size * 3);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uniform(0.0f, 0.99999994f);
  double mean = 0;
  int pdf_mismatches = 0;
  for (int py = 0; py < size; ++py)
    for (int px = 0; px < size; ++px) {
      // Pixel (px, py) shows point (x, y) of the square [-1, 1]^2 on the plane z = 0 (the surface's
      // frame is the world's); the camera at (0, -2, 2) looks down on it at about 45 degrees.
      const float x = 2.0f * (float(px) + 0.5f) / float(size) - 1.0f, y = 2.0f * (float(py) + 0.5f) / float(size) - 1.0f;
      const btfrt::Vec3 wo = normalize({0.0f - x, -2.0f - y, 2.0f});
      // The texture repeats twice across the square.
      float u = (x + 1.0f), v = (y + 1.0f);
      u -= std::floor(u);
      v -= std::floor(v);
      btfrt::Rgb sum;
      const btfrt::Rgb f_sun = material.eval(sun, wo, u, v);
      sum.r += sun_radiance * f_sun.r * sun.z;
      sum.g += sun_radiance * f_sun.g * sun.z;
      sum.b += sun_radiance * f_sun.b * sun.z;
      for (int s = 0; s < samples; ++s) {
        btfrt::Sample sample;
        if (!material.sample(wo, u, v, uniform(rng), uniform(rng), sample)) continue;
        if (material.pdf(sample.wi, wo, u, v) != sample.pdf) ++pdf_mismatches;
        sum.r += sky_radiance * sample.weight.r / float(samples);
        sum.g += sky_radiance * sample.weight.g / float(samples);
        sum.b += sky_radiance * sample.weight.b / float(samples);
      }
      float* p = &image[(std::size_t(py) * size + std::size_t(px)) * 3];
      p[0] = sum.r, p[1] = sum.g, p[2] = sum.b;
      mean += double(sum.r + sum.g + sum.b) / 3.0;
    }
  mean /= double(size * size);
  std::printf("%s: %d x %d texels, rendered %d x %d at %d samples per pixel, mean radiance %.4f\n", argv[1],
              material.width(), material.height(), size, size, samples, mean);
  if (!(mean > 0.0 && std::isfinite(mean))) throw std::runtime_error("the image is black or not finite");
  if (pdf_mismatches != 0) throw std::runtime_error(std::to_string(pdf_mismatches) + " samples whose pdf() differs from sample()'s");
  if (argc > 2) {
    // Written to a temporary file and renamed, so a failed run leaves no half-written image.
    const std::string out = argv[2], temporary = out + ".partial";
    {
      std::ofstream file(temporary, std::ios::binary);
      file << "P6\n" << size << " " << size << "\n255\n";
      for (float c : image) {
        const float srgb = c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
        file.put(char(std::uint8_t(std::lround(255.0f * std::fmin(std::fmax(srgb, 0.0f), 1.0f)))));
      }
      if (!file) throw std::runtime_error(temporary + ": write failed");
    }
    if (std::rename(temporary.c_str(), out.c_str()) != 0) throw std::runtime_error(out + ": cannot be written");
  }
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "runtime_render: %s\n", e.what());
  return 1;
}
