// `btf eval FILE`: the table's f at one pair of directions, in degrees.
#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>
#include <memory>

#include "btf/core/error.h"
#include "btf/core/half_diff.h"
#include "btf/core/math.h"
#include "btf/material/tabulated_brdf.h"
#include "commands.h"
#include "material_input.h"

namespace btf::cli {
namespace {

// Angles are kept as the user typed them (double) so that --json echoes 10 as 10.0, not as the
// float 10.000000953674316; they become float only where the directions are formed.
struct EvalOptions {
  std::string file;
  double theta_i = 0, phi_i = 0, theta_o = 0, phi_o = 0;
  std::vector<double> half_diff;  // theta_h, theta_d, phi_d
  std::optional<TableLookup> lookup;
  bool json = false;
};

float radians(double degrees) { return float(degrees * double(kPi) / 180.0); }

void runEval(const EvalOptions& o) {
  const BrdfInput input = openBrdfInput(o.file, o.lookup);
  const Material& brdf = *input.brdf;
  glm::vec3 wi, wo;
  if (!o.half_diff.empty()) {
    HalfDiff hd;
    hd.theta_h = radians(o.half_diff[0]);
    hd.theta_d = radians(o.half_diff[1]);
    hd.phi_d = radians(o.half_diff[2]);
    const DirectionPair pair = fromHalfDiff(hd);
    wi = pair.wi;
    wo = pair.wo;
  } else {
    wi = sphericalDirection(radians(o.theta_i), radians(o.phi_i));
    wo = sphericalDirection(radians(o.theta_o), radians(o.phi_o));
  }
  const Rgb f = brdf.eval(wi, wo);
  const char* lookup = input.evaluation;
  const float deg = 180.0f / kPi;
  if (o.json) {
    nlohmann::json out{{"file", o.file}, {"lookup", lookup}};
    if (o.half_diff.empty()) {
      out.update({{"theta_i_deg", o.theta_i}, {"phi_i_deg", o.phi_i}, {"theta_o_deg", o.theta_o}, {"phi_o_deg", o.phi_o}});
    } else {
      // The directions the half/diff angles give, as angles of their own (computed, so in float).
      out.update({{"theta_h_deg", o.half_diff[0]},
                  {"theta_d_deg", o.half_diff[1]},
                  {"phi_d_deg", o.half_diff[2]},
                  {"theta_i_deg", double(sphericalTheta(wi) * deg)},
                  {"phi_i_deg", double(sphericalPhi(wi) * deg)},
                  {"theta_o_deg", double(sphericalTheta(wo) * deg)},
                  {"phi_o_deg", double(sphericalPhi(wo) * deg)}});
    }
    out["f"] = {f.r, f.g, f.b};
    std::cout << out.dump(2) << "\n";
    return;
  }
  std::printf("f = %.6g %.6g %.6g (1/sr, %s) at theta_i %.2f phi_i %.2f theta_o %.2f phi_o %.2f deg\n", f.r, f.g, f.b,
              lookup, sphericalTheta(wi) * deg, sphericalPhi(wi) * deg, sphericalTheta(wo) * deg,
              sphericalPhi(wo) * deg);
}

}  // namespace

void registerEvalCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("eval", "Value f (1/sr, RGB) of a measured table at one pair of directions (degrees)");
  auto o = std::make_shared<EvalOptions>();
  cmd->add_option("FILE", o->file, "Measured material (.binary MERL, .exr from btf convert, .bsdf RGL, .json btf fit or .octree)")->required();
  const auto angle = CLI::Range(-360.0, 360.0);
  auto* ti = cmd->add_option("--theta-i", o->theta_i, "Light polar angle")->check(CLI::Range(0.0, 90.0))->capture_default_str();
  auto* pi = cmd->add_option("--phi-i", o->phi_i, "Light azimuth")->check(angle)->capture_default_str();
  auto* to = cmd->add_option("--theta-o", o->theta_o, "View polar angle")->check(CLI::Range(0.0, 90.0))->capture_default_str();
  auto* po = cmd->add_option("--phi-o", o->phi_o, "View azimuth")->check(angle)->capture_default_str();
  cmd->add_option("--half-diff", o->half_diff, "Rusinkiewicz angles THETA_H THETA_D PHI_D instead (phi_h = 0)")
      ->expected(3)
      ->excludes(ti)->excludes(pi)->excludes(to)->excludes(po);
  addLookupOption(*cmd, o->lookup, "Table lookup of a MERL-layout table (not of an RGL .bsdf or a model)");
  cmd->add_flag("--json", o->json, "Machine-readable output");
  cmd->callback([o] { runEval(*o); });
}

}  // namespace btf::cli
