// The JSON file of a fitted analytic model (`btf fit -o params.json`), usable as a material
// anywhere a file is (`btf info/eval/plot/sample`, {"type": "fitted", "file": ...} in a scene):
//   {"format": "libbtf-fit", "version": 1, "model": "ggx" | "ggx2" | "abc" | "ward" | "lafortune",
//    "parameters": {"diffuse": [r, g, b], "f0": [r, g, b], "alpha": a}             (ggx)
//                  {ggx's, "f0_2": [r, g, b], "alpha_2": a}                        (ggx2)
//                  {"diffuse": [...], "a": [r, g, b], "b": B, "c": C, "ior": n}    (abc)
//                  {"diffuse": [...], "specular": [...], "alpha": a}               (ward)
//                  {"diffuse": [...], "lobes": [{"rho": [...], "c": [cx, cy, cz],
//                                                "exponent": n}, ...]}             (lafortune)
//    "fit": {"source", "rel_rmse", "converged", "cost", "samples", "excluded", "starts",
//            "screening_converged", "iterations", "seconds", "ceres", "albedo": [{"theta_o_deg",
//            "data", "fit", "rel_error"}, ...], "warnings": [...]}}               (informative)
// The parameter keys are those of the same models written inline in a scene.
#pragma once

#include <filesystem>
#include <string>

#include "btf/fit/analytic_fit.h"

namespace btf {

inline constexpr const char* kFitFileFormat = "libbtf-fit";

// Writes through a temporary file renamed into place. `source` names the data fitted.
void writeFitFile(const std::filesystem::path& path, const AnalyticFit& fit, const std::string& source);

// Throws FileError naming the file and the problem (missing, not JSON, another format or version,
// an unknown model, a missing, misspelt or out-of-range parameter).
AnalyticParameters readFitFile(const std::filesystem::path& path);

}  // namespace btf
