// Spectral .bsdf files: the fields each public loader reads (a table per loader, checked field by
// field against what the writer emits), the round trip of the spectra written by Jakob-Hanika
// upsampling (core/rgb_to_spectrum.h) through libbtf's spectral reader (CIE 1931, D65), and the
// reader's handling of spectral and RGB-only files.
#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "btf/core/error.h"
#include "btf/io/rgl_tensor.h"
#include "btf/material/ggx.h"
#include "btf/material/lambert.h"
#include "btf/material/material_difference.h"
#include "btf/material/rgl_acquisition.h"
#include "btf/material/rgl_brdf.h"
#include "support/test_support.h"

namespace {

using btf::Rgb;
using D = btf::TensorDtype;

// One field as a loader checks it. Dimensions: a number, or a symbol that must agree across the
// fields of one file: P = phi_i count, T = theta_i count, W = wavelength count, R = table
// resolution, * = any; `absent` fields must not be in the file.
struct LoaderField {
  const char* name;
  D dtype;
  std::vector<std::string> shape;
  bool absent = false;
};
struct Loader {
  const char* name;
  std::vector<LoaderField> fields;
};

// What each public loader reads before it accepts a file, from its source:
// - pbrt-v4: src/pbrt/bxdfs.cpp, MeasuredBRDF::Create (spectra + wavelengths; isotropic when
//   phi_i has <= 2 values).
// - Mitsuba 3, spectral variants: src/bsdfs/measured.cpp, Measured::Measured (a file with
//   `wavelengths` is spectral and read through `spectra`).
// - Mitsuba 3, RGB variants: the same constructor; `rgb` is read as the spectra with 3 channels,
//   and a file holding `wavelengths` is refused ("Measurements in spectral format require the use
//   of a spectral variant of Mitsuba!").
// - RGL brdf-loader, powitacq_rgb.inl (BRDF::BRDF): `rgb`; powitacq.inl: as pbrt-v4.
const std::vector<Loader>& loaders() {
  static const std::vector<Loader> l = {
      {"pbrt-v4 MeasuredBRDF / powitacq.inl",
       {{"description", D::UInt8, {"*"}},
        {"theta_i", D::Float32, {"T"}},
        {"phi_i", D::Float32, {"P"}},
        {"wavelengths", D::Float32, {"W"}},
        {"ndf", D::Float32, {"*", "*"}},
        {"sigma", D::Float32, {"*", "*"}},
        {"vndf", D::Float32, {"P", "T", "*", "*"}},
        {"luminance", D::Float32, {"P", "T", "R", "R"}},
        {"spectra", D::Float32, {"P", "T", "W", "R", "R"}},
        {"jacobian", D::UInt8, {"1"}}}},
      {"Mitsuba 3 measured, spectral variants",
       {{"description", D::UInt8, {"*"}},
        {"theta_i", D::Float32, {"T"}},
        {"phi_i", D::Float32, {"P"}},
        {"wavelengths", D::Float32, {"W"}},
        {"ndf", D::Float32, {"*", "*"}},
        {"sigma", D::Float32, {"*", "*"}},
        {"vndf", D::Float32, {"P", "T", "*", "*"}},
        {"luminance", D::Float32, {"P", "T", "R", "R"}},
        {"spectra", D::Float32, {"P", "T", "W", "R", "R"}},
        {"jacobian", D::UInt8, {"1"}}}},
      {"Mitsuba 3 measured, RGB variants",
       {{"description", D::UInt8, {"*"}},
        {"theta_i", D::Float32, {"T"}},
        {"phi_i", D::Float32, {"P"}},
        {"wavelengths", D::Float32, {"*"}, true},
        {"ndf", D::Float32, {"*", "*"}},
        {"sigma", D::Float32, {"*", "*"}},
        {"vndf", D::Float32, {"P", "T", "*", "*"}},
        {"luminance", D::Float32, {"P", "T", "R", "R"}},
        {"rgb", D::Float32, {"P", "T", "3", "R", "R"}},
        {"jacobian", D::UInt8, {"1"}}}},
      {"RGL powitacq_rgb.inl",
       {{"description", D::UInt8, {"*"}},
        {"theta_i", D::Float32, {"T"}},
        {"phi_i", D::Float32, {"P"}},
        {"ndf", D::Float32, {"*", "*"}},
        {"sigma", D::Float32, {"*", "*"}},
        {"vndf", D::Float32, {"P", "T", "*", "*"}},
        {"luminance", D::Float32, {"P", "T", "R", "R"}},
        {"rgb", D::Float32, {"P", "T", "3", "R", "R"}},
        {"jacobian", D::UInt8, {"1"}}}},
  };
  return l;
}

// Empty when the file passes the loader's checks, else what fails.
std::string problemsFor(const Loader& loader, const btf::TensorFile& file) {
  std::map<std::string, std::uint64_t> symbols;
  std::string problems;
  for (const LoaderField& want : loader.fields) {
    const btf::TensorField* f = file.find(want.name);
    if (want.absent) {
      if (f) problems += std::string(want.name) + " present; ";
      continue;
    }
    if (!f) {
      problems += std::string(want.name) + " missing; ";
      continue;
    }
    if (f->dtype != want.dtype) problems += std::string(want.name) + " dtype; ";
    if (f->shape.size() != want.shape.size()) {
      problems += std::string(want.name) + " rank; ";
      continue;
    }
    for (std::size_t k = 0; k < want.shape.size(); ++k) {
      const std::string& s = want.shape[k];
      if (s == "*") continue;
      if (std::isdigit(static_cast<unsigned char>(s[0]))) {
        if (f->shape[k] != std::stoull(s)) problems += std::string(want.name) + " dim " + std::to_string(k) + "; ";
      } else if (const auto [it, fresh] = symbols.emplace(s, f->shape[k]); !fresh && it->second != f->shape[k]) {
        problems += std::string(want.name) + " dim " + std::to_string(k) + " != " + s + "; ";
      }
    }
  }
  return problems;
}

std::shared_ptr<const btf::Material> copperGgx(float alpha) {
  return std::make_shared<btf::Ggx>(Rgb(0.05f, 0.04f, 0.02f), Rgb(0.95f, 0.64f, 0.54f), alpha, alpha);
}

TEST(RglSpectral, WrittenFilesPassEveryLoadersFieldChecks) {
  const btf::TensorFile spectral = btf::inMemoryTensorFile(btf::acquireRglFields(*copperGgx(0.3f)), "s.bsdf");
  btf::RglAcquisitionOptions rgb_only;
  rgb_only.spectral = false;
  const btf::TensorFile rgb = btf::inMemoryTensorFile(btf::acquireRglFields(*copperGgx(0.3f), rgb_only), "r.bsdf");
  for (const Loader& loader : loaders()) {
    const bool mitsuba_rgb = std::string(loader.name) == "Mitsuba 3 measured, RGB variants";
    const bool reads_spectra = std::string(loader.name).find("spectral") != std::string::npos ||
                               std::string(loader.name).find("pbrt") != std::string::npos;
    // The default (spectral) file: every loader but Mitsuba's RGB variants.
    EXPECT_EQ(problemsFor(loader, spectral).empty(), !mitsuba_rgb) << loader.name << ": " << problemsFor(loader, spectral);
    // The RGB-only file: the RGB readers, not the spectral ones.
    EXPECT_EQ(problemsFor(loader, rgb).empty(), !reads_spectra) << loader.name << ": " << problemsFor(loader, rgb);
  }
  // The checker itself fails on what a loader refuses.
  btf::TensorFile broken = spectral;
  for (auto& f : broken.fields)
    if (f.name == "spectra") f.shape[2] = 47;
  EXPECT_NE(problemsFor(loaders()[0], broken).find("spectra dim 2"), std::string::npos);
  // The wavelengths: 360 to 830 nm in 10 nm steps, the range pbrt-v4 samples.
  const auto wl = spectral.require("wavelengths", D::Float32, {48}).toFloats();
  EXPECT_EQ(wl.front(), 360.0f);
  EXPECT_EQ(wl.back(), 830.0f);
}

// The issue's round trip: the albedo of the spectral channels, integrated against the CIE 1931
// curves under D65 to linear sRGB (RglChannels::Spectra), within 1% of the source's at theta 0,
// 30, 60 and 75 deg (deterministic quadrature, material_difference.h), and within 1e-4 of the RGB
// channels' (what the upsampling alone changes).
TEST(RglSpectral, SpectralChannelsKeepTheAlbedoOfTheSource) {
  const std::vector<std::pair<std::string, std::shared_ptr<const btf::Material>>> sources = {
      {"ggx 0.1 copper", copperGgx(0.1f)},
      {"ggx 0.3 copper", copperGgx(0.3f)},
      {"lambert orange", std::make_shared<btf::Lambert>(Rgb(0.7f, 0.3f, 0.05f))},
      {"lambert blue", std::make_shared<btf::Lambert>(Rgb(0.05f, 0.1f, 0.6f))},
  };
  btf::MaterialDifferenceOptions at;
  at.theta_o_deg = {0.0f, 30.0f, 60.0f, 75.0f};
  at.pair_count = 20'000;
  for (const auto& [name, source] : sources) {
    const btf::TensorFile file = btf::inMemoryTensorFile(btf::acquireRglFields(*source), name + ".bsdf");
    const btf::RglBrdf spectral(file, btf::RglChannels::Spectra), rgb(file, btf::RglChannels::Rgb);
    const btf::MaterialDifference to_source = btf::compareMaterials(spectral, *source, at);
    EXPECT_LT(to_source.max_albedo_rel_error, 0.01) << name;
    const btf::MaterialDifference to_rgb = btf::compareMaterials(spectral, rgb, at);
    EXPECT_LT(to_rgb.max_albedo_rel_error, 1e-4) << name;
  }
}

TEST(RglSpectral, ReaderTakesSpectralOnlyFilesAndRefusesMissingTables) {
  const std::vector<btf::TensorField> fields = btf::acquireRglFields(*copperGgx(0.2f));
  std::vector<btf::TensorField> spectral_only;
  for (const auto& f : fields)
    if (f.name != "rgb") spectral_only.push_back(f);
  const btf::RglBrdf from_spectra(btf::inMemoryTensorFile(spectral_only, "spec.bsdf"));
  const btf::RglBrdf from_rgb(btf::inMemoryTensorFile(fields, "rgb.bsdf"));
  const glm::vec3 wo = btf::sphericalDirection(0.5f, 0.2f), wi = btf::sphericalDirection(0.6f, 3.0f);
  const Rgb a = from_spectra.eval(wi, wo), b = from_rgb.eval(wi, wo);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1e-4f * b.maxComponent());

  btf::RglAcquisitionOptions rgb_only;
  rgb_only.spectral = false;
  const btf::TensorFile no_spectra = btf::inMemoryTensorFile(btf::acquireRglFields(*copperGgx(0.2f), rgb_only), "r.bsdf");
  try {
    btf::RglBrdf m(no_spectra, btf::RglChannels::Spectra);
    FAIL() << "spectra read from an RGB-only file";
  } catch (const btf::FileError& e) {
    EXPECT_NE(std::string(e.what()).find("r.bsdf"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("has no field 'spectra'"), std::string::npos) << e.what();
  }
  // Wavelengths that do not cover the visible range are named.
  std::vector<btf::TensorField> narrow = spectral_only;
  for (auto& f : narrow)
    if (f.name == "wavelengths") {
      std::vector<double> wl(48);
      for (int k = 0; k < 48; ++k) wl[k] = 450 + k;
      f = btf::tensorField("wavelengths", D::Float32, {48}, wl);
    }
  try {
    btf::RglBrdf m(btf::inMemoryTensorFile(narrow, "narrow.bsdf"));
    FAIL() << "a spectrum of 450-497 nm accepted";
  } catch (const btf::FileError& e) {
    EXPECT_NE(std::string(e.what()).find("field 'wavelengths'"), std::string::npos) << e.what();
  }
}

}  // namespace
