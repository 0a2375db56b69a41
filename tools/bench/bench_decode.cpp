// `btf bench decode FILE.btfz`: how fast a compressed BTF gives measured samples at random
// (texel, view, light), one at a time (VqBtf::value) and through the stream call (VqBtf::values,
// blocks of 256), beside the eval of a one-lobe Lafortune model in the same run: the cheapest
// analytic model a renderer would use instead, and the peer of the compression targets. Random
// samples are the worst case (every lookup a chain of cache misses once the tables outgrow the
// caches); a renderer's coherent lookups only do better. One thread; each rate is the best of the
// repeats, since other processes only ever slow a run down.
#include "bench_decode.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "btf/compress/vq_btf.h"
#include "btf/core/error.h"
#include "btf/core/rng.h"
#include "btf/material/lafortune.h"
#include "btf/core/warp.h"

namespace btf::cli {
// Named after the file: the unity build compiles the commands together, and their helpers share
// names (Args, Row).
namespace bench_decode {
namespace {

using Clock = std::chrono::steady_clock;

struct Args {
  std::string input, material;
  std::uint64_t samples = 1 << 22;
  int repeats = 3;
  std::uint64_t seed = 1;
  bool json = false;
};

// Samples per second of one pass over n samples; the caller keeps the best.
template <class Pass>
double rate(std::size_t n, Pass pass) {
  const auto start = Clock::now();
  pass();
  return double(n) / std::max(std::chrono::duration<double>(Clock::now() - start).count(), 1e-12);
}

void runBenchDecode(const Args& a) {
  // 52 bytes per sample (the sample, two directions for the model, its decoded value): 2^25 is 1.7 GB.
  if (a.samples < 256 || a.samples > (std::uint64_t(1) << 25))
    throw Error("--samples must be in [256, 33554432] (one block of the stream call to 1.7 GB of samples)");
  if (a.repeats < 1) throw Error("--repeats must be at least 1");
  const VqBtf vq = VqBtf::read(a.input, a.material);
  const std::vector<int>& views = vq.views().views();
  const int width = vq.width(), height = vq.height();
  const std::size_t n = std::size_t(a.samples / 256 * 256);  // whole blocks

  // Uniform random samples over the texels, the views the file holds and the lights, and as many
  // uniform direction pairs for the model: drawn before timing.
  Rng rng(a.seed);
  auto pick = [&](int count) { return std::min(int(rng.uniform() * float(count)), count - 1); };
  std::vector<BtfSampleIndex> samples(n);
  for (BtfSampleIndex& s : samples)
    s = {pick(width), pick(height), views[std::size_t(pick(int(views.size())))], pick(kBtfDirectionCount)};
  std::vector<glm::vec3> wi(n), wo(n);
  for (std::size_t i = 0; i < n; ++i) {
    wi[i] = squareToUniformHemisphere(rng.uniform2D());
    wo[i] = squareToUniformHemisphere(rng.uniform2D());
  }
  // tests/bench/bench_btf.cpp's model (a glossy lobe of exponent 15 over a diffuse term), so that the
  // two report against one peer; the programs share no library where it could live.
  const Lafortune lafortune(Rgb(0.2f), {LafortuneLobe{Rgb(0.2f), {-0.6f, -0.6f, 0.55f}, 15.0f}});

  // What is timed must be right: the stream gives value()'s results bit for bit (its contract), and
  // the checksum sums what the samples decode to, so that it follows the file and the seed alone.
  std::vector<Rgb> decoded(n);
  vq.values(samples, decoded);
  double checksum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const BtfSampleIndex& s = samples[i];
    const Rgb v = vq.value(s.x, s.y, s.view, s.light);
    for (int c = 0; c < 3; ++c)
      if (std::bit_cast<std::uint32_t>(v[c]) != std::bit_cast<std::uint32_t>(decoded[i][c]))
        throw Error(a.input + ": values() differs from value() at texel (" + std::to_string(s.x) + ", " +
                    std::to_string(s.y) + "), view " + std::to_string(s.view) + ", light " + std::to_string(s.light));
    checksum += double(v.r) + double(v.g) + double(v.b);
  }

  // The passes sum a channel so that no call can be optimized away. The three measures take turns
  // within each repeat, so that a slow spell of the machine falls on all of them alike.
  double sink = 0.0, value_rate = 0.0, stream_rate = 0.0, model_rate = 0.0;
  std::vector<Rgb> block(256);
  for (int k = 0; k < a.repeats; ++k) {
    value_rate = std::max(value_rate, rate(n, [&] {
      for (const BtfSampleIndex& s : samples) sink += vq.value(s.x, s.y, s.view, s.light).g;
    }));
    stream_rate = std::max(stream_rate, rate(n, [&] {
      for (std::size_t i = 0; i < n; i += block.size()) {
        vq.values(std::span(samples.data() + i, block.size()), block);
        sink += block[0].g;
      }
    }));
    model_rate = std::max(model_rate, rate(n, [&] {
      for (std::size_t i = 0; i < n; ++i) sink += lafortune.eval(wi[i], wo[i], {}).g;
    }));
  }
  volatile double kept = sink;  // a volatile store: the timed passes' sums count as used
  (void)kept;
  const double table_mb = double(vq.lookupTableBytes()) / 1e6;

  if (a.json) {
    const nlohmann::json j = {{"file", a.input},     {"texels", {width, height}},      {"views", views.size()},
                              {"samples", n},        {"repeats", a.repeats},           {"table_MB", table_mb},
                              {"value_per_s", value_rate}, {"values_per_s", stream_rate}, {"lafortune_per_s", model_rate},
                              {"value_vs_lafortune", value_rate / model_rate},
                              {"values_vs_lafortune", stream_rate / model_rate}, {"checksum", checksum}};
    std::printf("%s\n", j.dump(2).c_str());
    return;
  }
  std::printf("%s: %d x %d texels, %zu views, decoded tables %.2f MB\n", a.input.c_str(), width, height, views.size(),
              table_mb);
  std::printf("%zu random (texel, view, light) samples, best of %d, one thread:\n", n, a.repeats);
  std::printf("  value()                 %8.2f M/s  %5.2fx one-lobe Lafortune\n", value_rate / 1e6, value_rate / model_rate);
  std::printf("  values(), blocks of 256 %8.2f M/s  %5.2fx one-lobe Lafortune\n", stream_rate / 1e6, stream_rate / model_rate);
  std::printf("  one-lobe Lafortune eval %8.2f M/s\n", model_rate / 1e6);
  std::printf("values() matched value() bit for bit on every sample; checksum of the decoded values %.9g\n", checksum);
}

}  // namespace
}  // namespace bench_decode

void addBenchDecodeCommand(CLI::App& bench) {
  auto args = std::make_shared<bench_decode::Args>();
  auto* cmd = bench.add_subcommand(
      "decode",
      "Measured samples per second from a .btfz at random (texel, view, light), one at a time and through the stream "
      "call, beside a one-lobe Lafortune eval in the same run");
  cmd->add_option("input", args->input, "A .btfz file")->required();
  cmd->add_option("--material", args->material, "The material of a .btfz database to read");
  cmd->add_option("--samples", args->samples, "Random samples per pass (whole blocks of 256)")->capture_default_str();
  cmd->add_option("--repeats", args->repeats, "Passes per measure; the best counts")->capture_default_str();
  cmd->add_option("--seed", args->seed, "Random seed of the samples")->capture_default_str();
  cmd->add_flag("--json", args->json, "Machine-readable output");
  cmd->callback([args] { bench_decode::runBenchDecode(*args); });
}

}  // namespace btf::cli
