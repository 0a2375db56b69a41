// btf-datagen's access to the published MERL fits: where the CSV tables are, listing them, and
// showing where the fits of one material disagree.
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

// The tables from --fits-dir if given (an error if it lacks them), else from the folder configured
// at build time (../shared/data/real/fits), else from the installed copy (share/libbtf/fits next
// to the executable's bin/). Throws btf::Error listing what was tried.
MerlFits loadMerlFits(const std::string& fits_dir_option);
// The folders searched when no --fits-dir is given, in order (for scenes with merl-fit materials).
std::vector<std::filesystem::path> defaultFitsFolders();

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
