// `btf convert IN OUT`: between the MERL-layout table formats. MERL .binary <-> EXR stack of
// half/diff slices (layout in btf/io/merl_exr_stack.h); any other BRDF the registry opens (an RGL
// .bsdf, a fit, a merl-fit spec) converts to either by tabulating it into the MERL layout; any of
// them converts to an octree table (.octree, compress/octree_table.h) with --tolerance, and an
// octree back to a table. And between BTF layouts: any BTF the registry opens (an image folder, a
// Bonn .btf file, a .btfz) to an image folder or a Bonn .btf file (support/btf_output.h). Any
// isotropic material, or a BTF texel, to an RGL .bsdf by virtual acquisition (support/rgl_output.h).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "btf/compress/octree_table.h"
#include "btf/core/error.h"
#include "btf/fit/analytic_fit.h"
#include "btf/io/image.h"
#include "btf/io/merl_exr_stack.h"
#include "btf/material/registry.h"
#include "btf_output.h"
#include "commands.h"
#include "material_input.h"
#include "rgl_output.h"

namespace btf::cli {
namespace {

struct ConvertOptions {
  std::string in, out;
  double tolerance = 0;
  bool tolerance_given = false;
  BtfOutputOptions btf;
  RglOutputOptions rgl;
};

// The largest relative difference of a measured cell from its stored value: the quantity the
// tolerance bounds (|stored - cell| <= tolerance * |stored| per channel).
double largestRelativeError(const MerlTable& table, const MerlTable& stored) {
  double worst = 0;
  for (std::size_t c = 0; c < MerlTable::kEntriesPerChannel; ++c) {
    if (!table.isMeasured(c)) continue;
    for (int ch = 0; ch < 3; ++ch) {
      const double s = stored.raw(ch, c), d = std::abs(s - table.raw(ch, c));
      if (d > 0) worst = std::max(worst, s != 0 ? d / std::abs(s) : INFINITY);
    }
  }
  return worst;
}

// What convert writes, by the output's extension.
enum class TableOutput { MerlBinary, ExrStack, Octree };

TableOutput tableOutputOf(const std::filesystem::path& path) {
  const std::string ext = path.extension().string();
  if (ext == ".binary") return TableOutput::MerlBinary;
  if (ext == ".exr") return TableOutput::ExrStack;
  if (ext == ".octree") return TableOutput::Octree;
  if (ext == ".json") throw FileError(path, "convert does not write fits; btf fit does");
  throw FileError(path, "convert writes .binary (MERL), .exr (a stack of MERL half/diff slices), .octree or .bsdf (RGL)");
}

// The registered format of that extension: the one the file will be read back as.
const MaterialFileFormat& formatOf(const std::filesystem::path& path) {
  for (const MaterialType* t : materialTypes())
    for (const MaterialFileFormat& f : t->formats)
      if (std::find(f.extensions.begin(), f.extensions.end(), path.extension().string()) != f.extensions.end()) return f;
  throw FileError(path, "no registered format has this extension");
}

void writeOctree(const ConvertOptions& o, const MerlTable& table) {
  const OctreeTable octree = OctreeTable::build(table, o.tolerance);
  writeOctreeFile(o.out, octree);
  const MerlTable stored = octree.expand();
  const double full_bytes = double(sizeof(std::int32_t) * 3 + table.values.size() * sizeof(double));
  const auto bytes = std::uintmax_t(std::filesystem::file_size(o.out));
  std::printf("wrote %s (%s)\n", o.out.c_str(), formatOf(o.out).description.c_str());
  std::printf("  tolerance   %g (every cell within tolerance x |stored value|, per channel)\n", o.tolerance);
  std::printf("  tree        %zu nodes, %zu leaves (of %zu cells)\n", octree.nodes().size(), octree.leaves().size(),
              MerlTable::kEntriesPerChannel);
  std::printf("  bytes       %ju (%.2f%% of the %.0f of a MERL .binary)\n", bytes, 100.0 * double(bytes) / full_bytes, full_bytes);
  std::printf("  rel_rmse    %.3g of f cos within 80 deg of the normal, cell by cell (as btf fit measures)\n",
              tableRelRmse(stored, table));
  std::printf("  max error   %.3g relative, over measured cells\n", largestRelativeError(table, stored));
}

void runConvert(const ConvertOptions& o) {
  const IdentifiedMaterial from = identifyMaterial(o.in);
  if (std::filesystem::path(o.out).extension() == ".bsdf") {
    if (o.tolerance_given) throw Error("--tolerance applies to an .octree output, not to " + o.out);
    if (!(o.btf == BtfOutputOptions{})) throw Error("the BTF output options do not apply to an RGL file (" + o.out + ")");
    return writeRglOutput(from, o.in, o.out, o.rgl);
  }
  if (o.rgl.given() || !o.rgl.texel.empty())
    throw Error("--theta-i, --resolution, --vndf-resolution, --ndf-resolution, --description, --rgb-only and --texel apply to an "
                "RGL output (OUT ending in .bsdf), not to " + o.out);
  if (isBtf(from)) {
    if (o.tolerance_given) throw Error("--tolerance applies to an .octree output of a BRDF, not to the BTF " + o.in);
    return writeBtfOutput(*materialBtf(from), o.out, o.btf);
  }
  if (!(o.btf == BtfOutputOptions{}))
    throw Error("--layout, --format, --components, --relative-error, --scalar, --color-model and --log apply to a "
                "BTF input; " + o.in + " is a BRDF");
  const TableOutput to = tableOutputOf(o.out);
  const bool same = from.format == &formatOf(o.out);
  if (same && to != TableOutput::Octree)  // an octree may be rebuilt at another tolerance
    throw FileError(o.out, "has the same format as " + o.in + "; convert changes the format");
  if (o.tolerance_given && to != TableOutput::Octree)
    throw Error("--tolerance applies to an .octree output only, not to " + o.out);
  const MerlTable table = materialTable(from);
  if (to == TableOutput::Octree) return writeOctree(o, table);
  if (to == TableOutput::ExrStack) writeImageStack(o.out, merlToExrStack(table));
  else writeMerl(o.out, table);
  std::printf("wrote %s (%s)\n", o.out.c_str(), formatOf(o.out).description.c_str());
}

}  // namespace

void registerConvertCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "convert",
      "Convert between MERL-layout tables: MERL .binary <-> EXR stack (.exr: 90 parts, one per theta_h index, each 180x90 RGB "
      "float of phi_d x theta_d with f in 1/sr; unmeasured samples stay negative), -> octree (.octree, lossless at tolerance "
      "0), and from an RGL .bsdf or a btf fit .json by tabulating it. Any isotropic material (or a BTF texel with --texel) "
      "-> an RGL .bsdf by virtual acquisition (Dupuy & Jakob 2018), with RGB and spectra for pbrt-v4 and Mitsuba 3's measured plugins (--rgb-only: for Mitsuba 3's RGB variants). A BTF (image folder, Bonn .btf, .btfz) converts to "
      "an image folder or a Bonn .btf file (OUT ending in .btf: DFMF, FMF or PVF by a truncated SVD)");
  auto o = std::make_shared<ConvertOptions>();
  cmd->add_option("IN", o->in,
                  "Input: any BRDF the registry opens (.binary, .exr, .octree, .bsdf, a fit .json, merl-fit:MODEL:NAME), "
                  "or a BTF (an image folder, a Bonn .btf, a .btfz)")
      ->required();
  cmd->add_option("OUT", o->out, "Output (.binary, .exr, .octree or .bsdf; for a BTF a folder, .btf, or .bsdf with --texel), written atomically")
      ->required();
  addBtfOutputOptions(*cmd, o->btf);
  addRglOutputOptions(*cmd, o->rgl);
  cmd->add_option_function<double>(
         "--tolerance",
         [o](double t) {
           o->tolerance = t;
           o->tolerance_given = true;
         },
         "Octree output: neighbouring cells merge while max - min <= t (|max| + |min|) in every channel, so each cell "
         "stays within t x its stored value; 0 (default) is lossless")
      ->check(CLI::NonNegativeNumber);
  cmd->callback([o] { runConvert(*o); });
}

}  // namespace btf::cli
