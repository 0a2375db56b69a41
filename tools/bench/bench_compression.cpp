// `btf bench compression [-o DIR]`: rate-distortion and speed of the multi-level VQ compressor
// against per-view PCA at equal storage, on the synthetic BTFs of `btf-datagen btf` (streamed from
// the generator, cached in memory when small) and on measured BTFs (--inputs: image folders, whole
// or partial), and BRDF compression of the real RGL materials and the generator presets as
// one-texel BTFs beside published compact sizes. Every setting is judged by rel_rmse (linear),
// rel_rmse of the displayed colours and mean SSIM (io/btf_quality.h), beside the data's own noise
// floor.
//   DIR/compression.csv       one row per (method, material, setting)
//   DIR/brdf_compression.csv  one row per BRDF
//   DIR/compression_ratio_vs_error.{png,svg}, DIR/compression_ratio_vs_display_error.{png,svg},
//   DIR/compression_ratio_vs_ssim.{png,svg}, DIR/compression_speed_vs_error.{png,svg}
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "bench_compression.h"
#include "bench_compression_scaling.h"
#include "btf/compress/pca.h"
#include "btf/compress/vq_btf.h"
#include "btf/core/error.h"
#include "btf/core/rng.h"
#include "btf/io/atomic_file.h"
#include "btf/io/btf_images.h"
#include "btf/io/btf_quality.h"
#include "btf/material/registry.h"
#include "comma_list.h"
#include "gnuplot_charts.h"
#include "presets.h"
#include "synthetic_btf.h"
#include "btf_patterns.h"

namespace btf::cli {
// Named after the file: the unity build compiles the commands together, and their helpers share
// names (Args, Row).
namespace bench_compression {
namespace {

struct Args {
  std::string output = "bench-compression";
  std::string patterns = "fabric,stones,paint,leather";
  int size = 64;
  std::uint64_t seed = 1;
  std::vector<float> epsilons{0.0025f, 0.005f, 0.01f, 0.02f, 0.04f};
  std::vector<int> levels{1, 2, 3};
  // The chromaticity tolerance follows epsilon (chroma_scale * epsilon, at least the smallest the
  // format takes): with a fixed one the chroma codebooks stop shrinking and the rate-distortion
  // curve flattens at large epsilon. 0.5 gives the library's default pair at epsilon 0.02 (chroma 0.01).
  float chroma_scale = 0.5f;
  bool level1_cut = false;  // VqOptions::level1_cut for every VQ row
  bool quick = false;
  bool brdfs = true;
  std::string inputs;  // measured BTF image folders, comma-separated
  // A published point to mark on the charts: "label,rel_rmse_display,mean_ssim,ratio_u8".
  std::string reference_point;
  bool scaling = false;  // the time-scaling study (bench_compression_scaling.h)
  CompressionScalingOptions scaling_options;
};

struct ReferencePoint {
  std::string label;
  double rel_rmse_display = 0, mean_ssim = 0, ratio_u8 = 0;
};

std::optional<ReferencePoint> parseReferencePoint(const std::string& text) {
  if (text.empty()) return std::nullopt;
  const std::vector<std::string> parts = splitCommaList(text);
  if (parts.size() != 4)
    throw Error("--reference-point '" + text + "': expected LABEL,REL_RMSE_DISPLAY,MEAN_SSIM,RATIO_U8");
  try {
    return ReferencePoint{parts[0], std::stod(parts[1]), std::stod(parts[2]), std::stod(parts[3])};
  } catch (const std::exception&) {
    throw Error("--reference-point '" + text + "': the last three fields must be numbers");
  }
}

struct Row {
  std::string method, material;
  int texels = 0;
  double epsilon = -1, chroma_epsilon = -1;
  int levels = 0, components = -1;
  std::uint64_t bytes = 0;
  double ratio_u8 = 0, ratio_f32 = 0, rel_rmse = 0, psnr_db = 0, compression_s = 0, evals_per_s = 0;
  double mean_ssim = 0, rel_rmse_display = 0, noise_rel_rmse = 0;
};

// The measures of a decoded BTF against its source (rel_rmse, psnr_db, displayed error, SSIM).
void measureErrors(Row& r, const BtfSource& source, const BtfSource& decoded) {
  const BtfErrorStats e = compareBtf(source, decoded);
  r.rel_rmse = e.rel_rmse;
  r.psnr_db = e.psnr_db;
  const BtfSsimStats ssim = compareBtfSsim(source, decoded);
  r.mean_ssim = ssim.mean_ssim;
  r.rel_rmse_display = ssim.rel_rmse_display;
}

double seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// Entries decoded per second by value() at random (texel, view, light): the cost of evaluating
// straight from the compressed form at measured directions (one thread).
double decodeRate(const BtfLookup& lookup, std::uint64_t seed) {
  constexpr int kDraws = 1 << 20;
  struct Query { int x, y, v, l; };
  std::vector<Query> queries(kDraws);
  Rng rng(seed);
  for (Query& q : queries) {
    const glm::vec2 a = rng.uniform2D(), b = rng.uniform2D();
    q = {std::min(int(a.x * float(lookup.lookupWidth())), lookup.lookupWidth() - 1),
         std::min(int(a.y * float(lookup.lookupHeight())), lookup.lookupHeight() - 1),
         lookup.lookupViews().view(std::min(int(b.x * float(lookup.lookupViews().count())), lookup.lookupViews().count() - 1)),
         0};
    const int lights = lookup.lookupViews().directions().lightCount(q.v);
    q.l = std::min(int(b.y * float(lights)), lights - 1);
  }
  const auto start = std::chrono::steady_clock::now();
  float sink = 0;
  for (const Query& q : queries) sink += lookup.value(q.x, q.y, q.v, q.l).g;
  const double s = seconds(start);
  volatile float keep = sink;
  (void)keep;
  return double(kDraws) / s;
}

float chromaEpsilonFor(float epsilon, float chroma_scale) {
  return std::clamp(chroma_scale * epsilon, kVqMinChromaEpsilon, 1.0f);
}

Row measureVq(const BtfSource& source, const std::string& material, float epsilon, float chroma_epsilon, int levels,
              bool level1_cut, const std::filesystem::path& scratch) {
  VqOptions options;
  options.level1_cut = level1_cut;
  options.epsilon = epsilon;
  options.chroma_epsilon = chroma_epsilon;
  options.levels = levels;
  const auto start = std::chrono::steady_clock::now();
  const VqBtf compressed = compressVq(source, options);
  Row r;
  r.compression_s = seconds(start);
  compressed.write(scratch);
  r.bytes = std::filesystem::file_size(scratch);
  const VqBtf reread = VqBtf::read(scratch);
  std::filesystem::remove(scratch);
  measureErrors(r, source, reread);
  r.method = "vq";
  r.material = material;
  r.epsilon = epsilon;
  r.chroma_epsilon = chroma_epsilon;
  r.levels = levels;
  r.evals_per_s = decodeRate(reread, 7);
  return r;
}

Row measurePca(const BtfSource& source, const std::string& material, int components) {
  const auto start = std::chrono::steady_clock::now();
  const PcaBtf pca = compressPca(source, components);
  Row r;
  r.compression_s = seconds(start);
  r.method = "pca";
  r.material = material;
  r.components = components;
  r.bytes = pca.storedBytes();
  measureErrors(r, source, pca);
  r.evals_per_s = decodeRate(pca, 7);
  return r;
}

void finish(Row& r, const BtfSource& source, double noise_rel_rmse) {
  r.texels = source.width() * source.height();
  r.noise_rel_rmse = noise_rel_rmse;
  r.ratio_u8 = double(source.entryCount()) * 3.0 / double(r.bytes);
  r.ratio_f32 = 4.0 * r.ratio_u8;
}

void writeCsv(const std::filesystem::path& path, const std::vector<Row>& rows) {
  writeFileAtomically(path, [&](std::ofstream& out) {
    out << "method,material,texels,epsilon,levels,components,bytes,ratio_u8,ratio_f32,rel_rmse,psnr_db,compression_s,"
           "evals_per_s,chroma_epsilon,mean_ssim,rel_rmse_display,noise_rel_rmse\n";
    for (const Row& r : rows) {
      out << r.method << ',' << r.material << ',' << r.texels << ',';
      if (r.epsilon >= 0) out << r.epsilon;
      out << ',';
      if (r.levels > 0) out << r.levels;
      out << ',';
      if (r.components >= 0) out << r.components;
      out << ',' << r.bytes << ',' << r.ratio_u8 << ',' << r.ratio_f32 << ',' << r.rel_rmse << ',' << r.psnr_db << ','
          << r.compression_s << ',' << r.evals_per_s << ',';
      if (r.chroma_epsilon >= 0) out << r.chroma_epsilon;
      out << ',' << r.mean_ssim << ',' << r.rel_rmse_display << ',' << r.noise_rel_rmse << '\n';
    }
  });
}

std::string seriesOf(const Row& r) {
  return r.method == "vq" ? r.material + " vq " + std::to_string(r.levels) + "-level" : r.material + " pca";
}

tools::GnuplotOutcome drawCharts(const std::filesystem::path& folder, const std::vector<Row>& rows,
                                 const std::optional<ReferencePoint>& mark) {
  std::vector<std::string> series;
  for (const Row& r : rows)
    if (std::find(series.begin(), series.end(), seriesOf(r)) == series.end()) series.push_back(seriesOf(r));
  // Each series' points in order of ratio, so its line does not zigzag (PCA rows come in the order
  // of the VQ budgets of every level count).
  std::vector<Row> sorted = rows;
  std::stable_sort(sorted.begin(), sorted.end(), [](const Row& a, const Row& b) { return a.ratio_u8 < b.ratio_u8; });
  std::map<std::string, std::ostringstream> ratio, speed, display, ssim;
  for (const Row& r : sorted) {
    const std::string s = seriesOf(r);
    ratio[s] << r.rel_rmse << ' ' << r.ratio_u8 << '\n';
    speed[s] << r.rel_rmse << ' ' << r.evals_per_s << '\n';
    display[s] << r.rel_rmse_display << ' ' << r.ratio_u8 << '\n';
    ssim[s] << r.mean_ssim << ' ' << r.ratio_u8 << '\n';
  }
  std::ostringstream data;
  for (std::size_t i = 0; i < series.size(); ++i) {
    data << "$ratio" << i << " << EOD\n" << ratio[series[i]].str() << "EOD\n";
    data << "$speed" << i << " << EOD\n" << speed[series[i]].str() << "EOD\n";
    data << "$display" << i << " << EOD\n" << display[series[i]].str() << "EOD\n";
    data << "$ssim" << i << " << EOD\n" << ssim[series[i]].str() << "EOD\n";
  }
  if (mark) {
    data << "$mark_display << EOD\n" << mark->rel_rmse_display << ' ' << mark->ratio_u8 << "\nEOD\n";
    data << "$mark_ssim << EOD\n" << mark->mean_ssim << ' ' << mark->ratio_u8 << "\nEOD\n";
  }
  auto plot = [&](const std::string& prefix, bool with_mark = false) {
    std::ostringstream p;
    p << "plot ";
    for (std::size_t i = 0; i < series.size(); ++i) {
      const bool pca = series[i].ends_with(" pca");
      p << (i ? ", " : "") << '$' << prefix << i << " using 1:2 with linespoints " << (pca ? "dt 2 pt 6" : "pt 7")
        << " ps 1.2 title " << tools::gnuplotQuote(series[i]);
    }
    if (with_mark && mark)
      p << ", $mark_" << prefix << " using 1:2 with points pt 3 ps 2.5 lc rgb 'black' title "
        << tools::gnuplotQuote(mark->label);
    return p.str() + "\n";
  };
  const std::vector<tools::GnuplotChart> charts = {
      {"compression_ratio_vs_error",
       "set title 'Compression ratio (8-bit raw) vs rel_rmse: multi-level VQ and per-view PCA at equal storage'\n"
       "set logscale xy\nset xlabel 'rel_rmse (RMSE / RMS of the data)'\nset ylabel 'ratio_u8'\n"
       "set arrow from graph 0, first 1000 to graph 1, first 1000 nohead dt 3\n" + plot("ratio")},
      {"compression_ratio_vs_display_error",
       "set title 'Compression ratio vs rel_rmse of the displayed colours (sRGB, clipped to white)'\n"
       "set logscale xy\nset xlabel 'rel_rmse of the sRGB-encoded values'\nset ylabel 'ratio_u8'\nset key inside left top\n" +
           plot("display", true)},
      {"compression_ratio_vs_ssim",
       "set title 'Compression ratio vs mean SSIM (sRGB luma, 8 x 8 windows, all images)'\n"
       "set logscale y\nset xlabel 'mean SSIM'\nset ylabel 'ratio_u8'\nset key inside right top\n" + plot("ssim", true)},
      {"compression_speed_vs_error",
       "set title 'Decoding speed from the compressed form vs rel_rmse (one core, random entries)'\n"
       "set logscale xy\nset xlabel 'rel_rmse'\nset ylabel 'entries decoded per second'\n" + plot("speed")},
  };
  return tools::drawGnuplotCharts(folder, "compression_charts.gp", data.str(), charts);
}

// BRDFs as one-texel BTFs at the 81 x 81 directions: the real RGL materials (beside their own file
// size) and the generator presets.
void benchBrdfs(const std::filesystem::path& folder, float epsilon, bool quick) {
  struct BrdfRow {
    std::string name;
    std::uint64_t bytes = 0, source_bytes = 0;
    double rel_rmse = 0;
  };
  std::vector<BrdfRow> rows;
  auto run = [&](const Material& m, const std::string& name, std::uint64_t source_bytes) {
    const BtfData data = brdfAsBtf(m, name);
    VqOptions options;
    options.epsilon = epsilon;
    const VqBtf vq = compressVq(data, options);
    const std::filesystem::path scratch = folder / (name + ".part.btfz");
    vq.write(scratch);
    BrdfRow r{name, std::filesystem::file_size(scratch), source_bytes, compareBtf(data, VqBtf::read(scratch)).rel_rmse};
    std::filesystem::remove(scratch);
    rows.push_back(r);
  };
  std::vector<std::filesystem::path> rgl_files;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(BTF_RGL_BUILD_DIR, ec))
    if (entry.path().extension() == ".bsdf") rgl_files.push_back(entry.path());
  std::sort(rgl_files.begin(), rgl_files.end());
  if (quick) rgl_files.resize(std::min<std::size_t>(rgl_files.size(), 1));
  for (const std::filesystem::path& file : rgl_files) {
    run(*openMaterial(file.string()), file.stem().string(), std::filesystem::file_size(file));
  }
  for (const auto& preset : datagen::presets())
    if (!quick || preset.name == "plastic-red") run(*preset.make(), preset.name, 0);
  writeFileAtomically(folder / "brdf_compression.csv", [&](std::ofstream& out) {
    out << "material,btfz_bytes,source_bytes,rel_rmse\n";
    for (const BrdfRow& r : rows) out << r.name << ',' << r.bytes << ',' << r.source_bytes << ',' << r.rel_rmse << '\n';
  });
  std::printf("\nBRDFs as one-texel BTFs (81 x 81 directions, raw 78,732 bytes as float RGB), epsilon %g:\n", epsilon);
  std::printf("%-28s %10s %14s %9s\n", "material", "btfz bytes", "source bytes", "rel_rmse");
  for (const BrdfRow& r : rows)
    std::printf("%-28s %10llu %14s %9.4f\n", r.name.c_str(), static_cast<unsigned long long>(r.bytes),
                r.source_bytes ? std::to_string(r.source_bytes).c_str() : "-", r.rel_rmse);
  std::printf("Published compact sizes for scale: RGL format ~16 KiB per isotropic spectral sample (Dupuy & Jakob 2018),\n"
              "Bagher et al. 2016 3.2 KB, a neural BRDF 675 weights (2.7 KB as float32).\n");
}

// One material of the table: every VQ setting, then PCA at the storage of each VQ setting.
void benchMaterial(const Args& args, const std::string& name, const BtfSource& source, const std::vector<float>& epsilons,
                   const std::vector<int>& levels, std::vector<Row>& rows) {
  const double noise = estimateBtfNoiseFloor(source).rel_rmse;
  std::printf("%-8s %s, %d x %d texels; noise floor rel_rmse %.4f (btf_quality.h)\n", name.c_str(),
              source.views().describe().c_str(), source.width(), source.height(), noise);
  std::vector<std::uint64_t> vq_bytes;
  for (int l : levels)
    for (float e : epsilons) {
      const float ce = chromaEpsilonFor(e, args.chroma_scale);
      Row r = measureVq(source, name, e, ce, l, args.level1_cut, std::filesystem::path(args.output) / (name + ".part.btfz"));
      finish(r, source, noise);
      vq_bytes.push_back(r.bytes);
      std::printf("%-8s vq  levels %d eps %-7g chroma %-7g ratio_u8 %8.1f rel_rmse %.4f display %.4f ssim %.4f  %6.1f s  "
                  "%.3g entries/s\n",
                  name.c_str(), l, e, ce, r.ratio_u8, r.rel_rmse, r.rel_rmse_display, r.mean_ssim, r.compression_s,
                  r.evals_per_s);
      std::fflush(stdout);
      rows.push_back(r);
    }
  // PCA at the storage of every VQ setting (equal storage), at most one row per component count.
  std::vector<int> done;
  for (std::uint64_t budget : vq_bytes) {
    const int k = pcaComponentsForBudget(source.width(), source.height(), budget, PcaPrecision::Half,
                                         source.views().count());
    if (k < 0 || std::find(done.begin(), done.end(), k) != done.end()) continue;
    done.push_back(k);
    Row r = measurePca(source, name, k);
    finish(r, source, noise);
    std::printf("%-8s pca k %-3d (budget %llu bytes) ratio_u8 %8.1f rel_rmse %.4f display %.4f ssim %.4f  %6.1f s\n",
                name.c_str(), k, static_cast<unsigned long long>(budget), r.ratio_u8, r.rel_rmse, r.rel_rmse_display,
                r.mean_ssim, r.compression_s);
    std::fflush(stdout);
    rows.push_back(r);
  }
}

void runBenchCompression(const Args& args) {
  std::filesystem::create_directories(args.output);
  const std::optional<ReferencePoint> mark = parseReferencePoint(args.reference_point);
  std::vector<std::string> patterns = splitCommaList(args.patterns);
  std::vector<float> epsilons = args.epsilons;
  std::vector<int> levels = args.levels;
  int size = args.size;
  if (args.quick) {
    if (!patterns.empty()) patterns = {patterns.front()};
    size = 8;
    epsilons = {0.04f};
    levels = {1, 3};
  }
  if (args.scaling) {
    CompressionScalingOptions o = args.scaling_options;
    if (args.quick) o.sides = {4, 6, 8}, o.direction_side = 4, o.scattered = 40;
    benchCompressionScaling(args.output, o);
  }
  std::vector<Row> rows;
  for (const std::string& name : patterns) {
    const auto pattern = synthetic::parseBtfPattern(name);
    const std::unique_ptr<BtfSource> generated = synthetic::makeSyntheticBtf(pattern, size, size, args.seed);
    // Every setting reads the data at least twice (compress, compare): keep it in memory when it fits
    // in 2 GiB, else stream from the generator each time.
    std::unique_ptr<BtfData> cached;
    if (double(generated->entryCount()) * sizeof(Rgb) <= 2.0 * (1ull << 30))
      cached = std::make_unique<BtfData>(BtfData::copyOf(*generated));
    const BtfSource& source = cached ? static_cast<const BtfSource&>(*cached) : *generated;
    benchMaterial(args, name, source, epsilons, levels, rows);
  }
  for (const std::string& input : splitCommaList(args.inputs)) {
    const BtfImageFolder folder = BtfImageFolder::open(input);
    // In memory when it fits in 2 GiB (a one-view slice of 256 x 256 texels: 64 MiB).
    std::unique_ptr<BtfData> cached;
    if (double(folder.entryCount()) * sizeof(Rgb) <= 2.0 * (1ull << 30))
      cached = std::make_unique<BtfData>(BtfData::copyOf(folder));
    const BtfSource& source = cached ? static_cast<const BtfSource&>(*cached) : folder;
    benchMaterial(args, folder.name(), source, epsilons, levels, rows);
  }
  if (rows.empty() && !args.scaling) throw Error("bench compression: nothing to measure (no --patterns and no --inputs)");
  if (rows.empty()) return;
  writeCsv(std::filesystem::path(args.output) / "compression.csv", rows);
  const tools::GnuplotOutcome charts = drawCharts(args.output, rows, mark);
  if (args.brdfs) benchBrdfs(args.output, args.quick ? 0.04f : 0.01f, args.quick);
  std::printf("\nwrote %s/compression.csv", args.output.c_str());
  for (const auto& f : charts.files) std::printf(", %s", f.filename().c_str());
  std::printf("\n");
  if (!charts.message.empty()) std::printf("%s\n", charts.message.c_str());
}

}  // namespace
}  // namespace bench_compression

void addBenchCompressionCommand(CLI::App& bench) {
  auto args = std::make_shared<bench_compression::Args>();
  auto* cmd = bench.add_subcommand(
      "compression",
      "Multi-level VQ vs per-view PCA at equal storage on synthetic BTFs: ratio_u8, ratio_f32, rel_rmse, psnr_db, "
      "compression seconds, decode rate; CSV and gnuplot charts; BRDFs as one-texel BTFs");
  cmd->add_option("-o,--output", args->output, "Output folder")->capture_default_str();
  cmd->add_option("--patterns", args->patterns, "Synthetic BTF patterns (comma-separated)")->capture_default_str();
  cmd->add_option("--size", args->size, "Texels per side")->capture_default_str()->check(CLI::Range(4, 1024));
  cmd->add_option("--seed", args->seed, "Generator seed")->capture_default_str();
  cmd->add_option("--epsilons", args->epsilons, "VQ tolerances")->delimiter(',')->capture_default_str();
  cmd->add_flag("--level1-cut", args->level1_cut,
               "VQ rows code level-1 entries in a principal basis, cut to what their tolerance needs "
               "(btf compress --level1-cut)");
  cmd->add_option("--chroma-scale", args->chroma_scale,
                  "Chromaticity tolerance per unit of epsilon (chroma_epsilon = scale * epsilon, at least 0.001)")
      ->capture_default_str()
      ->check(CLI::Range(0.0f, 100.0f));
  cmd->add_option("--levels", args->levels, "VQ level counts")->delimiter(',')->capture_default_str()->check(CLI::Range(1, 3));
  cmd->add_flag("--quick", args->quick, "One pattern at 8 x 8, one tolerance, two BRDFs (for tests)");
  cmd->add_flag("!--no-brdfs", args->brdfs, "Skip the BRDF table");
  cmd->add_option("--inputs", args->inputs,
                  "Measured BTF image folders to bench beside the patterns (comma-separated; --patterns '' for "
                  "these alone)");
  cmd->add_flag("--scaling", args->scaling,
                "First measure how compression time grows with texels (three sizes on the Bonn dome and the 81-direction "
                "set) and with directions (81, dome, a scattered set): texel-directions per second per core, "
                "compression_scaling.csv and a chart");
  cmd->add_option("--scaling-sizes", args->scaling_options.sides, "Texels per side of the texel study")
      ->delimiter(',')
      ->capture_default_str()
      ->check(CLI::Range(2, 1024));
  cmd->add_option("--reference-point", args->reference_point,
                  "A published result to mark on the display-error and SSIM charts: LABEL,REL_RMSE_DISPLAY,MEAN_SSIM,"
                  "RATIO_U8");
  cmd->callback([args] { bench_compression::runBenchCompression(*args); });
}

}  // namespace btf::cli
