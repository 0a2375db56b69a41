// `btf bench rgl-writer -o DIR`: how much an RGL .bsdf written by virtual acquisition
// (material/rgl_acquisition.h) loses. Each material is written at the database's resolutions (an
// RGL file at its own), read back by RglBrdf from the encoded bytes, and compared with its source:
// rel_rmse of f cos and directional albedo at theta_o 0-75 deg (material_difference.h), and the
// chi-square test of the written file's own warp at theta_o 0, 30, 60 and 80 deg; the albedo
// error of the file's spectral channels (read through `spectra`, CIE 1931 under D65) at theta_o
// 0/30/60/75 deg, and the largest albedo error at grazing theta_o 70, 75 and 80 deg. The materials: GGX
// at four roughnesses, Lambert, Phong, the btf-datagen presets as the MERL tables btf-datagen
// writes, and the shared RGL files. DIR/rgl_writer.csv holds every figure.
#include "bench_rgl_writer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "bench_materials.h"
#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/core/progress.h"
#include "btf/io/atomic_file.h"
#include "btf/material/ggx.h"
#include "btf/material/lambert.h"
#include "btf/material/material_difference.h"
#include "btf/material/phong.h"
#include "btf/material/rgl_acquisition.h"
#include "btf/material/rgl_brdf.h"
#include "btf/material/tabulated_brdf.h"
#include "btf/sampling/chi2.h"
#include "comma_list.h"
#include "presets.h"

namespace btf::cli {
namespace bench_rgl_writer {
namespace {

struct Args {
  std::string output, materials;
  bool quick = false;
  RglAcquisitionOptions resolutions;  // for sources that are not RGL files
};

struct Source {
  std::string name;
  std::shared_ptr<const Material> material;
  RglAcquisitionOptions options;
  std::shared_ptr<const TensorFile> own;  // an RGL file: re-measured on its own parameterization
};

// The analytic models of the list: a coloured GGX conductor over a weak diffuse term at
// four roughnesses, a white Lambertian surface, a Phong lobe over a diffuse term.
std::vector<Source> analyticSources() {
  std::vector<Source> s;
  for (const float alpha : {0.05f, 0.1f, 0.3f, 0.5f}) {
    char name[32];
    std::snprintf(name, sizeof name, "ggx-a%g", double(alpha));
    s.push_back({name, std::make_shared<Ggx>(Rgb(0.05f, 0.04f, 0.02f), Rgb(0.95f, 0.64f, 0.54f), alpha, alpha), {}, {}});
  }
  s.push_back({"lambert", std::make_shared<Lambert>(Rgb(0.8f)), {}, {}});
  s.push_back({"phong-n50", std::make_shared<Phong>(Rgb(0.3f, 0.2f, 0.1f), Rgb(0.5f), 50.0f), {}, {}});
  return s;
}

Source sourceNamed(const std::string& name, const RglAcquisitionOptions& resolutions) {
  for (Source& s : analyticSources())
    if (s.name == name) {
      s.options = resolutions;
      return s;
    }
  BenchMaterial m = loadBenchMaterial(name);
  Source s{m.name, m.material, resolutions, {}};
  if (const auto* rgl = dynamic_cast<const RglBrdf*>(m.material.get())) {
    s.options.resolution = rgl->resolution();
    s.own = std::make_shared<const TensorFile>(readTensorFile(name));
    s.options.parameterization = s.own.get();
  }
  return s;
}

std::vector<std::string> defaultNames(bool quick) {
  if (quick) return {"ggx-a0.3", "lambert"};
  std::vector<std::string> names;
  for (const Source& s : analyticSources()) names.push_back(s.name);
  for (const datagen::Preset& p : datagen::presets()) names.push_back(p.name);
  for (const std::string& name : defaultBenchMaterialNames(false))
    if (std::filesystem::path(name).extension() == ".bsdf") names.push_back(name);
  return names;
}

struct Row {
  std::string name;
  std::size_t bytes = 0;
  MaterialDifference difference;
  std::vector<float> chi2_theta_o;
  std::vector<double> chi2_p;
  double spectral_albedo_rel_error = 0;  // RglChannels::Spectra against the source, 0/30/60/75 deg
  double grazing_albedo_rel_error = 0;   // the RGB channels against the source, 70/75/80 deg
  double seconds = 0;
};

void writeCsv(const std::filesystem::path& path, const std::vector<Row>& rows) {
  writeFileAtomically(path, [&](std::ofstream& out) {
    out << "material,bytes,seconds,fcos_rel_rmse,max_albedo_rel_error,spectral_albedo_rel_error,grazing_albedo_rel_error";
    for (const float t : rows.front().difference.theta_o_deg) out << ",albedo_" << t << ",reference_albedo_" << t;
    for (const float t : rows.front().chi2_theta_o) out << ",chi2_p_" << t;
    out << '\n';
    for (const Row& r : rows) {
      out << '"' << r.name << "\"," << r.bytes << ',' << r.seconds << ',' << r.difference.fcos_rel_rmse << ','
          << r.difference.max_albedo_rel_error << ',' << r.spectral_albedo_rel_error << ',' << r.grazing_albedo_rel_error;
      for (std::size_t k = 0; k < r.difference.albedo.size(); ++k)
        out << ',' << r.difference.albedo[k].luminance() << ',' << r.difference.reference_albedo[k].luminance();
      for (const double p : r.chi2_p) out << ',' << p;
      out << '\n';
    }
  });
}

void run(const Args& a) {
  const std::vector<std::string> names = a.materials.empty() ? defaultNames(a.quick) : splitCommaList(a.materials);
  if (names.empty()) throw Error("--materials lists no material");
  std::filesystem::create_directories(a.output);
  Chi2Options chi2;
  chi2.sample_count = a.quick ? 50'000 : 400'000;
  std::printf("chi-square of each written file's own warp: %llu draws per view, significance %.2g\n",
              static_cast<unsigned long long>(chi2.sample_count), chi2.significance);
  std::printf("%-34s %9s %7s %9s %9s %9s %9s  %s\n", "material", "bytes", "seconds", "rel_rmse", "albedo", "spectral",
              "grazing", "chi2 p at 0/30/60/80 deg");
  std::vector<Row> rows;
  Progress progress("bench rgl-writer", names.size());
  for (const std::string& name : names) {
    const Source s = sourceNamed(name, a.resolutions);
    Row row;
    row.name = s.name;
    const auto start = std::chrono::steady_clock::now();
    std::vector<TensorField> fields = acquireRglFields(*s.material, s.options);
    row.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    row.bytes = encodeTensorFile(fields).size();
    const TensorFile file = inMemoryTensorFile(std::move(fields), s.name + ".bsdf");
    const RglBrdf written(file);
    MaterialDifferenceOptions compare;
    compare.pair_count = a.quick ? 50'000 : 400'000;
    row.difference = compareMaterials(written, *s.material, compare);
    // Albedo only: few pairs for the rel_rmse these two do not report.
    MaterialDifferenceOptions spectral_at = compare, grazing_at = compare;
    spectral_at.pair_count = grazing_at.pair_count = 1'000;
    spectral_at.theta_o_deg = {0.0f, 30.0f, 60.0f, 75.0f};
    grazing_at.theta_o_deg = {70.0f, 75.0f, 80.0f};
    row.spectral_albedo_rel_error =
        compareMaterials(RglBrdf(file, RglChannels::Spectra), *s.material, spectral_at).max_albedo_rel_error;
    row.grazing_albedo_rel_error = compareMaterials(written, *s.material, grazing_at).max_albedo_rel_error;
    for (const float t : {0.0f, 30.0f, 60.0f, 80.0f}) {
      row.chi2_theta_o.push_back(t);
      row.chi2_p.push_back(chi2TestMaterial(written, sphericalDirection(t * kPi / 180.0f, 0.3f), {}, chi2).p_value);
    }
    std::printf("%-34s %9zu %7.2f %9.4f %8.2f%% %8.2f%% %8.2f%% ", row.name.c_str(), row.bytes, row.seconds,
                row.difference.fcos_rel_rmse, 100.0 * row.difference.max_albedo_rel_error,
                100.0 * row.spectral_albedo_rel_error, 100.0 * row.grazing_albedo_rel_error);
    for (const double p : row.chi2_p) std::printf(" %.3f", p);
    std::printf("\n");
    std::fflush(stdout);
    rows.push_back(std::move(row));
    progress.advance();
  }
  int albedo_ok = 0, rmse_ok = 0, chi2_ok = 0, spectral_ok = 0, grazing_ok = 0;
  for (const Row& r : rows) {
    albedo_ok += r.difference.max_albedo_rel_error <= 0.01;
    rmse_ok += r.difference.fcos_rel_rmse <= 0.03;
    spectral_ok += r.spectral_albedo_rel_error <= 0.01;
    grazing_ok += r.grazing_albedo_rel_error <= 0.02;
    chi2_ok += std::all_of(r.chi2_p.begin(), r.chi2_p.end(), [&](double p) { return p > chi2.significance; });
  }
  std::printf("albedo within 1%% at every theta_o: %d of %zu; f cos rel_rmse within 3%%: %d of %zu; chi-square passed "
              "at all four views: %d of %zu\n",
              albedo_ok, rows.size(), rmse_ok, rows.size(), chi2_ok, rows.size());
  std::printf("spectral channels' albedo within 1%% at 0/30/60/75 deg: %d of %zu; albedo within 2%% at 70/75/80 deg: %d "
              "of %zu\n",
              spectral_ok, rows.size(), grazing_ok, rows.size());
  const std::filesystem::path csv = std::filesystem::path(a.output) / "rgl_writer.csv";
  writeCsv(csv, rows);
  std::printf("wrote %s (%zu rows)\n", csv.string().c_str(), rows.size());
}

}  // namespace
}  // namespace bench_rgl_writer

void addBenchRglWriterCommand(CLI::App& bench) {
  auto* cmd = bench.add_subcommand(
      "rgl-writer",
      "What an RGL .bsdf written by virtual acquisition (btf convert X out.bsdf) loses: rel_rmse of f cos and albedo "
      "error against the source, and the chi-square test of the written file's warp; CSV");
  auto a = std::make_shared<bench_rgl_writer::Args>();
  cmd->add_option("--materials", a->materials,
                  "Comma-separated: ggx-a0.05, ggx-a0.1, ggx-a0.3, ggx-a0.5, lambert, phong-n50, btf-datagen presets, or any "
                  "isotropic material file or spec (default: all of those and the shared RGL files)");
  cmd->add_flag("--quick", a->quick, "Two materials, few pairs and draws (for tests)");
  cmd->add_option("--theta-i", a->resolutions.theta_i_count,
                  "Incidence angles of the written files (an RGL source keeps its own)")->capture_default_str();
  cmd->add_option("--resolution", a->resolutions.resolution,
                  "Luminance/RGB nodes per side (an RGL source keeps its own)")->capture_default_str();
  cmd->add_option("--vndf-resolution", a->resolutions.vndf_resolution,
                  "VNDF nodes per side (an RGL source keeps its own)")->capture_default_str();
  cmd->add_option("--ndf-resolution", a->resolutions.ndf_resolution, "NDF and sigma nodes")->capture_default_str();
  cmd->add_option("-o,--output", a->output, "Output folder (rgl_writer.csv)")->required();
  cmd->callback([a] { bench_rgl_writer::run(*a); });
}

}  // namespace btf::cli
