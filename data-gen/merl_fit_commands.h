// btf-datagen's access to the published MERL fits: where the CSV tables are, listing them, and
// showing where the fits of one material disagree.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

#include "btf/io/merl_fits.h"

namespace btf::datagen {

// Fits disagree when their mean-RGB albedos at 0/30/60 degrees differ by more than this fraction
// of the largest (see compareMerlFits).
inline constexpr double kFitDisagreementThreshold = 0.10;

// The tables from --fits-dir if given (an error if it lacks them), else from the folder configured
// at build time (../shared/data/real/fits), else from the installed copy (share/libbtf/fits next
// to the executable's bin/). Throws btf::Error listing what was tried.
MerlFits loadMerlFits(const std::string& fits_dir_option);

// --list-merl-fits: every name with the models that fit it.
void listMerlFits(const MerlFits& fits, bool json);

// The comparison as JSON: {"name", "theta_o_deg", "fits": [{"model", "albedo": [[r,g,b]...]}],
// "spread", "spread_theta_o_deg", "threshold", "disagree"}.
nlohmann::json comparisonJson(const MerlFitComparison& comparison);
// Text: one line per model, then a "warning:" line when the fits disagree.
void printFitComparison(const MerlFitComparison& comparison);

}  // namespace btf::datagen
