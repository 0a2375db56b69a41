// `btf sample FILE --theta-o DEG --sampler NAME -n N -o out.png`: draws N samples for one outgoing
// direction, tests them against the sampler's pdf by chi-square and pictures histogram, pdf and
// difference.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/sampling/chi2.h"
#include "commands.h"
#include "material_input.h"
#include "sample_figure.h"
#include "btf/sampling/sampler_choice.h"
#include "sampling_measures.h"

namespace btf::cli {
namespace {

struct SampleOptions {
  std::string file, output, sampler = "dp-cdf", parameterization = "auto";
  float theta_o = 30.0f, phi_o = 0.0f;
  float epsilon = SamplerOptions{}.epsilon;
  float threshold = SamplerOptions{}.threshold;
  std::uint64_t count = 1'000'000;
  std::uint64_t seed = 1;
  bool json = false;
};

// Finer than the chi-square default (20 x 40) so the picture shows lobes; the test pools cells
// expecting fewer than 5 draws, so small N stays valid.
constexpr int kThetaBins = 40, kPhiBins = 80;
constexpr double kAlpha = 0.01;

void runSample(const SampleOptions& o) {
  const auto choice = parseSamplerChoice(o.sampler);
  if (!choice) throw Error("unknown sampler '" + o.sampler + "' (known: " + samplerChoiceNames() + ")");
  const auto parameterization = parseParameterization(o.parameterization);
  if (!parameterization) throw Error("unknown parameterization '" + o.parameterization + "' (known: auto, incident, half)");
  if (!(o.theta_o >= 0.0f && o.theta_o < 90.0f))
    throw Error("--theta-o must be in [0, 90) degrees (got " + std::to_string(o.theta_o) + ")");
  if (std::filesystem::path(o.output).extension() != ".png")
    throw FileError(o.output, "sample writes PNG images: give the output a .png name");
  std::shared_ptr<const Material> material = openMaterial(o.file);
  SamplerOptions sampler_options;
  sampler_options.epsilon = o.epsilon;
  sampler_options.threshold = o.threshold;
  sampler_options.parameterization = *parameterization;
  const std::shared_ptr<const Material> sampled = withSampler(*choice, material, sampler_options);

  const float to_radians = kPi / 180.0f;
  const glm::vec3 wo = sphericalDirection(o.theta_o * to_radians, o.phi_o * to_radians);
  Chi2Options chi2;
  chi2.theta_bins = kThetaBins;
  chi2.phi_bins = kPhiBins;
  chi2.sample_count = o.count;
  chi2.significance = kAlpha;
  chi2.seed = o.seed;
  const Chi2Result result = chi2TestMaterial(*sampled, wo, {}, chi2);
  const double samples_per_s = samplesPerSecond(*sampled, wo, o.count, o.seed);
  const auto* binned = dynamic_cast<const BinnedSampler*>(sampled.get());
  std::optional<double> stream_samples_per_s;
  if (binned) stream_samples_per_s = streamSamplesPerSecond(*binned, wo, o.count, o.seed);

  char header[256], footer[320];
  std::snprintf(header, sizeof header, "%s, sampler %s, theta_o %.1f, phi_o %.1f deg, N = %llu",
                std::filesystem::path(o.file).filename().string().c_str(), o.sampler.c_str(), o.theta_o, o.phi_o,
                static_cast<unsigned long long>(o.count));
  std::snprintf(footer, sizeof footer, "chi2 = %.1f, dof %d, p = %.4g at alpha = %.2g: %s; %.3g samples/s (one core)",
                result.statistic, result.degrees_of_freedom, result.p_value, kAlpha,
                result.accepted ? "accepted" : "REJECTED", samples_per_s);
  writeImage(o.output, renderSampleFigure(result, header, footer));

  if (o.json) {
    nlohmann::json j = {{"file", o.file},          {"sampler", o.sampler},
                        {"theta_o_deg", o.theta_o}, {"phi_o_deg", o.phi_o},
                        {"samples", o.count},      {"seed", o.seed},
                        {"chi2_statistic", result.statistic}, {"chi2_dof", result.degrees_of_freedom},
                        {"chi2_p", result.p_value}, {"alpha", kAlpha},
                        {"accepted", result.accepted}, {"failed_samples", result.failed_samples},
                        {"samples_per_s", samples_per_s}, {"output", o.output}};
    if (binned) {
      const SamplerStats stats = binned->stats();
      j["bytes"] = stats.bytes;
      j["full_cdf_bytes"] = stats.full_cdf_bytes;
      j["parameterization"] = stats.parameterization;
      if (std::isfinite(stats.auto_variance_incident)) {
        j["auto_relative_variance_incident"] = stats.auto_variance_incident;
        j["auto_relative_variance_half"] = stats.auto_variance_half;
      }
      j["stream_samples_per_s"] = *stream_samples_per_s;
    }
    std::printf("%s\n", j.dump(2).c_str());
    return;
  }
  std::printf("%s\n", result.message.c_str());
  std::printf("chi2 statistic %.2f, dof %d, p-value %.4g (alpha %.2g): %s\n", result.statistic,
              result.degrees_of_freedom, result.p_value, kAlpha, result.accepted ? "accepted" : "rejected");
  if (binned) {
    const SamplerStats stats = binned->stats();
    std::printf("parameterization %s", stats.parameterization.c_str());
    if (std::isfinite(stats.auto_variance_incident))
      std::printf(" (auto: relative variance of f cos / pdf, incident %.4g, half %.4g)", stats.auto_variance_incident,
                  stats.auto_variance_half);
    std::printf("; tables %zu bytes (%.3f of the full CDF)\n", stats.bytes,
                double(stats.bytes) / double(std::max<std::size_t>(stats.full_cdf_bytes, 1)));
  }
  std::printf("samples/s %.4g (one core, direction + pdf)\n", samples_per_s);
  if (stream_samples_per_s)
    std::printf("samples/s %.4g through the stream call (one core, blocks of 256)\n", *stream_samples_per_s);
  std::printf("wrote %s\n", o.output.c_str());
}

}  // namespace

void registerSampleCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("sample", "Draw N samples for one outgoing direction, chi-square test them against the "
                                           "sampler's pdf, and write a PNG of histogram, pdf and difference");
  auto o = std::make_shared<SampleOptions>();
  cmd->add_option("FILE", o->file, "Measured material (.binary MERL, .exr from btf convert, .bsdf RGL, .json btf fit or .octree)")->required();
  cmd->add_option("--theta-o", o->theta_o, "Outgoing zenith angle (deg, [0, 90))")->required();
  cmd->add_option("--phi-o", o->phi_o, "Outgoing azimuth (deg)")->capture_default_str();
  cmd->add_option("--sampler", o->sampler, "One of: " + samplerChoiceNames() + " (material: the file's own sampler)")
      ->capture_default_str();
  cmd->add_option("--epsilon", o->epsilon, "DP-CDF tolerance")->check(CLI::NonNegativeNumber)->capture_default_str();
  cmd->add_option("--parameterization", o->parameterization,
                  "Tables over the incident direction, over the half vector, or auto (measures both)")
      ->check(CLI::IsMember({"auto", "incident", "half"}))->capture_default_str();
  cmd->add_option("--threshold", o->threshold, "Quadtree subdivision threshold (max/mean)")
      ->check(CLI::PositiveNumber)->capture_default_str();
  cmd->add_option("-n,--samples", o->count, "Number of draws")->check(CLI::Range(std::uint64_t(1000), std::uint64_t(1e9)))
      ->capture_default_str();
  cmd->add_option("--seed", o->seed, "Random seed")->capture_default_str();
  cmd->add_option("-o,--output", o->output, "Output PNG, written atomically")->required();
  cmd->add_flag("--json", o->json, "Print the results as JSON");
  cmd->callback([o] { runSample(*o); });
}

}  // namespace btf::cli
