// The RGL writer: tensor_file encoding, virtual acquisition (material/rgl_acquisition.h) read back
// by RglBrdf, the dj-warp sampler, and bad input.
//
// Accuracy bounds are those the format's default resolutions reach (8 incidence angles, 32 x 32
// tables; `btf bench rgl-writer` measures every material of the list and how finer resolutions
// converge). Chi-square tests: 100,000 draws per view, significance 0.01, fixed seeds (an outcome
// is deterministic: a chance rejection would fail every run, never flake).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/core/rng.h"
#include "btf/io/rgl_tensor.h"
#include "btf/material/ggx.h"
#include "btf/material/lambert.h"
#include "btf/material/material_difference.h"
#include "btf/material/rgl_acquisition.h"
#include "btf/material/rgl_brdf.h"
#include "btf/material/ward.h"
#include "btf/sampling/chi2.h"
#include "btf/sampling/rgl_warp_sampler.h"
#include "btf/sampling/sampler_choice.h"
#include "support/test_support.h"

namespace {

using btf::Rgb;

std::shared_ptr<const btf::Material> ggx(float alpha) {
  return std::make_shared<btf::Ggx>(Rgb(0.05f, 0.04f, 0.02f), Rgb(0.95f, 0.64f, 0.54f), alpha, alpha);
}

btf::RglBrdf writtenAndRead(const btf::Material& m, const btf::RglAcquisitionOptions& o = {}) {
  return btf::RglBrdf(btf::inMemoryTensorFile(btf::acquireRglFields(m, o), "written.bsdf"));
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const btf::Error& e) {
    return e.what();
  }
  return "";
}

TEST(TensorWriter, WritesWhatTheReaderReadsFieldForFieldWithAlignedData) {
  const std::vector<double> values = {0.5, -1.25, 3.0, 1e-3, 7.0, 8.0};
  const std::vector<double> bytes = {1, 2, 255};
  const std::vector<btf::TensorField> fields = {
      btf::tensorTextField("description", "a test"),
      btf::tensorField("values", btf::TensorDtype::Float32, {2, 3}, values),
      btf::tensorField("flags", btf::TensorDtype::UInt8, {3}, bytes),
      btf::tensorField("wide", btf::TensorDtype::Float64, {1, 1, 6}, values)};
  btf::test::TempDir dir;
  const auto path = dir / "t.bsdf";
  btf::writeTensorFile(path, fields);
  const btf::TensorFile back = btf::readTensorFile(path);
  ASSERT_EQ(back.fields.size(), fields.size());
  for (std::size_t k = 0; k < fields.size(); ++k) {
    EXPECT_EQ(back.fields[k].name, fields[k].name);
    EXPECT_EQ(back.fields[k].dtype, fields[k].dtype);
    EXPECT_EQ(back.fields[k].shape, fields[k].shape);
    EXPECT_EQ(back.fields[k].bytes, fields[k].bytes);
    EXPECT_EQ(back.fields[k].offset % 8, 0u) << fields[k].name;  // as the RGL database's files
  }
  EXPECT_EQ(back.fields[1].toFloats()[1], -1.25f);
  EXPECT_EQ(back.fields[0].toText(), "a test");
  EXPECT_EQ(back.file_size, btf::encodeTensorFile(fields).size());
}

TEST(TensorWriter, RefusesDuplicateNamesValuesThatDoNotFitAndShortData) {
  const std::vector<double> three = {1, 2, 3};
  const auto a = btf::tensorField("a", btf::TensorDtype::Float32, {3}, three);
  EXPECT_NE(errorOf([&] { btf::encodeTensorFile({a, a}); }).find("'a' appears twice"), std::string::npos);
  EXPECT_NE(errorOf([&] { btf::tensorField("b", btf::TensorDtype::Float32, {2, 2}, three); }).find("needs 4 values, got 3"),
            std::string::npos);
  const std::vector<double> big = {256};
  EXPECT_NE(errorOf([&] { btf::tensorField("c", btf::TensorDtype::UInt8, {1}, big); }).find("is not a u8 value"),
            std::string::npos);
  auto cut = a;
  cut.bytes.pop_back();
  EXPECT_NE(errorOf([&] { btf::encodeTensorFile({cut}); }).find("holds 11 bytes, not 12"), std::string::npos);
}

// Names, dtypes, shapes and order as the RGL database's own files hold them (test_rgl_spectral.cpp
// checks them against each public loader's list).
TEST(RglAcquisition, FieldsAreThoseOfTheRglDatabaseFiles) {
  const std::vector<btf::TensorField> fields = btf::acquireRglFields(*ggx(0.3f));
  std::vector<std::string> names;
  for (const auto& f : fields) names.push_back(f.name);
  EXPECT_EQ(names, (std::vector<std::string>{"version", "description", "phi_i", "theta_i", "sigma", "ndf", "vndf",
                                             "luminance", "rgb", "wavelengths", "spectra", "jacobian", "valid"}));
  const btf::TensorFile file = btf::inMemoryTensorFile(fields, "g.bsdf");
  using D = btf::TensorDtype;
  EXPECT_EQ(file.require("version", D::UInt32, {2}).toFloats(), (std::vector<float>{1, 0}));
  file.require("description", D::UInt8, {-1});
  file.require("phi_i", D::Float32, {1});
  const auto theta = file.require("theta_i", D::Float32, {8}).toFloats();
  file.require("sigma", D::Float32, {2, 128});
  file.require("ndf", D::Float32, {2, 128});
  file.require("vndf", D::Float32, {1, 8, 128, 128});
  file.require("luminance", D::Float32, {1, 8, 32, 32});
  file.require("rgb", D::Float32, {1, 8, 3, 32, 32});
  file.require("wavelengths", D::Float32, {48});
  file.require("spectra", D::Float32, {1, 8, 48, 32, 32});
  EXPECT_EQ(file.require("jacobian", D::UInt8, {1}).bytes[0], std::byte{1});
  file.require("valid", D::UInt8, {8 * 32 * 32 / 8});
  // From the normal to the horizon, strictly increasing.
  EXPECT_EQ(theta.front(), 0.0f);
  EXPECT_NEAR(theta.back(), btf::kHalfPi, 1e-6f);
  for (std::size_t k = 1; k < theta.size(); ++k) EXPECT_GT(theta[k], theta[k - 1]);
  // The NDF is normalized: the projected area at the normal is 1.
  EXPECT_NEAR(file.require("sigma", D::Float32, {2, 128}).toFloats()[0], 1.0f, 1e-6f);
}

TEST(RglAcquisition, WrittenGgxAgreesWithItsSourceFromRoughToNearMirror) {
  for (const float alpha : {0.05f, 0.1f, 0.3f, 0.5f}) {
    const auto source = ggx(alpha);
    const btf::MaterialDifference d = btf::compareMaterials(writtenAndRead(*source), *source);
    EXPECT_LT(d.fcos_rel_rmse, 0.03) << "alpha " << alpha;
    EXPECT_LT(d.max_albedo_rel_error, 0.01) << "alpha " << alpha;
  }
}

// Lambert is this parameterization's hard case at 8 incidence angles (its retrieved NDF is broad and
// the table between the angles interpolates a varying weight): the bound is what the format
// reaches, and finer angles converge.
TEST(RglAcquisition, WrittenLambertKeepsItsAlbedoAndConvergesWithMoreIncidenceAngles) {
  const btf::Lambert lambert(Rgb(0.8f));
  const btf::MaterialDifference coarse = btf::compareMaterials(writtenAndRead(lambert), lambert);
  EXPECT_LT(coarse.max_albedo_rel_error, 0.01);
  EXPECT_LT(coarse.fcos_rel_rmse, 0.04);
  btf::RglAcquisitionOptions fine;
  fine.theta_i_count = 16;
  fine.resolution = 64;
  const btf::MaterialDifference better = btf::compareMaterials(writtenAndRead(lambert, fine), lambert);
  EXPECT_LT(better.fcos_rel_rmse, 0.7 * coarse.fcos_rel_rmse);
}

TEST(RglAcquisition, WrittenFilesWarpPassesChiSquareAtFourViews) {
  btf::Chi2Options chi2;
  chi2.sample_count = 100'000;
  for (const auto& m : {ggx(0.1f), std::shared_ptr<const btf::Material>(std::make_shared<btf::Lambert>(Rgb(0.5f)))}) {
    const btf::RglBrdf written = writtenAndRead(*m);
    for (const float theta : {0.0f, 30.0f, 60.0f, 80.0f}) {
      const btf::Chi2Result r = btf::chi2TestMaterial(written, btf::sphericalDirection(glm::radians(theta), 0.4f), {}, chi2);
      EXPECT_GT(r.p_value, chi2.significance) << m->name() << " theta_o " << theta;
    }
  }
}

// Re-measured on its own parameterization, an RGL file comes back to float rounding.
TEST(RglAcquisition, SharedRglFilesWrittenAgainAgreeWithTheOriginals) {
  for (const std::string& stem : btf::test::kRglFiles) {
    const btf::TensorFile original = btf::readTensorFile(btf::test::rglPath(stem));
    const btf::RglBrdf source(original);
    btf::RglAcquisitionOptions o;
    o.resolution = source.resolution();
    o.parameterization = &original;
    const btf::MaterialDifference d = btf::compareMaterials(writtenAndRead(source, o), source);
    EXPECT_LT(d.fcos_rel_rmse, 1e-4) << stem;
    EXPECT_LT(d.max_albedo_rel_error, 1e-4) << stem;
  }
}

TEST(RglAcquisition, IsDeterministic) {
  const auto m = ggx(0.2f);
  EXPECT_EQ(btf::encodeTensorFile(btf::acquireRglFields(*m)), btf::encodeTensorFile(btf::acquireRglFields(*m)));
}

// A material that returns a fixed value everywhere: NaN, negative or zero.
class ConstantMaterial final : public btf::Material {
 public:
  explicit ConstantMaterial(float v) : v_(v) {}
  Rgb eval(const glm::vec3&, const glm::vec3&, glm::vec2) const override { return Rgb(v_); }
  std::optional<btf::BsdfSample> sample(const glm::vec3&, glm::vec2, glm::vec2) const override { return std::nullopt; }
  float pdf(const glm::vec3&, const glm::vec3&, glm::vec2) const override { return 0; }
  std::string name() const override { return "constant"; }

 private:
  float v_;
};

TEST(RglAcquisition, RefusesAnisotropicMaterialsBadResolutionsAndBadValues) {
  const btf::Ward ward(Rgb(0.1f), Rgb(0.6f), 0.08f, 0.35f);
  EXPECT_NE(errorOf([&] { btf::acquireRglFields(ward); }).find("is anisotropic"), std::string::npos);
  btf::RglAcquisitionOptions o;
  o.resolution = 2;
  EXPECT_NE(errorOf([&] { btf::acquireRglFields(*ggx(0.3f), o); }).find("luminance/RGB resolution must be in [4, 256], not 2"),
            std::string::npos);
  o = {};
  o.theta_i_count = 1;
  EXPECT_NE(errorOf([&] { btf::acquireRglFields(*ggx(0.3f), o); }).find("theta_i"), std::string::npos);
  const std::string nan = errorOf([] { btf::acquireRglFields(ConstantMaterial(std::numeric_limits<float>::quiet_NaN())); });
  EXPECT_NE(nan.find("constant returns f = (nan"), std::string::npos) << nan;
  EXPECT_NE(nan.find("finite and non-negative"), std::string::npos) << nan;
  EXPECT_NE(errorOf([] { btf::acquireRglFields(ConstantMaterial(-1.0f)); }).find("returns f = (-1"), std::string::npos);
}

// A black material has nothing to find an NDF from; the file stays readable and reflects nothing.
TEST(RglAcquisition, BlackMaterialGivesAReadableFileThatReflectsNothing) {
  const btf::RglBrdf written = writtenAndRead(ConstantMaterial(0.0f));
  const glm::vec3 wo = btf::sphericalDirection(0.5f, 0.0f);
  EXPECT_EQ(written.eval(btf::sphericalDirection(0.4f, 3.0f), wo).luminance(), 0.0f);
}

TEST(RglWarpSampler, SamplesTheMaterialThroughItsWrittenWarpWithItsOwnEval) {
  const auto source = ggx(0.15f);
  const auto sampled = btf::withSampler(btf::SamplerChoice::DjWarp, source, {});
  EXPECT_EQ(btf::samplerTableBytes(*sampled), btf::encodeTensorFile(btf::acquireRglFields(*source)).size());
  const glm::vec3 wo = btf::sphericalDirection(0.7f, 1.0f), wi = btf::sphericalDirection(0.6f, 4.0f);
  EXPECT_EQ(sampled->eval(wi, wo).r, source->eval(wi, wo).r);
  btf::Chi2Options chi2;
  chi2.sample_count = 100'000;
  const btf::Chi2Result r = btf::chi2TestMaterial(*sampled, wo, {}, chi2);
  EXPECT_GT(r.p_value, chi2.significance);
  // sample() returns pdf() of its direction, and the weight f cos / pdf of the source's f.
  btf::Rng rng(3);
  int drawn = 0;
  for (int k = 0; k < 1000; ++k) {
    const auto s = sampled->sample(wo, {}, rng.uniform2D());
    if (!s) continue;
    ++drawn;
    EXPECT_FLOAT_EQ(s->pdf, sampled->pdf(s->wi, wo));
    EXPECT_NEAR(s->weight.g, source->eval(s->wi, wo).g * s->wi.z / s->pdf, 1e-4f * (1 + s->weight.g));
  }
  EXPECT_GT(drawn, 900);
}

}  // namespace
