// `btf bench bonn`: compression judged against the file a user downloads. Per texel side, a
// Bonn-size material of realistic statistics (the print pattern through the measured camera:
// per-texel variation, sensor noise, misregistration, 8-bit codes; `btf-datagen btf --camera`) on
// the dome's 151 x 151 directions, written as DFMF, is compressed by `btf compress` as a user runs
// it, and set beside the format's own way to get smaller: the same file re-factorised with fewer
// components at the bytes of the .btfz (`btf convert --components`).
//   DIR/bonn.csv                  one row per (side, method, epsilon)
//   DIR/bonn_ratio.{png,svg}      bytes of the input over bytes written, against texels
//   DIR/bonn_error.{png,svg}      rel_rmse of the .btfz and of the equal-bytes DFMF, against texels
//   DIR/bonn_cost.{png,svg}       compression seconds and peak memory, against texels
// Every command runs in its own process, so that its seconds and peak memory are its own (btf
// compress reports peak_memory_bytes); errors are against the DFMF file's own decode.
#include "bench_bonn.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "btf/core/error.h"
#include "btf/io/atomic_file.h"
#include "btf/io/bonn_btf.h"
#include "gnuplot_charts.h"
#include "process.h"

namespace btf::cli {
namespace bench_bonn {
namespace {
namespace fs = std::filesystem;

struct Args {
  std::string output = "bench-bonn";
  std::vector<int> sides{50, 100, 200, 400};
  std::vector<float> epsilons{0.05f, 0.02f};
  std::string pattern = "print";
  std::uint64_t seed = 1;
  int vq_max_side = 32;  // VQ's codebooks grow with texels x lights: beyond this side it is not tried
  bool keep = false;
  bool quick = false;
};

struct Row {
  int side = 0;
  double texels = 0, pairs = 0;
  std::uint64_t input_bytes = 0;
  double generate_s = 0;
  std::string method, form, components;
  float epsilon = 0;
  std::uint64_t bytes = 0;
  double ratio_input = 0, rel_rmse = 0, mean_ssim = 0, seconds = 0, peak_mib = 0;
};

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

std::string componentsOf(const nlohmann::json& report) {
  if (!report.contains("components")) return "";
  std::string out;
  for (const auto& k : report["components"]) out += (out.empty() ? "" : " ") + std::to_string(k.get<int>());
  return out;
}

// The largest component count k (the same for every factorisation, none above its own count) whose
// DFMF file takes at most `target` bytes: the header and the other bytes stay, each component of a
// factorisation costs its singular value and a column of each factor. 0 when none is that small.
int componentsAtBytes(const BonnBtfHeader& h, std::uint64_t target) {
  std::uint64_t stored = 0;
  std::uint32_t most = 0;
  const auto cost = [](const BonnBtfFactor& f, std::uint32_t k) {
    return std::uint64_t(k) * (1 + std::uint64_t(f.rows) + f.columns) * std::uint64_t(f.scalar_bytes);
  };
  for (const BonnBtfFactor& f : h.factors) {
    stored += cost(f, f.components);
    most = std::max(most, f.components);
  }
  const std::uint64_t rest = h.file_bytes - stored;
  int best = 0;
  for (std::uint32_t k = 1; k <= most; ++k) {
    std::uint64_t bytes = rest;
    for (const BonnBtfFactor& f : h.factors) bytes += cost(f, std::min(k, f.components));
    if (bytes > target) break;
    best = int(k);
  }
  return best;
}

Row compressRow(const Row& base, const fs::path& btf, const fs::path& input, const fs::path& out, float epsilon,
                const std::string& form) {
  const nlohmann::json r = tools::runJsonCommand({btf.string(), "compress", input.string(), out.string(), "--epsilon",
                                                  fmt(epsilon), "--form", form, "--allow-larger", "--json"});
  Row row = base;
  row.method = form == "auto" ? "btfz" : "btfz-" + form;
  row.epsilon = epsilon;
  row.form = r.value("form", "");
  row.components = componentsOf(r);
  row.bytes = r.value("bytes", std::uint64_t(0));
  row.ratio_input = r.value("ratio_input", 0.0);
  row.rel_rmse = r.value("rel_rmse", 0.0);
  row.mean_ssim = r.value("mean_ssim", 0.0);
  row.seconds = r.value("compression_s", 0.0);
  row.peak_mib = double(r.value("peak_memory_bytes", std::uint64_t(0))) / double(1 << 20);
  return row;
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The input re-factorised at k components: the bytes the format itself reaches, and its error.
Row baselineRow(const Row& base, const fs::path& btf, const fs::path& input, const BonnBtfHeader& header,
                const Row& compressed, const fs::path& out) {
  Row row = base;
  row.method = "dfmf-equal-bytes";
  row.form = "dfmf";
  row.epsilon = compressed.epsilon;
  const int k = componentsAtBytes(header, compressed.bytes);
  row.components = std::to_string(k);
  if (k == 0) {
    std::printf("  no DFMF file of %llu bytes holds even one component\n", static_cast<unsigned long long>(compressed.bytes));
    return row;
  }
  const auto start = std::chrono::steady_clock::now();
  tools::runCommand({btf.string(), "convert", input.string(), out.string(), "--components", std::to_string(k),
                     "--relative-error", "1e-9", "--color-model", std::to_string(header.color_model)});
  row.seconds = secondsSince(start);
  const nlohmann::json e = tools::runJsonCommand({btf.string(), "compare", out.string(), input.string(), "--json"});
  row.bytes = fs::file_size(out);
  row.ratio_input = double(base.input_bytes) / double(row.bytes);
  row.rel_rmse = e.value("rel_rmse", 0.0);
  row.mean_ssim = e.value("mean_ssim", 0.0);
  return row;
}

void printRow(const Row& r) {
  std::printf("  %-17s eps %-5g %-22s %12llu bytes, %7.2f x smaller, rel_rmse %.4f, SSIM %.4f, %8.1f s, %7.0f MiB%s%s\n",
              r.method.c_str(), double(r.epsilon), r.form.c_str(), static_cast<unsigned long long>(r.bytes),
              r.ratio_input, r.rel_rmse, r.mean_ssim, r.seconds, r.peak_mib, r.components.empty() ? "" : ", components ",
              r.components.c_str());
  std::fflush(stdout);
}

void writeCsv(const fs::path& path, const std::vector<Row>& rows) {
  writeFileAtomically(path, [&](std::ofstream& out) {
    out << "side,texels,pairs,input_bytes,generate_s,method,epsilon,form,components,bytes,ratio_input,rel_rmse,"
           "mean_ssim,seconds,peak_memory_mib\n";
    for (const Row& r : rows)
      out << r.side << ',' << r.texels << ',' << r.pairs << ',' << r.input_bytes << ',' << fmt(r.generate_s) << ','
          << r.method << ',' << fmt(r.epsilon) << ',' << r.form << ',' << r.components << ',' << r.bytes << ','
          << fmt(r.ratio_input) << ',' << fmt(r.rel_rmse) << ',' << fmt(r.mean_ssim) << ',' << fmt(r.seconds) << ','
          << fmt(r.peak_mib) << '\n';
  });
}

// One gnuplot series per (method, epsilon): the column `y` against texels.
void drawCharts(const fs::path& folder, const std::vector<Row>& rows) {
  std::vector<std::pair<std::string, float>> series;
  for (const Row& r : rows)
    if (std::find(series.begin(), series.end(), std::pair{r.method, r.epsilon}) == series.end())
      series.emplace_back(r.method, r.epsilon);
  std::ostringstream data;
  for (std::size_t i = 0; i < series.size(); ++i) {
    data << "$s" << i << " << EOD\n";
    for (const Row& r : rows)
      if (r.method == series[i].first && r.epsilon == series[i].second && r.bytes > 0)
        data << r.texels << ' ' << r.ratio_input << ' ' << r.rel_rmse << ' ' << r.seconds << ' ' << r.peak_mib << '\n';
    data << "EOD\n";
  }
  const auto plot = [&](int column, bool compressed_only) {
    std::ostringstream p;
    p << "plot ";
    bool first = true;
    for (std::size_t i = 0; i < series.size(); ++i) {
      if (compressed_only && series[i].first == "dfmf-equal-bytes") continue;
      const std::string title = series[i].first + " at epsilon " + fmt(series[i].second);
      p << (first ? "" : ", ") << "$s" << i << " using 1:" << column << " with linespoints pt 7 ps 1.2 title "
        << tools::gnuplotQuote(title);
      first = false;
    }
    return p.str() + "\n";
  };
  const std::string axes = "set logscale x\nset xlabel 'texels'\nset key inside left top\n";
  const tools::GnuplotOutcome charts = tools::drawGnuplotCharts(
      folder, "bonn.gp", data.str(),
      {{"bonn_ratio", "set title 'Bytes of the DFMF input over bytes written (Bonn dome, 151 x 151)'\n" + axes +
                          "set logscale y\nset ylabel 'input bytes / output bytes'\n" + plot(2, true)},
       {"bonn_error", "set title 'rel_rmse against the DFMF file''s decode: .btfz, and DFMF at its bytes'\n" + axes +
                          "set logscale y\nset ylabel 'rel_rmse'\n" + plot(3, false)},
       {"bonn_seconds", "set title 'Compression seconds (wall)'\n" + axes + "set logscale y\nset ylabel 'seconds'\n" +
                            plot(4, true)},
       {"bonn_memory", "set title 'Peak memory of btf compress'\n" + axes + "set ylabel 'MiB'\n" + plot(5, true)}});
  for (const auto& f : charts.files) std::printf("wrote %s\n", f.c_str());
  if (!charts.message.empty()) std::printf("%s\n", charts.message.c_str());
}

void runBenchBonn(Args a) {
  if (a.quick) {
    a.sides = {12};
    a.epsilons = {0.05f};
  }
  const fs::path folder = a.output, work = folder / "work";
  fs::create_directories(work);
  const fs::path btf = tools::programBeside("btf"), datagen = tools::programBeside("btf-datagen");
  std::printf("Bonn-size compression: pattern %s through the measured camera, Bonn dome 151 x 151, DFMF input\n",
              a.pattern.c_str());
  std::vector<Row> rows;
  for (const int side : a.sides) {
    const fs::path input = work / ("input-" + std::to_string(side) + ".btf");
    const nlohmann::json g = tools::runJsonCommand(
        {datagen.string(), "btf", "--pattern", a.pattern, "--camera", "--size", std::to_string(side), "--seed",
         std::to_string(a.seed), "--directions", "dome", "--layout", "dfmf", "-o", input.string(), "--json"});
    const BonnBtfHeader header = readBonnBtfHeader(input);
    Row base;
    base.side = side;
    base.texels = double(header.width) * double(header.height);
    base.pairs = double(header.directions->pairCount());
    base.input_bytes = header.file_bytes;
    base.generate_s = g.value("seconds", 0.0);
    std::printf("%d x %d texels: input %s, %llu bytes (components", side, side, input.filename().c_str(),
                static_cast<unsigned long long>(base.input_bytes));
    for (const BonnBtfFactor& f : header.factors) std::printf(" %u", f.components);
    std::printf("), generated in %.1f s\n", base.generate_s);
    for (const float epsilon : a.epsilons) {
      const fs::path out = work / ("out-" + std::to_string(side) + "-" + fmt(epsilon) + ".btfz");
      rows.push_back(compressRow(base, btf, input, out, epsilon, "auto"));
      printRow(rows.back());
      const Row compressed = rows.back();
      fs::remove(out);
      if (side <= a.vq_max_side && compressed.form != "vq") {
        rows.push_back(compressRow(base, btf, input, out, epsilon, "vq"));
        printRow(rows.back());
        fs::remove(out);
      }
      const fs::path refactored = work / ("dfmf-" + std::to_string(side) + "-" + fmt(epsilon) + ".btf");
      rows.push_back(baselineRow(base, btf, input, header, compressed, refactored));
      printRow(rows.back());
      fs::remove(refactored);
    }
    if (!a.keep) fs::remove(input);
    writeCsv(folder / "bonn.csv", rows);  // after every side: a long run keeps what it measured
  }
  if (!a.keep) fs::remove_all(work);
  std::printf("wrote %s\n", (folder / "bonn.csv").c_str());
  drawCharts(folder, rows);
}

}  // namespace
}  // namespace bench_bonn

void addBenchBonnCommand(CLI::App& bench) {
  auto a = std::make_shared<bench_bonn::Args>();
  auto* cmd = bench.add_subcommand(
      "bonn",
      "Compression against the file a user downloads: a realistic Bonn-size BTF (measured-camera statistics, the "
      "dome's 151 x 151 directions) written as DFMF, compressed by btf compress, beside the DFMF re-factorised with "
      "fewer components at equal bytes: bytes, rel_rmse, SSIM, seconds and peak memory against texels; CSV and charts");
  cmd->add_option("-o,--output", a->output, "Output folder")->capture_default_str();
  cmd->add_option("--sides", a->sides, "Texels per side (comma-separated)")
      ->delimiter(',')
      ->capture_default_str()
      ->check(CLI::Range(4, 1024));
  cmd->add_option("--epsilons", a->epsilons, "btf compress tolerances (comma-separated)")
      ->delimiter(',')
      ->capture_default_str()
      ->check(CLI::Range(0.0f, 0.99f));
  cmd->add_option("--pattern", a->pattern, "The generator's pattern (btf-datagen btf --pattern)")->capture_default_str();
  cmd->add_option("--seed", a->seed, "Generator seed")->capture_default_str();
  cmd->add_option("--vq-max-side", a->vq_max_side,
                  "Also compress by VQ alone (--form vq) up to this side; its codebooks grow with texels x lights")
      ->capture_default_str();
  cmd->add_flag("--keep", a->keep, "Keep the generated inputs (DIR/work)");
  cmd->add_flag("--quick", a->quick, "One side of 12 texels, epsilon 0.05 (for tests)");
  cmd->callback([a] { bench_bonn::runBenchBonn(*a); });
}

}  // namespace btf::cli
