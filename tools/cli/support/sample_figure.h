// The picture of `btf sample`: over the upper hemisphere's cells of a chi-square test (equal solid
// angle: uniform in cos(theta) and phi), the histogram of the draws beside the pdf integrated over
// each cell, on one logarithmic colour scale of density (1/sr), and their difference in standard
// deviations ((observed - expected) / sqrt(expected)), which is what the chi-square statistic sums.
#pragma once

#include <string>

#include "btf/io/image.h"
#include "btf/sampling/chi2.h"

namespace btf::cli {

// An sRGB canvas with three labelled panels and their colour bars; `title` heads it and `footer`
// (the test's verdict) is printed below. The result needs an even theta_bins (hemisphere rows).
Image renderSampleFigure(const Chi2Result& result, const std::string& title, const std::string& footer);

}  // namespace btf::cli
