// btf-datagen's reports on the published MERL fits (the tables are found by btf::loadMerlFits):
// listing them, and showing where the fits of one material disagree.
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "btf/fit/merl_fits.h"

namespace btf::datagen {

// Fits disagree strongly when their mean-RGB albedos at 0/30/60 degrees differ by more than this
// fraction of the largest (see compareMerlFits). A much tighter threshold would flag nearly all
// MERL materials, which tells a user nothing.
inline constexpr double kFitDisagreementThreshold = 0.30;

// The comparison of the published fits of the material a measured file is named after (its stem,
// as MERL names its files: gold-metallic-paint.binary), or of `name` when given. Nothing when the
// name is no fitted material or the fit tables cannot be found (then only a note is logged).
std::optional<MerlFitComparison> compareFitsOfFile(const std::filesystem::path& file, const std::string& name = "");

// --list-merl-fits: every name with the models that fit it.
void listMerlFits(const MerlFits& fits, bool json);

// The comparison as JSON: {"name", "theta_o_deg", "fits": [{"model", "albedo": [[r,g,b]...]}],
// "spread", "spread_theta_o_deg", "threshold", "disagree"}.
nlohmann::json comparisonJson(const MerlFitComparison& comparison);
// Text: one line per model, then a "warning:" line when the fits disagree.
void printFitComparison(const MerlFitComparison& comparison);

}  // namespace btf::datagen
