// `btf convert IN OUT`: MERL .binary <-> EXR stack of half/diff slices (layout in merl_exr_stack.h);
// an RGL .bsdf material converts to either by tabulating it into the MERL layout.
#include <cstdio>
#include <memory>

#include "btf/core/error.h"
#include "commands.h"
#include "measured_file.h"
#include "merl_exr_stack.h"

namespace btf::cli {
namespace {

void runConvert(const std::string& in, const std::string& out) {
  const MeasuredFormat from = measuredFormatOf(in);
  const MeasuredFormat to = measuredFormatOf(out);
  if (to == MeasuredFormat::RglTensor) throw FileError(out, "convert cannot write .bsdf files (RGL tensor_file is read-only here)");
  if (from == to) throw FileError(out, "has the same format as " + in + "; convert goes .binary -> .exr or .exr -> .binary");
  const MerlTable table = loadMeasuredTable(in);
  if (to == MeasuredFormat::ExrStack) writeImageStack(out, merlToExrStack(table));
  else writeMerl(out, table);
  std::printf("wrote %s (%s)\n", out.c_str(), describe(to).c_str());
}

}  // namespace

void registerConvertCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "convert",
      "Convert MERL .binary <-> EXR stack (.exr), or tabulate an RGL .bsdf into either: 90 parts, one per theta_h index, each 180x90 RGB float of "
      "phi_d x theta_d with f in 1/sr; unmeasured samples stay negative; 32-bit float precision");
  auto in = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  cmd->add_option("IN", *in, "Input (.binary, .exr or .bsdf)")->required();
  cmd->add_option("OUT", *out, "Output (.exr or .binary), written atomically")->required();
  cmd->callback([in, out] { runConvert(*in, *out); });
}

}  // namespace btf::cli
