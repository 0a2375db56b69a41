// The lat-long environment map light (render/environment_map.h): its direction <-> pixel
// convention, that sample() draws exactly the density pdf() reports (chi-square, 1e6 draws,
// 20 x 40 cells, significance 0.01, fixed seed), that the pdf integrates to 1, that meanRadiance
// is what Monte Carlo through sample() estimates, and its errors.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "btf/core/error.h"
#include "btf/core/rng.h"
#include "btf/io/image.h"
#include "btf/render/environment_map.h"
#include "btf/sampling/chi2.h"
#include "support/raw_image_writer.h"
#include "support/test_support.h"

namespace {

using btf::Image;
using btf::Rgb;
using btf::render::EnvironmentMap;

constexpr double kPi = std::numbers::pi;

// A map with structure everywhere: a smooth colour gradient in theta and phi, a bright spot
// straddling the phi = 0 seam, a dim band near the bottom pole and a few black pixels.
Image structuredMap(int width = 24, int height = 12) {
  Image image(width, height, 3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double u = (x + 0.5) / width, v = (y + 0.5) / height;
      image.at(x, y, 0) = float(0.35 + 0.8 * v + 0.3 * std::sin(2 * kPi * u));
      image.at(x, y, 1) = float(0.5 + 0.4 * std::cos(2 * kPi * u) * (1 - v));
      image.at(x, y, 2) = float(0.1 + u);
    }
  for (int c = 0; c < 3; ++c) {
    image.at(0, height / 3, c) = 40.0f;
    image.at(width - 1, height / 3, c) = 25.0f;
    image.at(width / 2, height - 1, c) = 1e-4f;  // far below the floor: must stay reachable
    image.at(3, 2, c) = 0.0f;                     // black: never drawn
    image.at(7, height - 2, c) = 0.0f;
  }
  image.at(width / 4, height / 2, 1) = 0.0f;  // not black: red and blue remain
  return image;
}

Image constantMap(int width, int height, Rgb value) {
  Image image(width, height, 3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c) image.at(x, y, c) = value[c];
  return image;
}

// Midpoint rule over (theta, phi) in the map's own convention (theta from +y, phi from +x towards
// +z), with dw = sin(theta) dtheta dphi; independent of the map's CDFs and solid angles.
template <class F>
double integrateOverSphere(const F& f, int theta_steps, int phi_steps) {
  const double dtheta = kPi / theta_steps, dphi = 2.0 * kPi / phi_steps;
  double sum = 0.0;
  for (int i = 0; i < theta_steps; ++i) {
    const double theta = (i + 0.5) * dtheta;
    for (int j = 0; j < phi_steps; ++j) {
      const double phi = (j + 0.5) * dphi;
      const glm::vec3 d{float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)),
                        float(std::sin(theta) * std::sin(phi))};
      sum += f(d) * std::sin(theta);
    }
  }
  return sum * dtheta * dphi;
}

// The chi-square harness cuts the sphere about +z with phi from +x towards +y; the map's frame has
// its pole at +y and phi from +x towards +z. Swapping y and z carries one onto the other, so that
// the pixel edges (lines of constant theta or phi) fall on the lines the harness follows exactly.
glm::vec3 harnessToMap(const glm::vec3& h) { return {h.x, h.z, h.y}; }
glm::vec3 mapToHarness(const glm::vec3& d) { return {d.x, d.z, d.y}; }

btf::Chi2Result chi2OfMap(const EnvironmentMap& map, const btf::DirectionPdf& pdf) {
  return btf::chi2Test(
      [&map](glm::vec2 u) -> std::optional<glm::vec3> {
        const auto s = map.sample(u);
        if (!s) return std::nullopt;
        return mapToHarness(s->direction);
      },
      pdf, btf::Chi2Options{});  // 1e6 draws, 20 x 40 cells, significance 0.01, seed 1
}

}  // namespace

TEST(EnvironmentMap, DirectionAndPixelConventionIncludingSeamAndPoles) {
  const EnvironmentMap map(constantMap(16, 8, Rgb(1.0f)), 1.0f, "constant");
  using V = glm::vec3;
  // +x: phi = 0, equator; +z: phi = pi/2; -x: phi = pi; -z: phi = 3 pi/2.
  EXPECT_NEAR(EnvironmentMap::directionToUv(V(1, 0, 0)).x, 0.0f, 1e-7f);
  EXPECT_NEAR(EnvironmentMap::directionToUv(V(1, 0, 0)).y, 0.5f, 1e-7f);
  EXPECT_NEAR(EnvironmentMap::directionToUv(V(0, 0, 1)).x, 0.25f, 1e-6f);
  EXPECT_NEAR(EnvironmentMap::directionToUv(V(-1, 0, 0)).x, 0.5f, 1e-6f);
  EXPECT_NEAR(EnvironmentMap::directionToUv(V(0, 0, -1)).x, 0.75f, 1e-6f);
  // theta from +y: the top row is +y, the bottom row -y.
  EXPECT_EQ(map.pixelOf(V(0, 1, 0)), glm::ivec2(0, 0));
  EXPECT_EQ(map.pixelOf(V(0, -1, 0)).y, 7);
  EXPECT_EQ(map.pixelOf(V(1e-4f, 1, 0.3e-4f)).y, 0);
  EXPECT_EQ(map.pixelOf(V(-1e-4f, -1, -0.3e-4f)).y, 7);
  // The seam: just above phi = 0 is the first column, just below it (phi -> 2 pi) the last.
  EXPECT_EQ(map.pixelOf(V(1, 0.1f, 1e-6f)), glm::ivec2(0, 3));
  EXPECT_EQ(map.pixelOf(V(1, -0.1f, -1e-6f)), glm::ivec2(15, 4));
  EXPECT_EQ(map.pixelOf(V(1, 0.1f, -1e-30f)).x, 15);  // phi rounds to 2 pi: u = 1, the last column
  // Not normalized: only the direction counts.
  EXPECT_EQ(map.pixelOf(V(0, 0, 5)), map.pixelOf(V(0, 0, 1)));
  // Every pixel centre maps back to its pixel (even and odd sizes), and uv -> direction -> uv is the identity.
  for (const glm::ivec2 size : {glm::ivec2(16, 8), glm::ivec2(7, 5)}) {
    const EnvironmentMap m(constantMap(size.x, size.y, Rgb(1.0f)), 1.0f, "constant");
    for (int y = 0; y < size.y; ++y)
      for (int x = 0; x < size.x; ++x) {
        const glm::vec2 uv{(x + 0.5f) / size.x, (y + 0.5f) / size.y};
        const glm::vec3 d = EnvironmentMap::uvToDirection(uv);
        EXPECT_NEAR(glm::length(d), 1.0f, 1e-6f);
        EXPECT_EQ(m.pixelOf(d), glm::ivec2(x, y)) << size.x << "x" << size.y;
        const glm::vec2 back = EnvironmentMap::directionToUv(d);
        EXPECT_NEAR(back.x, uv.x, 1e-6f);
        EXPECT_NEAR(back.y, uv.y, 1e-6f);
      }
  }
}

TEST(EnvironmentMap, EvalIsThePixelValueTimesScale) {
  const Image image = structuredMap();
  const EnvironmentMap map(image, 2.5f, "structured");
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const glm::vec3 d = EnvironmentMap::uvToDirection({(x + 0.5f) / image.width, (y + 0.5f) / image.height});
      const Rgb L = map.eval(d);
      for (int c = 0; c < 3; ++c) ASSERT_FLOAT_EQ(L[c], 2.5f * image.at(x, y, c)) << x << "," << y;
    }
  // Piecewise constant: anywhere inside a pixel gives its value.
  const glm::vec3 corner = EnvironmentMap::uvToDirection({(3 + 0.02f) / 24, (4 + 0.97f) / 12});
  EXPECT_EQ(map.eval(corner), map.pixel(3, 4));
  EXPECT_EQ(map.eval(glm::vec3(0.0f)), Rgb(0.0f));
  EXPECT_EQ(map.pdf(glm::vec3(std::nanf(""), 0, 1)), 0.0f);
}

TEST(EnvironmentMap, PdfIntegratesToOneOverTheSphere) {
  for (const auto& [name, image] : {std::pair{"structured", structuredMap()}, std::pair{"odd", structuredMap(9, 5)}}) {
    const EnvironmentMap map(image, 1.0f, name);
    // 3600 x 3600 midpoints: pixel edges fall between midpoints (both sizes divide 3600), so the
    // rule is exact up to its O(h^2) error in sin(theta).
    const double integral = integrateOverSphere([&](const glm::vec3& d) { return double(map.pdf(d)); }, 3600, 3600);
    EXPECT_NEAR(integral, 1.0, 2e-5) << name;
  }
}

TEST(EnvironmentMap, SampleReturnsPdfAndEvalOfItsDirection) {
  const EnvironmentMap map(structuredMap(), 1.0f, "structured");
  btf::Rng rng(5);
  int drawn = 0;
  for (int k = 0; k < 100'000; ++k) {
    const auto s = map.sample(rng.uniform2D());
    if (!s) continue;
    ++drawn;
    ASSERT_NEAR(glm::length(s->direction), 1.0f, 1e-5f);
    ASSERT_EQ(s->pdf, map.pdf(s->direction));
    ASSERT_EQ(s->radiance, map.eval(s->direction));
    ASSERT_GT(s->pdf, 0.0f);
    ASSERT_FALSE(s->radiance.isBlack());  // black pixels are never drawn
  }
  EXPECT_GE(drawn, 99'990);
  // The corners of [0,1)^2 too.
  for (const glm::vec2 u : {glm::vec2(0.0f), glm::vec2(0x1.fffffep-1f), glm::vec2(0.0f, 0x1.fffffep-1f)}) {
    const auto s = map.sample(u);
    ASSERT_TRUE(s.has_value());
    EXPECT_EQ(s->pdf, map.pdf(s->direction));
  }
}

TEST(EnvironmentMap, SamplingPassesChiSquare) {
  const EnvironmentMap map(structuredMap(), 1.0f, "structured");
  const btf::Chi2Result r = chi2OfMap(map, [&map](const glm::vec3& h) { return double(map.pdf(harnessToMap(h))); });
  EXPECT_TRUE(r.accepted) << r.message << " (1e6 draws, 20 x 40 cells, alpha = 0.01)";
  EXPECT_EQ(r.failed_samples, 0u);
  // The test has power: the same draws against the uniform density are rejected.
  const btf::Chi2Result wrong = chi2OfMap(map, [](const glm::vec3&) { return 1.0 / (4.0 * kPi); });
  EXPECT_FALSE(wrong.accepted) << wrong.message;
}

TEST(EnvironmentMap, MonteCarloThroughSampleAgreesWithMeanRadiance) {
  const Image image = structuredMap();
  const EnvironmentMap map(image, 3.0f, "structured");
  // meanRadiance from the definition, pixel by pixel: L * solid angle / (4 pi).
  double expected[3] = {0, 0, 0};
  for (int y = 0; y < image.height; ++y) {
    const double solid_angle = 2 * kPi / image.width * (std::cos(kPi * y / image.height) - std::cos(kPi * (y + 1) / image.height));
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < 3; ++c) expected[c] += 3.0 * image.at(x, y, c) * solid_angle / (4 * kPi);
  }
  const Rgb mean = map.meanRadiance();
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(mean[c], expected[c], 1e-5 * expected[c]);
  // E[L / pdf] / (4 pi) over draws of sample(): within 5 standard errors (and 1%).
  constexpr int kDraws = 400'000;
  btf::Rng rng(17);
  double sum[3] = {0, 0, 0}, sum_sq[3] = {0, 0, 0};
  for (int k = 0; k < kDraws; ++k) {
    const auto s = map.sample(rng.uniform2D());
    if (!s) continue;
    for (int c = 0; c < 3; ++c) {
      const double v = s->radiance[c] / s->pdf / (4 * kPi);
      sum[c] += v;
      sum_sq[c] += v * v;
    }
  }
  for (int c = 0; c < 3; ++c) {
    const double estimate = sum[c] / kDraws;
    const double standard_error = std::sqrt(std::max(0.0, sum_sq[c] / kDraws - estimate * estimate) / kDraws);
    EXPECT_NEAR(estimate, mean[c], 5 * standard_error + 1e-9) << "channel " << c;
    EXPECT_NEAR(estimate, mean[c], 0.01 * mean[c]) << "channel " << c;
  }
}

TEST(EnvironmentMap, ConstantMapIsSampledUniformly) {
  for (const glm::ivec2 size : {glm::ivec2(32, 16), glm::ivec2(5, 3), glm::ivec2(1, 1)}) {
    const EnvironmentMap map(constantMap(size.x, size.y, Rgb(0.3f, 0.6f, 0.9f)), 2.0f, "constant");
    const float uniform = float(1.0 / (4.0 * kPi));
    btf::Rng rng(23);
    for (int k = 0; k < 2000; ++k) {
      const auto s = map.sample(rng.uniform2D());
      ASSERT_TRUE(s.has_value());
      ASSERT_NEAR(s->pdf, uniform, 1e-5f * uniform) << size.x << "x" << size.y;
      ASSERT_EQ(s->radiance, Rgb(0.6f, 1.2f, 1.8f));
    }
    for (const glm::vec3 d : {glm::vec3(0, 1, 0), glm::vec3(0, -1, 0), glm::vec3(1, 0, 0), glm::vec3(-0.3f, 0.2f, -0.9f)})
      EXPECT_NEAR(map.pdf(d), uniform, 1e-5f * uniform);
    EXPECT_NEAR(map.meanRadiance().g, 1.2f, 1e-6f);
  }
}

TEST(EnvironmentMap, AllBlackMapSamplesUniformlyWithZeroRadiance) {
  const EnvironmentMap map(constantMap(8, 4, Rgb(0.0f)), 1.0f, "black");
  EXPECT_EQ(map.meanRadiance(), Rgb(0.0f));
  const auto s = map.sample({0.3f, 0.7f});
  ASSERT_TRUE(s.has_value());
  EXPECT_NEAR(s->pdf, 1.0 / (4.0 * kPi), 1e-7);
  EXPECT_TRUE(s->radiance.isBlack());
}

TEST(EnvironmentMap, OneBrightPixelTakesAlmostAllSamplesAndDimPixelsStayReachable) {
  constexpr int kWidth = 64, kHeight = 32;
  Image image = constantMap(kWidth, kHeight, Rgb(0.01f));
  const glm::ivec2 bright{40, 13}, dim{5, 30}, black{20, 20};
  for (int c = 0; c < 3; ++c) {
    image.at(bright.x, bright.y, c) = 1e4f;
    image.at(dim.x, dim.y, c) = 1e-9f;
    image.at(black.x, black.y, c) = 0.0f;
  }
  const EnvironmentMap map(image, 1.0f, "sun");
  const glm::vec3 bright_dir = EnvironmentMap::uvToDirection({(bright.x + 0.5f) / kWidth, (bright.y + 0.5f) / kHeight});
  const double bright_solid_angle =
      2 * kPi / kWidth * (std::cos(kPi * bright.y / kHeight) - std::cos(kPi * (bright.y + 1) / kHeight));
  const double p_bright = map.pdf(bright_dir) * bright_solid_angle;
  EXPECT_GT(p_bright, 0.99);
  constexpr int kDraws = 100'000;
  btf::Rng rng(29);
  int hits = 0;
  for (int k = 0; k < kDraws; ++k) {
    const auto s = map.sample(rng.uniform2D());
    ASSERT_TRUE(s.has_value());
    if (map.pixelOf(s->direction) == bright) {
      ++hits;
      EXPECT_EQ(s->radiance, Rgb(1e4f));
    }
  }
  EXPECT_NEAR(hits, kDraws * p_bright, 5 * std::sqrt(kDraws * p_bright * (1 - p_bright)));
  // The floor: a pixel 10^-7 of the background is still drawn with (at least) the floor's
  // weight, kSamplingFloor * mean luminance; a black pixel is never drawn.
  const glm::vec3 dim_dir = EnvironmentMap::uvToDirection({(dim.x + 0.5f) / kWidth, (dim.y + 0.5f) / kHeight});
  const double mean_luminance = map.meanRadiance().luminance();
  const float background_pdf = map.pdf(EnvironmentMap::uvToDirection({(dim.x + 1.5f) / kWidth, (dim.y + 0.5f) / kHeight}));
  EXPECT_GT(map.pdf(dim_dir), 0.0f);
  EXPECT_NEAR(map.pdf(dim_dir) / background_pdf, EnvironmentMap::kSamplingFloor * mean_luminance / 0.01, 1e-3);
  EXPECT_EQ(map.pdf(EnvironmentMap::uvToDirection({(black.x + 0.5f) / kWidth, (black.y + 0.5f) / kHeight})), 0.0f);
}

TEST(EnvironmentMap, RejectsBadFilesWithTheFileAndTheProblem) {
  btf::test::TempDir dir;
  auto expectFileError = [](const std::filesystem::path& path, const std::string& part) {
    try {
      EnvironmentMap::load(path, 1.0f);
      ADD_FAILURE() << "no error for " << path;
    } catch (const btf::FileError& e) {
      EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  expectFileError(dir / "missing.exr", "no such file");

  btf::writeImage(dir / "grey.exr", Image(8, 4, 1, 0.5f));
  expectFileError(dir / "grey.exr", "1 channel");

  auto writeWith = [&](const std::string& name, float value) {
    Image image = constantMap(16, 48, Rgb(0.5f));
    image.at(12, 40, 1) = value;
    btf::test::writeRawImage(dir / name, image);
    return dir / name;
  };
  expectFileError(writeWith("nan.exr", std::numeric_limits<float>::quiet_NaN()), "pixel (12, 40) channel 1 is NaN");
  expectFileError(writeWith("inf.exr", std::numeric_limits<float>::infinity()), "pixel (12, 40) channel 1 is infinite");
  expectFileError(writeWith("negative.exr", -0.25f), "pixel (12, 40) channel 1 is negative");

  // A good file loads; RGBA is fine (alpha ignored).
  Image rgba(8, 4, 4, 0.25f);
  btf::writeImage(dir / "rgba.exr", rgba);
  const EnvironmentMap map = EnvironmentMap::load(dir / "rgba.exr", 4.0f);
  EXPECT_EQ(map.width(), 8);
  EXPECT_EQ(map.height(), 4);
  EXPECT_NEAR(map.meanRadiance().r, 1.0f, 1e-6f);
  EXPECT_EQ(map.sourceName(), (dir / "rgba.exr").string());
}

TEST(EnvironmentMap, RejectsEmptyImagesAndBadScales) {
  try {
    EnvironmentMap(Image(0, 4, 3), 1.0f, "empty.exr");
    ADD_FAILURE() << "no error for an empty image";
  } catch (const btf::FileError& e) {
    EXPECT_NE(std::string(e.what()).find("empty.exr"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no pixels"), std::string::npos) << e.what();
  }
  const Image good = constantMap(4, 2, Rgb(1.0f));
  for (const float scale : {0.0f, -1.0f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    EXPECT_THROW(EnvironmentMap(good, scale, "good.exr"), btf::Error) << scale;
    EXPECT_THROW(EnvironmentMap::load("whatever.exr", scale), btf::Error) << scale;
  }
  // A finite value that the scale carries past the float range.
  EXPECT_THROW(EnvironmentMap(constantMap(4, 2, Rgb(3e38f)), 10.0f, "huge.exr"), btf::FileError);
}
