// `btf bench compressibility [-o DIR]`: how far the synthetic BTFs of `btf-datagen btf` and measured
// BTFs (--inputs, a centred window of --size texels) can be compressed at all, whatever the method
// (compress/compressibility.h): nearest-neighbour texel distances, the greedy texel codebook (the
// most texel reuse any scaled-codebook VQ can find) and the rank a linear basis needs, per
// tolerance. --max-view-theta keeps the views up to an elevation (0: the θv = 0 view alone, to set
// a synthetic BTF beside a measured one-view slice). The patterns are streamed from the generator
// (each view is read once).
//   DIR/compressibility.csv  one row per (pattern, epsilon); the nearest-neighbour columns repeat;
//                            seconds = generating the pattern's views + the analysis
//   DIR/compressibility_nearest.dat  per pattern, every texel's nearest-texel distance, ascending,
//                            with the fraction of texels at or below it (the empirical CDF)
//   DIR/compressibility_rank.dat     per pattern, the relative tail energy left by rank k, k = 0..min(T, D)
//   DIR/compressibility_nearest.png/.svg, compressibility_rank.png/.svg and compressibility_charts.gp
//                            (gnuplot, tools/cli/support/gnuplot_charts.h; skipped with a message without it)
// The .dat files hold one block per pattern, blocks separated by two blank lines (gnuplot `index`),
// each opened by a "# pattern NAME" comment.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "bench_compressibility.h"
#include "btf/compress/compressibility.h"
#include "btf/core/error.h"
#include "btf/io/atomic_file.h"
#include "btf/io/btf_images.h"
#include "btf/io/btf_subset.h"
#include "btf/material/registry.h"
#include "btf_patterns.h"
#include "camera_btf.h"
#include "comma_list.h"
#include "gnuplot_charts.h"
#include "synthetic_btf.h"

namespace btf::cli {
namespace {

struct Args {
  std::string output = "bench-compressibility";
  std::string patterns = "fabric,stones,paint,leather";
  int size = 32;
  std::uint64_t seed = 1;
  CompressibilityOptions analysis;
  std::string inputs;           // measured BTF image folders, comma-separated
  float max_view_theta = 75.0f;  // keep the views up to this elevation (degrees)
  // A camera in front of the synthetic patterns (synthetic/camera_btf.h): white is the pattern's
  // 99th percentile over its first view held, times camera_white.
  synthetic::CameraOptions camera = [] {
    synthetic::CameraOptions c;
    c.quantize = true;  // as a camera stores them, unless --camera-float
    return c;
  }();
  float camera_white = 0.0f;  // 0: no camera
};

// The views of `held` up to max_theta_deg, or a btf::Error naming the source when there are none.
BtfViewSet viewsUpTo(const BtfSource& source, float max_theta_deg) {
  std::vector<int> kept;
  for (const int v : source.views().views())
    if (source.directions().viewAngles(v).theta_deg <= max_theta_deg + 1e-3f) kept.push_back(v);
  if (kept.empty())
    throw Error(source.name() + " holds no view up to theta " + std::to_string(max_theta_deg) + " (it holds " +
                source.views().describe() + ")");
  return BtfViewSet(std::move(kept));
}

struct PatternResult {
  std::string pattern;
  int size = 0;
  CompressibilityReport report;
  double seconds = 0;
};

void writeCsv(const std::filesystem::path& path, const std::vector<PatternResult>& results) {
  writeFileAtomically(path, [&](std::ofstream& out) {
    out << "pattern,size,texels,directions,nn_p10,nn_p25,nn_p50,nn_p75,nn_p90,nn_max,nn_rel_error,epsilon,"
           "greedy_entries,greedy_rel_error,reuse_factor,rank,rank_rel_error,ratio_u8_bound,seconds\n";
    for (const PatternResult& p : results) {
      const CompressibilityReport& r = p.report;
      for (const CompressibilityAtEpsilon& a : r.at_epsilon)
        out << p.pattern << ',' << p.size << ',' << r.texels << ',' << r.directions << ',' << r.nn_p10 << ','
            << r.nn_p25 << ',' << r.nn_p50 << ',' << r.nn_p75 << ',' << r.nn_p90 << ',' << r.nn_max << ','
            << r.nn_rel_error << ',' << a.epsilon << ',' << a.greedy_entries << ',' << a.greedy_rel_error << ','
            << double(r.texels) / a.greedy_entries << ',' << a.rank << ',' << a.rank_rel_error << ','
            << a.ratio_u8_bound << ',' << p.seconds << '\n';
    }
  });
}

// The empirical CDF of the nearest-texel distance: "distance fraction" rows, distances ascending,
// fraction = share of texels whose nearest other texel is at that distance or closer.
std::string nearestCdf(const CompressibilityReport& r) {
  std::vector<double> sorted = r.nearest_distance;
  std::sort(sorted.begin(), sorted.end());
  std::ostringstream out;
  for (std::size_t i = 0; i < sorted.size(); ++i) out << sorted[i] << ' ' << double(i + 1) / sorted.size() << '\n';
  return out.str();
}

// The error curve of the best linear basis: "rank tail" rows for k = 0..min(T, D), the report's
// rank_rel_error (compressibility.h, measure 3), so it crosses each epsilon at the reported rank.
std::string rankTail(const CompressibilityReport& r) {
  std::ostringstream out;
  for (std::size_t k = 0; k < r.rank_rel_error.size(); ++k) out << k << ' ' << r.rank_rel_error[k] << '\n';
  return out.str();
}

// One block per pattern as described at the top of the file.
void writeBlocks(const std::filesystem::path& path, const std::string& columns, const std::vector<PatternResult>& results,
                 const std::vector<std::string>& blocks) {
  writeFileAtomically(path, [&](std::ofstream& out) {
    for (std::size_t i = 0; i < results.size(); ++i) {
      if (i) out << "\n\n";
      out << "# pattern " << results[i].pattern << " (" << results[i].report.texels << " texels, "
          << results[i].report.directions << " directions): " << columns << '\n' << blocks[i];
    }
  });
}

// A two-line gnuplot title.
std::string title(const std::string& first, const std::string& second) {
  return "set title " + tools::gnuplotQuote(first) + " . \"\\n\" . " + tools::gnuplotQuote(second) + '\n';
}

tools::GnuplotOutcome drawCharts(const std::filesystem::path& folder, const Args& args,
                                 const std::vector<PatternResult>& results, const std::vector<std::string>& nearest,
                                 const std::vector<std::string>& rank) {
  std::ostringstream data;
  for (std::size_t i = 0; i < results.size(); ++i) {
    data << "$nearest" << i << " << EOD\n" << nearest[i] << "EOD\n";
    data << "$rank" << i << " << EOD\n" << rank[i] << "EOD\n";
  }
  const CompressibilityReport& first = results.front().report;
  std::ostringstream what;
  what << args.size << " x " << args.size << " = " << first.texels << " texels per BTF, luminance at "
       << (args.analysis.directions > 0 ? "up to " + std::to_string(args.analysis.directions) + " sampled" : "all")
       << " (view, light) pairs of the views held"
       << (args.max_view_theta < 75.0f ? " up to theta " + std::to_string(int(args.max_view_theta)) : "")
       << ", seed " << args.seed;
  // Log axes cannot show 0. Distances below the left edge (texels of zero luminance, d = 0) are
  // drawn at the edge, so every texel still counts in the CDF; a tail of exactly 0 (k = rank of the
  // matrix) is left out, the segments towards tiny tails are clipped at the bottom edge.
  double low = 1e-3;
  for (double e : args.analysis.epsilons) low = std::min(low, e / 3);
  std::size_t max_rank = 1;
  for (const PatternResult& p : results) max_rank = std::max(max_rank, p.report.singular_values.size());
  std::ostringstream near_body, rank_body;
  near_body << title("Nearest other texel: fraction of texels whose nearest other texel is within distance x",
                     what.str())
            << "set logscale x\nset xrange [" << low << ":1]\nset yrange [0:1]\n"
            << "set xlabel 'x = scale-optimal relative distance min_s |a - s b| / |a| = sqrt(1 - cos^2(a, b)) "
               "between luminance vectors (log scale)'\n"
            << "set ylabel 'fraction of texels with nearest-texel distance <= x'\n";
  rank_body << title("Linear basis: relative error of the best rank-k model (Eckart-Young tail energy)", what.str())
            << "set logscale y\nset yrange [" << low << ":1]\nset xrange [0:" << max_rank << "]\n"
            << "set xlabel 'rank k (basis vectors kept, luminance only)'\n"
            << "set ylabel 'sqrt(sum_{i>k} s_i^2 / sum_i s_i^2) (log scale)'\n";
  for (double e : args.analysis.epsilons) {
    std::ostringstream label_text;
    label_text << "epsilon " << e;
    const std::string label = tools::gnuplotQuote(label_text.str());
    near_body << "set arrow from first " << e << ", graph 0 to first " << e << ", graph 1 nohead dt 2 lc rgb 'gray40'\n"
              << "set label " << label << " at first " << e << ", graph 0.98 rotate by 90 right offset -1.3,0 "
              << "tc rgb 'gray30' front\n";
    rank_body << "set arrow from graph 0, first " << e << " to graph 1, first " << e << " nohead dt 2 lc rgb 'gray40'\n"
              << "set label " << label << " at graph 0.99, first " << e << " right offset 0,0.6 tc rgb 'gray30' front\n";
  }
  near_body << "plot ";
  rank_body << "plot ";
  for (std::size_t i = 0; i < results.size(); ++i) {
    const std::string name = tools::gnuplotQuote(results[i].pattern);
    near_body << (i ? ", " : "") << "$nearest" << i << " using ($1 < " << low << " ? " << low
              << " : $1):2 with steps lw 2 title " << name;
    rank_body << (i ? ", " : "") << "$rank" << i << " using 1:($2 > 0 ? $2 : NaN) with lines lw 2 title " << name;
  }
  near_body << '\n';
  rank_body << '\n';
  return tools::drawGnuplotCharts(folder, "compressibility_charts.gp", data.str(),
                                  {{"compressibility_nearest", near_body.str()}, {"compressibility_rank", rank_body.str()}});
}

void printTables(const std::vector<PatternResult>& results) {
  std::printf("\nNearest other texel, scale-optimal relative distance sqrt(1 - cos^2) of the luminance vectors:\n");
  std::printf("%-8s %5s %6s %5s %7s %7s %7s %7s %7s %12s %8s\n", "pattern", "size", "texels", "dirs", "p10", "p25",
              "p50", "p75", "p90", "nn_rel_error", "seconds");
  for (const PatternResult& p : results) {
    const CompressibilityReport& r = p.report;
    std::printf("%-8s %5d %6d %5d %7.4f %7.4f %7.4f %7.4f %7.4f %12.4f %8.1f\n", p.pattern.c_str(), p.size, r.texels,
                r.directions, r.nn_p10, r.nn_p25, r.nn_p50, r.nn_p75, r.nn_p90, r.nn_rel_error, p.seconds);
  }
  std::printf("\nPer tolerance: greedy texel codebook (upper bound on level-3 reuse) and the rank of a linear basis\n"
              "(ratio_u8_bound: rank-k float16 model, luminance only, optimistic; see compressibility.h):\n");
  std::printf("%-8s %5s %8s %14s %16s %12s %6s %14s %14s\n", "pattern", "size", "epsilon", "greedy_entries",
              "greedy_rel_error", "reuse_factor", "rank", "rank_rel_error", "ratio_u8_bound");
  for (const PatternResult& p : results)
    for (const CompressibilityAtEpsilon& a : p.report.at_epsilon)
      std::printf("%-8s %5d %8g %14d %16.4f %12.2f %6d %14.4f %14.1f\n", p.pattern.c_str(), p.size, a.epsilon,
                  a.greedy_entries, a.greedy_rel_error, double(p.report.texels) / a.greedy_entries, a.rank,
                  a.rank_rel_error, a.ratio_u8_bound);
  if (!results.empty()) {
    // The largest rank whose bound still reaches ratio_u8 1000 (the project's target) at this size.
    const int texels = results.front().report.texels;
    int k = 0;
    while (rankRatioU8Bound(texels, k + 1) >= 1000) ++k;
    if (k > 0)
      std::printf("\nratio_u8 >= 1000 needs rank <= %d at %d texels (rank-k float16 model, bound above).\n", k, texels);
    else
      std::printf("\nNo rank reaches ratio_u8 1000 at %d texels: the float16 basis alone is larger.\n", texels);
  }
}

void runBenchCompressibility(const Args& args) {
  const std::vector<std::string> patterns = splitCommaList(args.patterns), inputs = splitCommaList(args.inputs);
  if (patterns.empty() && inputs.empty()) throw Error("bench compressibility: no --patterns and no --inputs");
  std::vector<synthetic::BtfPattern> parsed;
  for (const std::string& name : patterns) parsed.push_back(synthetic::parseBtfPattern(name));  // fail before work
  // Any BTF the registry opens (an image folder, a Bonn .btf file, a .btfz), so that a generated
  // Bonn file is measured as the real slice is.
  std::vector<std::shared_ptr<const BtfSource>> measured;
  for (const std::string& input : inputs) measured.push_back(openBtf(input));
  std::filesystem::create_directories(args.output);
  std::vector<PatternResult> results;
  auto analyze = [&](const std::string& name, const BtfSource& whole, std::chrono::steady_clock::time_point start,
                     bool synthetic) {
    const BtfSubset subset(whole, BtfSubset::centredRect(whole, args.size, args.size), viewsUpTo(whole, args.max_view_theta));
    std::optional<synthetic::CameraBtf> camera;
    if (synthetic && args.camera_white > 0) {
      synthetic::CameraOptions options = args.camera;
      options.white = args.camera_white * synthetic::exposureWhite(subset);
      options.seed = args.seed;
      camera.emplace(subset, options);
    }
    const BtfSource& source = camera ? static_cast<const BtfSource&>(*camera) : subset;
    PatternResult p{name, source.width(), analyzeCompressibility(source, args.analysis), 0};
    p.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("%-8s %dx%d, %s: nearest-texel distance median %.4f, rank at epsilon %g: %d (%.1f s)\n",
                p.pattern.c_str(), source.width(), source.height(), source.views().describe().c_str(), p.report.nn_p50,
                p.report.at_epsilon.empty() ? 0.0 : p.report.at_epsilon.front().epsilon,
                p.report.at_epsilon.empty() ? 0 : p.report.at_epsilon.front().rank, p.seconds);
    std::fflush(stdout);
    results.push_back(std::move(p));
  };
  for (std::size_t i = 0; i < patterns.size(); ++i) {
    const auto start = std::chrono::steady_clock::now();
    analyze(patterns[i] + (args.camera_white > 0 ? " (camera)" : ""),
            *synthetic::makeSyntheticBtf(parsed[i], args.size, args.size, args.seed), start, true);
  }
  for (const auto& source : measured) analyze(source->name(), *source, std::chrono::steady_clock::now(), false);
  const std::filesystem::path folder = args.output;
  const std::filesystem::path csv = folder / "compressibility.csv";
  writeCsv(csv, results);
  std::vector<std::string> nearest, rank;
  for (const PatternResult& p : results) {
    nearest.push_back(nearestCdf(p.report));
    rank.push_back(rankTail(p.report));
  }
  writeBlocks(folder / "compressibility_nearest.dat", "distance fraction_within", results, nearest);
  writeBlocks(folder / "compressibility_rank.dat", "rank tail_rel_energy", results, rank);
  const tools::GnuplotOutcome charts = drawCharts(folder, args, results, nearest, rank);
  printTables(results);
  std::printf("\nwrote %s, compressibility_nearest.dat, compressibility_rank.dat", csv.string().c_str());
  for (const auto& f : charts.files) std::printf(", %s", f.filename().c_str());
  std::printf("\n");
  if (!charts.message.empty()) std::printf("%s\n", charts.message.c_str());
}

}  // namespace

void addBenchCompressibilityCommand(CLI::App& bench) {
  auto args = std::make_shared<Args>();
  auto* cmd = bench.add_subcommand(
      "compressibility",
      "How compressible synthetic and measured BTFs are for any method: nearest-neighbour texel distances, greedy "
      "texel codebook size and linear rank per tolerance, with ratio_u8 bounds; CSV, tables and gnuplot charts "
      "(nearest-texel distance CDF, rank error curve)");
  cmd->add_option("-o,--output", args->output, "Output folder (compressibility.csv, .dat, charts)")->capture_default_str();
  cmd->add_option("--patterns", args->patterns, "Synthetic BTF patterns (comma-separated; '' for none)")
      ->capture_default_str();
  cmd->add_option("--inputs", args->inputs,
                  "Measured BTFs (comma-separated: image folders, Bonn .btf files, .btfz), analysed on a centred window of "
                  "--size texels");
  cmd->add_option("--max-view-theta", args->max_view_theta,
                  "Keep only the views up to this elevation in degrees (0: the view at the pole alone)")
      ->capture_default_str()
      ->check(CLI::Range(0.0f, 90.0f));
  cmd->add_option("--size", args->size, "Texels per side (the analysis is O(texels^2))")
      ->capture_default_str()
      ->check(CLI::Range(2, 128));
  cmd->add_option("--seed", args->seed, "Generator seed, also the seed of the direction sample")->capture_default_str();
  cmd->add_option("--directions", args->analysis.directions,
                  "(view, light) pairs sampled from the 6561 (0: all)")
      ->capture_default_str()
      ->check(CLI::Range(0, 6561));
  cmd->add_option("--camera-white", args->camera_white,
                  "Put a camera in front of the synthetic patterns (synthetic/camera_btf.h): white = this x the "
                  "99th percentile of the first view (0: no camera)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--camera-jitter", args->camera.jitter, "Camera: registration error, texels")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--camera-read-noise", args->camera.read_noise, "Camera: read noise std, in units of white")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--camera-shot-noise", args->camera.shot_noise, "Camera: shot noise std at white, in units of white")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("!--camera-float", args->camera.quantize, "Camera: keep float values (default: 8-bit sRGB codes)");
  cmd->add_option("--epsilons", args->analysis.epsilons, "Tolerances, each in (0, 1)")
      ->delimiter(',')
      ->capture_default_str();
  cmd->callback([args] {
    args->analysis.seed = args->seed;
    runBenchCompressibility(*args);
  });
}

}  // namespace btf::cli
