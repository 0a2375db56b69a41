#include "fit_scene_report.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "btf/io/atomic_file.h"

namespace btf::cli {
namespace {

// A candidate's name on the chart: "ggx", "lafortune 2 lobes", "octree 0.03", "vq 0.1", "full".
std::string shortLabel(const MaterialCandidate& c) {
  std::string label = c.label;
  for (const char* cut : {"fit ", " of the mean texel", " (81 x 81 directions)", "t=", "eps="}) {
    const std::size_t at = label.find(cut);
    if (at != std::string::npos) label.erase(at, std::string(cut).size());
  }
  return c.kind == "full" ? "full" : label;
}

}  // namespace

std::string fixed(double number, int digits) {
  char text[48];
  std::snprintf(text, sizeof text, "%.*g", digits, number);
  return text;
}

void writeFitSceneTables(const std::filesystem::path& folder, const std::string& stem, const std::vector<MaterialResult>& results) {
  writeFileAtomically(folder / (stem + ".csv"), [&](std::ofstream& out) {
    out << "material,type,candidate,kind,bytes,eval_per_s,samples_per_s,relmse_image,relmse_seen,chosen,note\n";
    for (const MaterialResult& r : results)
      for (std::size_t i = 0; i < r.candidates.size(); ++i) {
        const MaterialCandidate& c = r.candidates[i];
        std::string note = c.note;
        std::replace(note.begin(), note.end(), ',', ';');
        out << r.name << ',' << r.type << ',' << c.label << ',' << c.kind << ',' << c.bytes << ',' << r.speed[i].eval_per_s << ','
            << r.speed[i].samples_per_s << ',' << (c.material ? fixed(r.errors[i].image, 6) : "") << ','
            << (c.material ? fixed(r.errors[i].seen, 6) : "") << ',' << (int(i) == r.chosen) << ','
            << note << '\n';
      }
  });
  writeFileAtomically(folder / (stem + "-samplers.csv"), [&](std::ofstream& out) {
    out << "material,sampler,bytes,relmse_noise_image,relmse_noise_seen,chosen,within_budget\n";
    for (const MaterialResult& r : results)
      for (std::size_t i = 0; i < r.samplers.size(); ++i)
        out << r.name << ',' << r.samplers[i].name << ',' << r.samplers[i].bytes << ',' << fixed(r.samplers[i].error.image, 6) << ','
            << fixed(r.samplers[i].error.seen, 6) << ','
            << (int(i) == r.chosen_sampler) << ',' << r.sampler_within_budget << '\n';
  });
}

tools::GnuplotOutcome drawFitSceneChart(const std::filesystem::path& folder, const std::string& stem,
                                        const std::vector<MaterialResult>& results, double budget) {
  std::ostringstream data, body;
  int block = 0;
  body << "set title " << tools::gnuplotQuote("btf fit-scene: bytes against rendered error per material (relmse 0 drawn at 1e-6)")
       << "\nset logscale xy\nset xlabel 'bytes of the material'\nset ylabel 'rendered relmse against the reference'\n"
       << "set key outside right top\nset grid\nset yrange [5e-7:*]\nset format xy '%.0e'\n";
  std::string plots;
  for (const MaterialResult& r : results) {
    if (r.candidates.empty()) continue;
    data << "$m" << block << " << EOD\n";
    for (std::size_t k = 0; k < r.candidates.size(); ++k)
      if (r.candidates[k].material)
        data << r.candidates[k].bytes << ' ' << std::max(r.relmse[k], 1e-6) << ' ' << tools::gnuplotQuote(shortLabel(r.candidates[k]))
             << '\n';
    data << "EOD\n$c" << block << " << EOD\n";
    if (r.chosen >= 0) data << r.candidates[std::size_t(r.chosen)].bytes << ' ' << std::max(r.relmse[std::size_t(r.chosen)], 1e-6) << '\n';
    data << "EOD\n";
    plots += std::string(plots.empty() ? "" : ", ") + "$m" + std::to_string(block) + " using 1:2 with points pt 7 ps 0.8 lc " +
             std::to_string(block + 1) + " title " + tools::gnuplotQuote(r.name) + ", $m" + std::to_string(block) +
             " using 1:2:3 with labels offset 0.6,0.6 left font ',8' tc lt " + std::to_string(block + 1) + " notitle, $c" + std::to_string(block) +
             " using 1:2 with points pt 6 ps 2.2 lw 2 lc " + std::to_string(block + 1) + " title " +
             tools::gnuplotQuote(r.name + " (chosen)");
    ++block;
  }
  if (block == 0) return {};
  body << "plot " << plots << ", " << budget << " with lines dt 2 lc 'black' title 'budget'\n";
  return tools::drawGnuplotCharts(folder, stem + "-chart.gp", data.str(), {{stem + "-chart", body.str()}});
}


}  // namespace btf::cli
