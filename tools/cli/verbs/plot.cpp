// `btf plot FILE -o out.png`: a labelled half/diff slice and a rendered sphere, side by side.
#include <optional>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "btf/core/error.h"
#include "btf/core/math.h"
#include "btf/material/tabulated_brdf.h"
#include "commands.h"
#include "figure_canvas.h"
#include "material_input.h"
#include "plot_figures.h"
#include "text_labels.h"

namespace btf::cli {
// Named after the file: the unity build compiles the commands together, and their helpers share
// names (Args, Row, the figure constants).
namespace plot_command {
namespace {

struct PlotOptions {
  std::string file;
  std::string output;
  int size = 320;
  float light_theta = 45.0f;
  float light_phi = 120.0f;
  float exposure = 0.0f;
  std::optional<TableLookup> lookup;  // the table types' default when not given
};

constexpr int kFont = 15;            // label font size in pixels
constexpr int kMarginLeft = 76;      // y tick labels and the vertical axis title
constexpr int kMarginTop = 44;       // panel titles
constexpr int kMarginBottom = 64;    // x tick labels and axis title
constexpr int kColorBarGap = 12, kColorBarWidth = 14, kColorBarLabels = 70, kPanelGap = 28, kMarginRight = 20;

void blit(Image& dst, const Image& src, int x0, int y0) {
  for (int y = 0; y < src.height; ++y)
    for (int x = 0; x < src.width; ++x)
      for (int c = 0; c < 3; ++c) dst.at(x0 + x, y0 + y, c) = src.at(x, y, c);
}

std::string formatNumber(float v, int decimals) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*f", decimals, v);
  return text;
}

void drawSliceAxes(Image& canvas, int x0, int y0, int size) {
  for (float deg : {0.0f, 5.0f, 20.0f, 45.0f, 90.0f}) {
    const int x = x0 + sliceColumnOf(deg, size);
    fillRect(canvas, x, y0 + size, 1, 6, kInk);
    const std::string label = formatNumber(deg, 0);
    drawText(canvas, x - textWidth(label, kFont) / 2, y0 + size + 10, label, kInk, kFont);
  }
  const std::string x_title = "theta_h (degrees, square-root scale)";
  drawText(canvas, x0 + (size - textWidth(x_title, kFont)) / 2, y0 + size + 36, x_title, kInk, kFont);
  for (float deg : {0.0f, 30.0f, 60.0f, 90.0f}) {
    const int y = y0 + int(std::lround((1.0f - deg / 90.0f) * float(size - 1)));
    fillRect(canvas, x0 - 6, y, 6, 1, kInk);
    const std::string label = formatNumber(deg, 0);
    drawText(canvas, x0 - 10 - textWidth(label, kFont), y - textHeight(kFont) / 2, label, kInk, kFont);
  }
  const std::string y_title = "theta_d (degrees)";
  drawTextVertical(canvas, 8, y0 + (size - textWidth(y_title, kFont)) / 2, y_title, kInk, kFont);
}

void drawColorBar(Image& canvas, int x0, int y0, int size, const SliceFigure& slice) {
  for (int y = 0; y < size; ++y) fillRect(canvas, x0, y0 + y, kColorBarWidth, 1, colorMap(1.0f - float(y) / float(size - 1)));
  const int steps = 4;
  for (int i = 0; i <= steps; ++i) {
    const float t = float(i) / float(steps);
    const int y = y0 + int(std::lround((1.0f - t) * float(size - 1)));
    const std::string label = formatNumber(slice.log10_min + t * (slice.log10_max - slice.log10_min), 1);
    fillRect(canvas, x0 + kColorBarWidth, y, 4, 1, kInk);
    drawText(canvas, x0 + kColorBarWidth + 8, y - textHeight(kFont) / 2, label, kInk, kFont);
  }
  drawText(canvas, x0, kMarginTop - 30, "log10", kInk, kFont);
}

void runPlot(const PlotOptions& o) {
  OpenOptions options;
  options.lookup = o.lookup;
  IdentifiedMaterial material = identifyMaterial(o.file, options);  // an unknown input is named before a bad output
  if (std::filesystem::path(o.output).extension() != ".png")
    throw FileError(o.output, "plot writes PNG images: give the output a .png name");
  const BrdfInput input = openBrdfInput(std::move(material), o.file, o.lookup);
  const Material& brdf = *input.brdf;

  const int size = o.size;
  const int slice_x = kMarginLeft;
  const int bar_x = slice_x + size + kColorBarGap;
  const int sphere_x = bar_x + kColorBarWidth + kColorBarLabels + kPanelGap;
  Image canvas(sphere_x + size + kMarginRight, kMarginTop + size + kMarginBottom, 3);
  fillRect(canvas, 0, 0, canvas.width, canvas.height, kPaper);

  const SliceFigure slice = renderHalfDiffSlice(brdf, size);
  blit(canvas, slice.image, slice_x, kMarginTop);
  drawText(canvas, slice_x, kMarginTop - 30, "log10 f*cos(theta_i) at phi_d = 90 deg", kInk, kFont);
  drawSliceAxes(canvas, slice_x, kMarginTop, size);
  drawColorBar(canvas, bar_x, kMarginTop, size, slice);

  const float to_radians = kPi / 180.0f;
  const glm::vec3 light = sphericalDirection(o.light_theta * to_radians, o.light_phi * to_radians);
  blit(canvas, renderSpherePreview(brdf, size, light, o.exposure), sphere_x, kMarginTop);
  const std::string sphere_title = "light at theta " + formatNumber(o.light_theta, 0) + ", phi " + formatNumber(o.light_phi, 0) + " deg";
  drawText(canvas, sphere_x, kMarginTop - 30, sphere_title, kInk, kFont);
  const std::string exposure = "exposure " + formatNumber(o.exposure, 1) + " stops";
  drawText(canvas, sphere_x, kMarginTop + size + 10, exposure, kInk, kFont);

  writeImage(o.output, canvas);
  std::printf("wrote %s (%dx%d)\n", o.output.c_str(), canvas.width, canvas.height);
}

}  // namespace
}  // namespace plot_command

void registerPlotCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("plot", "PNG of a BRDF slice (log f*cos over theta_h x theta_d at phi_d = 90 deg) "
                                         "beside a sphere rendered under one directional light");
  auto o = std::make_shared<plot_command::PlotOptions>();
  cmd->add_option("FILE", o->file, "Measured material (.binary MERL, .exr from btf convert, .bsdf RGL, .json btf fit or .octree)")->required();
  cmd->add_option("-o,--output", o->output, "Output PNG, written atomically")->required();
  cmd->add_option("--size", o->size, "Pixel size of each square panel")->check(CLI::Range(64, 2048))->capture_default_str();
  cmd->add_option("--light-theta", o->light_theta, "Light angle from the view direction (deg)")
      ->check(CLI::Range(0.0f, 89.0f))->capture_default_str();
  cmd->add_option("--light-phi", o->light_phi, "Light azimuth in the image plane, from +x (right) towards up (deg)")
      ->check(CLI::Range(-360.0f, 360.0f))->capture_default_str();
  cmd->add_option("--exposure", o->exposure, "Sphere exposure in stops")->check(CLI::Range(-20.0f, 20.0f))->capture_default_str();
  addLookupOption(*cmd, o->lookup, "Table lookup of a MERL-layout table");
  cmd->callback([o] { plot_command::runPlot(*o); });
}

}  // namespace btf::cli
