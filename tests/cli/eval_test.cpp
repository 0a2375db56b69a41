// btf eval against the analytic model the table was generated from (datagen --eval).
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "cli_test_support.h"

namespace btf::test {
namespace {

using Angles = std::array<std::string, 4>;  // theta_i, phi_i, theta_o, phi_o in degrees

// Away from sharp peaks, so the comparison measures the lookup and not the sampling density.
const std::vector<Angles> kAngles = {{"0", "0", "0", "0"},      {"45", "90", "20", "270"}, {"40", "10", "50", "200"},
                                     {"60", "0", "60", "180"}, {"75", "30", "10", "120"}};

std::array<double, 3> rgb(const nlohmann::json& f) { return {f[0].get<double>(), f[1].get<double>(), f[2].get<double>()}; }

class EvalMatchesAnalytic : public testing::TestWithParam<std::string> {};

TEST_P(EvalMatchesAnalytic, WithinInterpolationError) {
  TempDir dir;
  const std::string table = (dir / "clean.binary").string();
  ASSERT_EQ(runDatagen({"--preset", GetParam(), "--clean", "-o", table}).exit_code, 0);
  // Interpolated lookup: linear in 1-degree cells of smooth lobes, well inside 2%. Nearest
  // lookup snaps to a cell corner (half a cell in each of three axes), so it may be several
  // percent off on a slope.
  const std::vector<std::pair<std::string, double>> lookups = {{"interpolated", 0.02}, {"nearest", 0.08}};
  for (const Angles& a : kAngles) {
    const CommandResult analytic = runDatagen({"--preset", GetParam(), "--clean", "--json", "--eval", a[0], a[1], a[2], a[3]});
    ASSERT_EQ(analytic.exit_code, 0) << analytic.output;
    const auto want = rgb(parseJsonOutput(analytic)["f"]);
    for (const auto& [lookup, tolerance] : lookups) {
      const CommandResult r = runBtf({"eval", table, "--theta-i", a[0], "--phi-i", a[1], "--theta-o", a[2],
                                      "--phi-o", a[3], "--lookup", lookup, "--json"});
      ASSERT_EQ(r.exit_code, 0) << r.output;
      const auto got = rgb(parseJsonOutput(r)["f"]);
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(got[c], want[c], tolerance * want[c] + 1e-5)
            << GetParam() << " " << lookup << " at " << a[0] << "," << a[1] << "," << a[2] << "," << a[3];
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Presets, EvalMatchesAnalytic, testing::Values("plastic-red", "rough-gold"),
                         [](const auto& info) {
                           std::string name = info.param;
                           for (char& c : name) if (c == '-') c = '_';
                           return name;
                         });

TEST(Eval, HalfDiffInputAgreesWithTheSameDirections) {
  TempDir dir;
  const std::string table = (dir / "t.binary").string();
  ASSERT_EQ(runDatagen({"--preset", "plastic-red", "--clean", "-o", table}).exit_code, 0);
  const CommandResult by_half_diff = runBtf({"eval", table, "--half-diff", "10", "20", "90", "--json"});
  ASSERT_EQ(by_half_diff.exit_code, 0) << by_half_diff.output;
  const nlohmann::json hd = parseJsonOutput(by_half_diff);
  // Evaluate again at the directions the half/diff input stands for (reported in the output).
  auto deg = [&](const char* key) { return std::to_string(hd[key].get<double>()); };
  const CommandResult by_directions = runBtf({"eval", table, "--theta-i", deg("theta_i_deg"), "--phi-i", deg("phi_i_deg"),
                                             "--theta-o", deg("theta_o_deg"), "--phi-o", deg("phi_o_deg"), "--json"});
  ASSERT_EQ(by_directions.exit_code, 0) << by_directions.output;
  const auto a = rgb(hd["f"]), b = rgb(parseJsonOutput(by_directions)["f"]);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], 1e-3 * a[c]);
  // theta_h = 10, theta_d = 20 at phi_d = 90 puts both directions at the same polar angle.
  EXPECT_NEAR(hd["theta_i_deg"].get<double>(), hd["theta_o_deg"].get<double>(), 1e-3);
}

TEST(Eval, JsonEchoesTheAnglesAsTyped) {
  TempDir dir;
  const std::string table = (dir / "t.binary").string();
  ASSERT_EQ(runDatagen({"--preset", "white-diffuse", "--clean", "-o", table}).exit_code, 0);
  const CommandResult r = runBtf({"eval", table, "--theta-i", "10", "--phi-i", "33.3", "--theta-o", "0.1", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // As typed, not through float: 33.3 as a float is 33.29999923706055.
  EXPECT_NE(r.output.find("\"theta_i_deg\": 10.0"), std::string::npos) << r.output;
  const nlohmann::json j = parseJsonOutput(r);
  EXPECT_EQ(j["phi_i_deg"].get<double>(), 33.3);
  EXPECT_EQ(j["theta_o_deg"].get<double>(), 0.1);
  EXPECT_EQ(j["phi_o_deg"].get<double>(), 0.0);
  EXPECT_EQ(j["lookup"], "interpolated");
}

TEST(Eval, RejectsAnglesOutsideTheHemisphere) {
  TempDir dir;
  const std::string table = (dir / "t.binary").string();
  ASSERT_EQ(runDatagen({"--preset", "white-diffuse", "--clean", "-o", table}).exit_code, 0);
  const CommandResult r = runBtf({"eval", table, "--theta-i", "120", "--theta-o", "10"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_LT(r.exit_code, 128);
  EXPECT_NE(r.output.find("--theta-i"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace btf::test
