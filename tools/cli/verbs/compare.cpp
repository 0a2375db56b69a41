// `btf compare A B`: how far a test image A is from a reference image B (relmse, rel_rmse,
// psnr_db, max_abs), and optionally a heat map of the relative error. When A and B are BTFs (image
// folders or .btfz files), how far BTF A is from BTF B over B's views: rel_rmse, psnr_db, the
// displayed rel_rmse and mean SSIM (io/btf_quality.h) and B's noise floor; --material picks one
// material of a .btfz database.
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "btf/core/error.h"
#include "btf/io/btf_quality.h"
#include "btf/io/image.h"
#include "btf/render/image_metrics.h"
#include "material_input.h"
#include "commands.h"

namespace btf::cli {
namespace {

struct CompareOptions {
  std::string test, reference, output;
  std::string material;  // of whichever BTF is a .btfz database
  double scale = 0.5;
  bool json = false;
};

// JSON has no infinity: a non-finite measure (psnr_db of equal images) is written as "inf" or
// "-inf", a string, rather than as null.
nlohmann::json measureJson(double v) {
  if (std::isfinite(v)) return v;
  if (std::isnan(v)) return "nan";
  return v > 0 ? "inf" : "-inf";
}

std::string formatMeasure(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

void runBtfCompare(const CompareOptions& o) {
  if (!o.output.empty()) throw Error("compare: -o (a heat map) is for images, not BTFs");
  auto open = [&](const std::string& path) {
    return openBtfInput(path, std::filesystem::path(path).extension() == ".btfz" ? o.material : std::string());
  };
  if (!o.material.empty() && std::filesystem::path(o.test).extension() != ".btfz" &&
      std::filesystem::path(o.reference).extension() != ".btfz")
    throw Error("compare: --material names a material of a .btfz database, and neither " + o.test + " nor " +
                o.reference + " is one");
  const BtfInput test = open(o.test), reference = open(o.reference);
  const BtfQuality quality = compareBtfQuality(*reference.source, *test.source);
  const BtfErrorStats& e = quality.error;
  const BtfSsimStats& ssim = quality.ssim;
  const BtfNoiseFloor& noise = quality.noise;
  const nlohmann::json out{{"test", o.test},
                           {"reference", o.reference},
                           {"texels", {reference.source->width(), reference.source->height()}},
                           {"views", reference.source->views().views()},
                           {"rel_rmse", measureJson(e.rel_rmse)},
                           {"psnr_db", measureJson(e.psnr_db)},
                           {"rel_rmse_display", measureJson(ssim.rel_rmse_display)},
                           {"mean_ssim", ssim.mean_ssim},
                           {"min_image_ssim", ssim.min_image_ssim},
                           {"ssim_white", ssim.white},
                           {"noise_rel_rmse", noise.rel_rmse}};
  if (o.json) {
    std::cout << out.dump(2) << "\n";
    return;
  }
  std::printf("test BTF %s against reference BTF %s: %d x %d texels, %s x %s\n", o.test.c_str(),
              o.reference.c_str(), reference.source->width(), reference.source->height(),
              reference.source->views().describe().c_str(), reference.source->directions().describeLights().c_str());
  std::printf("rel_rmse         %s  (RMSE / RMS of B, linear values)\n", formatMeasure(e.rel_rmse).c_str());
  std::printf("psnr_db          %s  (peak = max of B)\n", formatMeasure(e.psnr_db).c_str());
  std::printf("rel_rmse_display %s  (sRGB-encoded, clipped to white %g)\n", formatMeasure(ssim.rel_rmse_display).c_str(),
              double(ssim.white));
  std::printf("mean_ssim        %.6f  (worst image %.6f; luma, 8 x 8 windows, %zu images)\n", ssim.mean_ssim,
              ssim.min_image_ssim, ssim.images);
  std::printf("noise floor of B %s  (rel_rmse; rel_rmse is %.2f x it)\n", formatMeasure(noise.rel_rmse).c_str(),
              noise.rel_rmse > 0 ? e.rel_rmse / noise.rel_rmse : 0.0);
}

void runCompare(const CompareOptions& o) {
  // A BTF is what the registry opens as one (a folder, a Bonn .btf, a .btfz); anything else is
  // compared as an image, whose reader names its own problems.
  std::error_code ec;
  auto isBtfPath = [&](const std::string& p) {
    if (std::filesystem::is_directory(p, ec)) return true;
    try {
      return isBtf(identifyMaterial(p));
    } catch (const Error&) {
      return false;
    }
  };
  const bool test_btf = isBtfPath(o.test), reference_btf = isBtfPath(o.reference);
  if (test_btf || reference_btf) {
    if (!test_btf || !reference_btf)
      throw Error("compare: " + o.test + " and " + o.reference +
                  " must both be images or both be BTFs (image folders, Bonn .btf or .btfz files)");
    runBtfCompare(o);
    return;
  }
  if (!o.material.empty()) throw Error("compare: --material is for BTFs (.btfz databases), not images");
  const Image test = readImage(o.test);
  const Image reference = readImage(o.reference);
  const render::ImageComparison c = render::compareImages(test, reference, o.test, o.reference);
  if (!o.output.empty()) writeImage(o.output, render::errorHeatMap(test, reference, o.scale, o.test, o.reference));

  const std::string legend = "per-pixel |A - B| / (|B| + 0.01), mean over channels, viridis: dark purple = 0, teal = " +
                             formatMeasure(0.5 * o.scale) + ", yellow >= " + formatMeasure(o.scale);
  if (o.json) {
    nlohmann::json out{{"test", o.test},
                       {"reference", o.reference},
                       {"width", c.width},
                       {"height", c.height},
                       {"channels", c.channels},
                       {"relmse", measureJson(c.relmse)},
                       {"rel_rmse", measureJson(c.rel_rmse)},
                       {"psnr_db", measureJson(c.psnr_db)},
                       {"max_abs", measureJson(c.max_abs)}};
    if (!o.output.empty()) out["heat_map"] = {{"file", o.output}, {"scale", o.scale}, {"legend", legend}};
    std::cout << out.dump(2) << "\n";
    return;
  }
  std::printf("test %s against reference %s: %dx%d, %s\n", o.test.c_str(), o.reference.c_str(), c.width, c.height,
              c.channels == 3 ? "RGB" : "grey");
  std::printf("relmse   %s  (mean (A-B)^2 / (B^2 + 0.01))\n", formatMeasure(c.relmse).c_str());
  std::printf("rel_rmse %s  (RMSE / RMS of B)\n", formatMeasure(c.rel_rmse).c_str());
  std::printf("psnr_db  %s  (peak = max of B)\n", formatMeasure(c.psnr_db).c_str());
  std::printf("max_abs  %s\n", formatMeasure(c.max_abs).c_str());
  if (!o.output.empty()) std::printf("wrote %s: %s\n", o.output.c_str(), legend.c_str());
}

}  // namespace

void registerCompareCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "compare",
      "Compare a test image with a reference (relmse, rel_rmse, psnr_db, max_abs), or a test BTF with a reference BTF "
      "(rel_rmse, psnr_db, displayed rel_rmse, mean SSIM, the reference's noise floor)");
  auto o = std::make_shared<CompareOptions>();
  cmd->add_option("A", o->test,
                  "Test image (EXR or any format OpenImageIO reads; linear values), or a BTF (image folder or .btfz)")
      ->required();
  cmd->add_option("B", o->reference, "Reference image, the same size, or a BTF holding the views to compare")->required();
  cmd->add_option("-o,--output", o->output,
                  "Write a heat map of the relative error |A - B| / (|B| + 0.01) (viridis, sRGB; .png)");
  cmd->add_option("--scale", o->scale, "Relative error at the top (yellow) of the heat map")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--material", o->material,
                  "The material of a .btfz database to compare (of A, B or both, whichever are databases; btf info "
                  "lists them)");
  cmd->add_flag("--json", o->json, "Machine-readable output (a non-finite measure is the string \"inf\" or \"-inf\")");
  cmd->callback([o] { runCompare(*o); });
}

}  // namespace btf::cli
