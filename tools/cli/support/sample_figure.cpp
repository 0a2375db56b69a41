#include "sample_figure.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "btf/core/error.h"
#include "btf/core/math.h"
#include "figure_canvas.h"
#include "plot_figures.h"
#include "text_labels.h"

namespace btf::cli {
namespace {

constexpr int kFont = 15;
constexpr int kPanelWidth = 480, kPanelHeight = 240;
constexpr int kMarginLeft = 70, kMarginTop = 64, kPanelGap = 40, kMarginRight = 24;
constexpr int kAxisLabels = 52, kBarHeight = 14, kBarLabels = 40, kFooter = 40;
// The colour scale of densities spans this many decades below the largest cell.
constexpr float kDecades = 3.0f;
// Differences are clipped at this many standard deviations.
constexpr float kSigmaRange = 4.0f;

std::string format(const char* pattern, double v) {
  char text[48];
  std::snprintf(text, sizeof text, pattern, v);
  return text;
}

// Blue for too few draws, dark grey for agreement, orange for too many.
Rgb divergingMap(float t) {
  const Rgb neutral(0.22f), low(0.25f, 0.55f, 1.0f), high(1.0f, 0.55f, 0.15f);
  const float x = std::clamp(t, -1.0f, 1.0f);
  return x < 0 ? neutral * (1.0f + x) + low * (-x) : neutral * (1.0f - x) + high * x;
}

struct Panel {
  int x0, y0;
  int rows, cols;
};

// Fills the panel cell by cell: row r of the hemisphere at the top for cos(theta) = 1, phi from 0
// at the left to 360 degrees at the right.
template <typename ColorOf>
void paintCells(Image& canvas, const Panel& p, ColorOf color_of) {
  for (int y = 0; y < kPanelHeight; ++y) {
    const int row = std::min(p.rows - 1, y * p.rows / kPanelHeight);
    for (int x = 0; x < kPanelWidth; ++x) {
      const int col = std::min(p.cols - 1, x * p.cols / kPanelWidth);
      const Rgb c = color_of(row * p.cols + col);
      for (int ch = 0; ch < 3; ++ch) canvas.at(p.x0 + x, p.y0 + y, ch) = c[ch];
    }
  }
}

void drawAxes(Image& canvas, const Panel& p, bool with_y_labels) {
  for (int deg = 0; deg <= 360; deg += 90) {
    const int x = p.x0 + std::min(kPanelWidth - 1, deg * kPanelWidth / 360);
    fillRect(canvas, x, p.y0 + kPanelHeight, 1, 5, kInk);
    const std::string label = std::to_string(deg);
    drawText(canvas, x - textWidth(label, kFont) / 2, p.y0 + kPanelHeight + 7, label, kInk, kFont);
  }
  const std::string x_title = "phi_i (degrees)";
  drawText(canvas, p.x0 + (kPanelWidth - textWidth(x_title, kFont)) / 2, p.y0 + kPanelHeight + 27, x_title, kInk, kFont);
  if (!with_y_labels) return;
  for (float c : {1.0f, 0.5f, 0.0f}) {
    const int y = p.y0 + std::min(kPanelHeight - 1, int(std::lround((1.0f - c) * kPanelHeight)));
    fillRect(canvas, p.x0 - 5, y, 5, 1, kInk);
    const std::string label = format("%.1f", c);
    drawText(canvas, p.x0 - 9 - textWidth(label, kFont), y - textHeight(kFont) / 2, label, kInk, kFont);
  }
  const std::string y_title = "cos theta_i";
  drawTextVertical(canvas, 6, p.y0 + (kPanelHeight - textWidth(y_title, kFont)) / 2, y_title, kInk, kFont);
}

// A horizontal colour bar under a panel with labels at both ends and the middle.
template <typename MapOf>
void drawColorBar(Image& canvas, int x0, int y0, MapOf map_of, const std::string& lo, const std::string& mid,
                  const std::string& hi, const std::string& caption) {
  for (int x = 0; x < kPanelWidth; ++x) fillRect(canvas, x0 + x, y0, 1, kBarHeight, map_of(float(x) / float(kPanelWidth - 1)));
  const int label_y = y0 + kBarHeight + 4;
  drawText(canvas, x0, label_y, lo, kInk, kFont);
  drawText(canvas, x0 + (kPanelWidth - textWidth(mid, kFont)) / 2, label_y, mid, kInk, kFont);
  drawText(canvas, x0 + kPanelWidth - textWidth(hi, kFont), label_y, hi, kInk, kFont);
  drawText(canvas, x0 + (kPanelWidth - textWidth(caption, kFont)) / 2, label_y + textHeight(kFont) + 2, caption, kInk, kFont);
}

}  // namespace

Image renderSampleFigure(const Chi2Result& result, const std::string& title, const std::string& footer) {
  if (result.theta_bins % 2 != 0 || result.observed.size() != std::size_t(result.theta_bins) * result.phi_bins)
    throw Error("sample figure: the chi-square result needs an even number of theta bins and per-cell counts");
  const int rows = result.theta_bins / 2, cols = result.phi_bins;
  const int cells = rows * cols;
  // Densities per steradian: count / (N * cell solid angle); the cells are of equal solid angle.
  const double cell_sr = 4.0 * double(kPi) / double(result.theta_bins * result.phi_bins);
  const double scale = 1.0 / (double(std::max<std::uint64_t>(1, result.sample_count)) * cell_sr);
  double peak = 0;
  for (int k = 0; k < cells; ++k) peak = std::max({peak, result.observed[k] * scale, result.expected[k] * scale});
  const float log_max = float(std::log10(std::max(peak, 1e-30)));
  const float log_min = log_max - kDecades;
  auto density_color = [&](double density) {
    if (!(density > 0)) return colorMap(0.0f);
    return colorMap((float(std::log10(density)) - log_min) / kDecades);
  };

  const int bar_block = kBarHeight + 4 + 2 * textHeight(kFont) + 8;
  Image canvas(kMarginLeft + 3 * kPanelWidth + 2 * kPanelGap + kMarginRight,
               kMarginTop + kPanelHeight + kAxisLabels + bar_block + kBarLabels / 2 + kFooter, 3);
  fillRect(canvas, 0, 0, canvas.width, canvas.height, kPaper);
  drawText(canvas, kMarginLeft, 10, title, kInk, kFont + 2);

  const char* headings[3] = {"histogram of the draws (1/sr)", "integrated pdf (1/sr)",
                             "difference: (observed - expected) / sqrt(expected)"};
  for (int i = 0; i < 3; ++i) {
    const Panel p{kMarginLeft + i * (kPanelWidth + kPanelGap), kMarginTop, rows, cols};
    drawText(canvas, p.x0, kMarginTop - 24, headings[i], kInk, kFont);
    if (i == 0) paintCells(canvas, p, [&](int k) { return density_color(result.observed[k] * scale); });
    if (i == 1) paintCells(canvas, p, [&](int k) { return density_color(result.expected[k] * scale); });
    if (i == 2)
      paintCells(canvas, p, [&](int k) {
        const double e = result.expected[k], o = result.observed[k];
        if (e <= 0) return o > 0 ? divergingMap(1.0f) : divergingMap(0.0f);
        return divergingMap(float((o - e) / std::sqrt(e)) / kSigmaRange);
      });
    drawAxes(canvas, p, i == 0);
    const int bar_y = kMarginTop + kPanelHeight + kAxisLabels;
    if (i < 2) {
      drawColorBar(canvas, p.x0, bar_y, [](float t) { return colorMap(t); }, format("1e%.1f", log_min),
                   format("1e%.1f", log_min + 0.5 * kDecades), format("1e%.1f", log_max), "density, log scale");
    } else {
      drawColorBar(canvas, p.x0, bar_y, [](float t) { return divergingMap(2.0f * t - 1.0f); },
                   format("-%.0f", kSigmaRange), "0", format("+%.0f", kSigmaRange),
                   "standard deviations (clipped)");
    }
  }
  drawText(canvas, kMarginLeft, canvas.height - kFooter + 8, footer, kInk, kFont);
  return canvas;
}

}  // namespace btf::cli
