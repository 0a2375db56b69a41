// `btf bench compression --scaling`: VQ compression time against texels and against directions.
//   DIR/compression_scaling.csv       one row per (direction set, texels)
//   DIR/compression_scaling.{png,svg} seconds against texel-directions, log-log
// Throughput is texel-directions (texels x (view, light) pairs) per second of wall time, divided by
// the cores TBB runs on: the figure that says how long a material of another size takes.
#include "bench_compression_scaling.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>

#include "btf/compress/vq_btf.h"
#include "btf/core/btf_ring_layout.h"
#include "btf/io/atomic_file.h"
#include "btf_patterns.h"
#include "gnuplot_charts.h"
#include "synthetic_btf.h"

namespace btf::cli {
namespace {

struct ScalingRow {
  std::string study, set;
  int side = 0;
  double texels = 0, pairs = 0, seconds = 0, per_core = 0;
  std::vector<std::size_t> entries;
  std::uint64_t bytes = 0;
};

ScalingRow measure(const CompressionScalingOptions& o, const std::string& study, const std::string& set_name,
                   const BtfDirectionSetPtr& set, int side, const std::filesystem::path& scratch) {
  synthetic::SyntheticBtfOptions generator;
  generator.directions = set;
  const auto generated = synthetic::makeSyntheticBtf(synthetic::parseBtfPattern(o.pattern), side, side, o.seed, generator);
  const BtfData data = BtfData::copyOf(*generated);
  VqOptions options;
  options.epsilon = o.epsilon;
  const auto start = std::chrono::steady_clock::now();
  const VqBtf vq = compressVq(data, options);
  ScalingRow r;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  vq.write(scratch);
  r.bytes = std::filesystem::file_size(scratch);
  std::filesystem::remove(scratch);
  r.study = study;
  r.set = set_name;
  r.side = side;
  r.texels = double(data.texelCount());
  r.pairs = double(set->pairCount());
  const int cores = std::max(1, tbb::this_task_arena::max_concurrency());
  r.per_core = r.texels * r.pairs / r.seconds / cores;
  r.entries = vq.stats().codebook_entries;
  std::printf("%-9s %-24s %4d x %-4d texels x %6.0f pairs (%s): %8.2f s, %.3g texel-directions/s per core, %llu bytes\n",
              study.c_str(), set_name.c_str(), side, side, r.pairs, BtfRingLayout::of(*set, set_name).describe().c_str(),
              r.seconds, r.per_core, static_cast<unsigned long long>(r.bytes));
  std::fflush(stdout);
  return r;
}

// Least-squares slope of log(seconds) against log(x) over rows [first, last).
double exponent(const std::vector<ScalingRow>& rows, std::size_t first, std::size_t last, double ScalingRow::*x) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0, n = 0;
  for (std::size_t i = first; i < last; ++i) {
    const double lx = std::log(rows[i].*x), ly = std::log(rows[i].seconds);
    sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly, n += 1;
  }
  const double d = n * sxx - sx * sx;
  return d > 0 ? (n * sxy - sx * sy) / d : 0.0;
}

}  // namespace

void benchCompressionScaling(const std::filesystem::path& folder, const CompressionScalingOptions& o) {
  const BtfDirectionSetPtr dome = BtfDirectionSet::uboDome1(), ubo = BtfDirectionSet::ubo2003();
  const BtfDirectionSetPtr scattered = synthetic::scatteredDirectionSet(o.scattered, o.scattered);
  const std::string scattered_name = "scattered " + std::to_string(o.scattered) + "x" + std::to_string(o.scattered);
  const std::filesystem::path scratch = folder / "scaling.part.btfz";
  std::printf("\nVQ compression time against texels and directions (%s, epsilon %g, 3 levels, %d cores):\n",
              o.pattern.c_str(), double(o.epsilon), std::max(1, tbb::this_task_arena::max_concurrency()));
  std::vector<ScalingRow> rows;
  std::vector<std::pair<std::string, std::pair<std::size_t, std::size_t>>> fits;
  for (const auto& [name, set] : {std::pair{std::string("Bonn dome 1"), dome}, std::pair{std::string("UBO2003"), ubo}}) {
    const std::size_t first = rows.size();
    for (const int side : o.sides) rows.push_back(measure(o, "texels", name, set, side, scratch));
    fits.push_back({"texels on " + name, {first, rows.size()}});
  }
  const std::size_t first = rows.size();
  for (const auto& [name, set] : {std::pair{std::string("UBO2003"), ubo}, std::pair{std::string("Bonn dome 1"), dome},
                                  std::pair{scattered_name, scattered}})
    rows.push_back(measure(o, "directions", name, set, o.direction_side, scratch));
  std::printf("time ~ texels^a, pairs^b (least squares over the sizes above):\n");
  for (const auto& [label, range] : fits)
    std::printf("  %-28s a = %.2f\n", label.c_str(), exponent(rows, range.first, range.second, &ScalingRow::texels));
  std::printf("  %-28s b = %.2f (%d x %d texels; the scattered set is cut into bands, not rings)\n", "pairs",
              exponent(rows, first, rows.size(), &ScalingRow::pairs), o.direction_side, o.direction_side);

  writeFileAtomically(folder / "compression_scaling.csv", [&](std::ofstream& out) {
    out << "study,set,side,texels,pairs,seconds,texel_directions_per_s_per_core,level1_entries,level2_entries,"
           "level3_entries,bytes\n";
    for (const ScalingRow& r : rows) {
      out << r.study << ',' << r.set << ',' << r.side << ',' << r.texels << ',' << r.pairs << ',' << r.seconds << ','
          << r.per_core;
      for (std::size_t l = 0; l < 3; ++l) out << ',' << (l < r.entries.size() ? r.entries[l] : 0);
      out << ',' << r.bytes << '\n';
    }
  });
  // One line per set for the texel study, one line across the sets for the direction study.
  auto seriesOf = [](const ScalingRow& r) {
    return r.study == "texels" ? "more texels, " + r.set
                               : "more directions (81, dome, scattered), " + std::to_string(r.side) + "^2 texels";
  };
  std::ostringstream data;
  std::vector<std::string> series;
  for (const ScalingRow& r : rows)
    if (std::find(series.begin(), series.end(), seriesOf(r)) == series.end()) series.push_back(seriesOf(r));
  std::ostringstream plot;
  plot << "plot ";
  for (std::size_t i = 0; i < series.size(); ++i) {
    data << "$s" << i << " << EOD\n";
    for (const ScalingRow& r : rows)
      if (seriesOf(r) == series[i]) data << r.texels * r.pairs << ' ' << r.seconds << '\n';
    data << "EOD\n";
    plot << (i ? ", " : "") << "$s" << i << " using 1:2 with linespoints pt 7 ps 1.2 title " << tools::gnuplotQuote(series[i]);
  }
  const tools::GnuplotOutcome charts = tools::drawGnuplotCharts(
      folder, "compression_scaling.gp", data.str(),
      {{"compression_scaling",
        "set title 'VQ compression time against texels x (view, light) pairs'\nset logscale xy\n"
        "set xlabel 'texel-directions'\nset ylabel 'seconds (wall)'\nset key inside left top\n" +
            plot.str() + "\n"}});
  std::printf("wrote %s", (folder / "compression_scaling.csv").c_str());
  for (const auto& f : charts.files) std::printf(", %s", f.filename().c_str());
  std::printf("\n");
  if (!charts.message.empty()) std::printf("%s\n", charts.message.c_str());
}

}  // namespace btf::cli
