// What `btf fit-scene` found per material, and its reports: the candidates' and samplers' tables
// (CSV) and the chart of bytes against rendered error.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "fit_scene_candidates.h"
#include "fit_scene_measure.h"
#include "gnuplot_charts.h"

namespace btf::cli {

struct MaterialResult {
  std::string name, type;
  std::vector<MaterialCandidate> candidates;
  std::vector<double> relmse;  // per candidate: the error judged (NaN: not built)
  std::vector<RenderedError> errors;
  std::vector<FitSpeed> speed;
  int chosen = -1;             // index into candidates
  std::string skipped;         // why the material was not reduced at all
  // Sampler pass.
  struct SamplerTry {
    std::string name;
    std::size_t bytes = 0;
    double relmse = 0;  // the error judged
    RenderedError error;
  };
  std::vector<SamplerTry> samplers;
  int chosen_sampler = -1;
  bool sampler_within_budget = false;
};

// `number` with `digits` significant digits (%g).
std::string fixed(double number, int digits);

// <stem>.csv and <stem>-samplers.csv in `folder`, written atomically.
void writeFitSceneTables(const std::filesystem::path& folder, const std::string& stem, const std::vector<MaterialResult>& results);

// <stem>-chart.png/.svg: bytes against the error judged, per material, chosen points circled, the
// budget dashed.
tools::GnuplotOutcome drawFitSceneChart(const std::filesystem::path& folder, const std::string& stem,
                                        const std::vector<MaterialResult>& results, double budget);

}  // namespace btf::cli
