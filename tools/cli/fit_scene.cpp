// `btf fit-scene scene.json --budget 0.01 -o lean.json`: for every measured material of a scene,
// the smallest representation, and then the cheapest sampler, whose rendered error in this scene
// stays within the budget, with the others held at reference.
//
// Representations (fit_scene_candidates.h): analytic fits, octree tables, VQ forms, the full
// material. Each is rendered in place of the material, and its error is the relmse
// (render/image_metrics.h) of that image against the reference, over the whole image (or with
// --measure seen, also over the pixels where the material is seen first; see RenderedError). Both renders use common random
// numbers: every material is sampled by the cosine warp, whose directions do not depend on f,
// and Russian roulette is off, so the same pixel sample follows the same path in both and the
// images differ by f alone, not by the noise of two renders. Comparing two independent noisy renders would
// put their noise into every candidate's error. The candidates are ranked by bytes, and the first
// one within the budget is kept. The full material renders the reference exactly (relmse 0), so
// a material always has a choice; a material that keeps it "could not be reduced".
//
// Samplers: with the chosen representations in place, each reduced material tries cosine, its own
// sample() (an analytic fit's importance sampler), for octree tables the sampler of the tree's
// node bounds, DP-CDF (at epsilon 1e-3: a scene names its sampler, not the sampler's options) and
// the tabulated sampler (BTFs: the first two). The others keep the scene's samplers. The error is now noise:
// the relmse at the scene's spp (another seed) against a render at --reference-spp-factor times
// the spp. Of the samplers within the budget, the one with the fewest bytes is kept, and of equal
// bytes (the warps and a material's own sampler hold none) the least noisy; if none is within the
// budget, the least noisy is kept and the output says so.
//
// Outputs: the lean scene (paths relative to its folder), the chosen material files in
// <stem>-materials/, <stem>.csv (every candidate: bytes, eval/s, samples/s, rendered relmse),
// <stem>-samplers.csv, the chart <stem>-chart.png/.svg (bytes against rendered error per material,
// chosen points marked) and the reference and lean renders (<stem>-reference.exr, <stem>-lean.exr
// with PNG previews, <stem>-error.png).
#include <tbb/global_control.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include "btf/core/error.h"
#include "btf/core/progress.h"
#include "btf/core/rng.h"
#include "btf/io/atomic_file.h"
#include "btf/io/image.h"
#include "btf/render/image_metrics.h"
#include "btf/render/integrator.h"
#include "btf/render/render_output.h"
#include "btf/render/scene_loader.h"
#include "btf/sampling/binned_sampler.h"
#include "btf/sampling/octree_bound_sampler.h"
#include "btf/sampling/sampler_choice.h"
#include "btf/sampling/warp.h"
#include "comma_list.h"
#include "commands.h"
#include "fit_scene_candidates.h"
#include "gnuplot_charts.h"
#include "merl_fit_report.h"

namespace btf::cli {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

struct FitSceneOptions {
  std::string scene, output;
  double budget = 0.01;
  std::optional<int> spp;
  int reference_spp_factor = 8;
  std::uint64_t seed = 1;
  int threads = 0;
  std::string fits = "lafortune,ggx,ggx:linear,lafortune:2";
  std::string tolerances = "0.1,0.03,0.01";
  std::string epsilons = "0.1,0.03";
  bool samplers = true;
  std::string measure = "image";
};

struct Speed {
  double eval_per_s = 0, samples_per_s = 0;
};

// Evaluations and draws of the material's own sampler per second on one thread, over 20,000 fixed
// direction pairs (a report, not a benchmark: btf_bench has those).
Speed measureSpeed(const Material& m) {
  Rng rng(9);
  std::vector<glm::vec3> wi(20000), wo(20000);
  std::vector<glm::vec2> u(20000);
  for (std::size_t k = 0; k < wi.size(); ++k) {
    wi[k] = squareToCosineHemisphere(rng.uniform2D());
    wo[k] = squareToCosineHemisphere(rng.uniform2D());
    u[k] = rng.uniform2D();
  }
  using Clock = std::chrono::steady_clock;
  const glm::vec2 uv(0.5f);
  float sink = 0;
  auto t0 = Clock::now();
  for (std::size_t k = 0; k < wi.size(); ++k) sink += m.eval(wi[k], wo[k], uv).g;
  const double eval_s = std::chrono::duration<double>(Clock::now() - t0).count();
  t0 = Clock::now();
  for (std::size_t k = 0; k < wi.size(); ++k)
    if (const auto s = m.sample(wo[k], uv, u[k])) sink += s->pdf;
  const double sample_s = std::chrono::duration<double>(Clock::now() - t0).count();
  volatile float keep = sink;
  (void)keep;
  return {eval_s > 0 ? double(wi.size()) / eval_s : 0.0, sample_s > 0 ? double(wi.size()) / sample_s : 0.0};
}

struct Renderer {
  render::RenderSettings settings;
  std::unique_ptr<render::Integrator> integrator = render::makePathTracer();
  Image operator()(render::SceneDescription d, int spp, std::uint64_t seed) const {
    render::RenderSettings s = settings;
    s.spp = spp;
    s.seed = seed;
    const render::Scene scene(std::move(d));
    return integrator->render(scene, s).color;
  }
};

// Every material sampled by the cosine warp (common random numbers, see the top of the file).
render::SceneDescription withCosineSampling(render::SceneDescription d) {
  for (render::SceneMaterial& m : d.materials) {
    m.sampled = withSampler(SamplerChoice::Cosine, m.material, SamplerOptions{});
    m.sampler = "cosine";
  }
  return d;
}

// The material each pixel's centre sees first (-1: nothing, or a shape without a material).
std::vector<int> firstHitMaterials(const render::SceneDescription& d) {
  const render::Scene scene(d);
  const int w = d.camera.width, h = d.camera.height;
  std::vector<int> out(std::size_t(w) * std::size_t(h), -1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      render::SurfaceHit hit;
      if (scene.intersect(scene.camera().generateRay({float(x) + 0.5f, float(y) + 0.5f}), hit))
        out[std::size_t(y) * std::size_t(w) + std::size_t(x)] = d.shapes[hit.shape].material;
    }
  return out;
}

// A render's error against the reference: relmse over the whole image, and over the pixels where
// the material is seen first (the whole image's when it is seen nowhere). The budget applies to
// the first by default: a material seen small contributes little to the image, which is what lets
// it be modelled more cheaply. --measure seen applies it to the larger of the two, for a user who
// wants every object right on its own pixels (a material filling a tenth of the frame can lose its
// texture within an image-wide budget).
struct RenderedError {
  double image = 0, seen = 0;
  double judged(bool seen_too) const { return seen_too ? std::max(image, seen) : image; }
};

RenderedError renderedError(const Image& test, const Image& reference, const std::vector<int>& first_hit, int material) {
  RenderedError e;
  e.image = render::compareImages(test, reference).relmse;
  std::size_t n = 0;
  for (const int m : first_hit) n += m == material;
  if (n == 0) {
    e.seen = e.image;
    return e;
  }
  // The material's pixels as two one-row images, measured by the same comparison.
  Image a(int(n), 1, test.channels), b(int(n), 1, reference.channels);
  std::size_t k = 0;
  for (std::size_t p = 0; p < first_hit.size(); ++p) {
    if (first_hit[p] != material) continue;
    for (int c = 0; c < test.channels; ++c) {
      a.pixels[k * std::size_t(test.channels) + std::size_t(c)] = test.pixels[p * std::size_t(test.channels) + std::size_t(c)];
      b.pixels[k * std::size_t(reference.channels) + std::size_t(c)] = reference.pixels[p * std::size_t(reference.channels) + std::size_t(c)];
    }
    ++k;
  }
  e.seen = render::compareImages(a, b).relmse;
  return e;
}

struct MaterialResult {
  std::string name, type;
  std::vector<MaterialCandidate> candidates;
  std::vector<double> relmse;  // per candidate: the error judged (NaN: not built)
  std::vector<RenderedError> errors;
  std::vector<Speed> speed;
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

std::string resolveFrom(const fs::path& folder, const std::string& file) {
  const fs::path p(file);
  return (p.is_absolute() ? p : folder / p).lexically_normal().string();
}

// A path of the original scene rewritten for the lean scene's folder: absolute paths stay, relative
// ones are made relative to the new folder.
void rebase(json& node, const char* key, const fs::path& from, const fs::path& to) {
  if (!node.is_object() || !node.contains(key) || !node[key].is_string()) return;
  const fs::path p(node[key].get<std::string>());
  if (p.is_absolute()) return;
  node[key] = fs::absolute(from / p).lexically_normal().lexically_relative(fs::absolute(to).lexically_normal()).string();
}

std::string fixed(double v, int digits) {
  char text[48];
  std::snprintf(text, sizeof text, "%.*g", digits, v);
  return text;
}

// A candidate's name on the chart: "ggx", "lafortune 2 lobes", "octree 0.03", "vq 0.1", "full".
std::string shortLabel(const MaterialCandidate& c) {
  std::string label = c.label;
  for (const char* cut : {"fit ", " of the mean texel", " (81 x 81 directions)", "t=", "eps="}) {
    const std::size_t at = label.find(cut);
    if (at != std::string::npos) label.erase(at, std::string(cut).size());
  }
  return c.kind == "full" ? "full" : label;
}

tools::GnuplotOutcome drawChart(const fs::path& folder, const std::string& stem, const std::vector<MaterialResult>& results,
                                double budget) {
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

void runFitScene(const FitSceneOptions& o) {
  const fs::path scene_file(o.scene), output(o.output);
  if (output.extension() != ".json") throw FileError(output, "the lean scene is a scene file: the name must end in .json");
  const fs::path out_dir = output.parent_path().empty() ? fs::path(".") : output.parent_path();
  std::error_code ec;
  if (!fs::is_directory(out_dir, ec)) throw FileError(output, "the output folder does not exist");
  if (!(o.budget > 0) || !std::isfinite(o.budget)) throw Error("--budget must be a positive relmse");
  FitSceneSettings settings;
  settings.fits = splitCommaList(o.fits);
  for (const std::string& spec : settings.fits) (void)parseFitSpec(spec);  // refuse a bad one before any work
  settings.octree_tolerances.clear();
  for (const std::string& t : splitCommaList(o.tolerances)) settings.octree_tolerances.push_back(std::stod(t));
  settings.vq_epsilons.clear();
  for (const std::string& e : splitCommaList(o.epsilons)) settings.vq_epsilons.push_back(std::stod(e));

  std::optional<tbb::global_control> limit;
  if (o.threads > 0) limit.emplace(tbb::global_control::max_allowed_parallelism, std::size_t(o.threads));

  render::SceneLoadOptions load;
  load.fits_folders = tools::defaultFitsFolders();
  const render::SceneDescription description = render::loadSceneDescription(scene_file, load);
  json raw;
  {
    std::ifstream in(scene_file);
    raw = json::parse(in);  // the loader has read it already
  }
  const fs::path scene_dir = scene_file.parent_path().empty() ? fs::path(".") : scene_file.parent_path();

  Renderer render;
  render.settings.max_depth = description.render.max_depth;
  render.settings.rr_min_depth = description.render.max_depth;  // no roulette: see the top of the file
  const int spp = o.spp.value_or(description.render.spp);
  const auto& cam = description.camera;
  std::printf("%s: %d x %d, %d spp, budget relmse %g (%s)\n", o.scene.c_str(), cam.width, cam.height, spp, o.budget,
              o.measure == "seen" ? "of the image and of each material's own pixels" : "of the image");

  const render::SceneDescription cosine = withCosineSampling(description);
  const Image reference = render(cosine, spp, o.seed);
  const std::vector<int> first_hit = firstHitMaterials(description);

  const std::string stem = output.stem().string();
  const fs::path materials_dir = out_dir / (stem + "-materials");
  const fs::path work = out_dir / (stem + "-materials.work");
  fs::remove_all(work, ec);
  fs::create_directories(work);
  // The candidates' files live in `work` until the end; it goes whether the command ends well or not.
  struct RemoveOnExit {
    fs::path path;
    ~RemoveOnExit() {
      std::error_code e;
      fs::remove_all(path, e);
    }
  } remove_work{work};

  std::vector<MaterialResult> results;
  for (std::size_t k = 0; k < description.materials.size(); ++k) {
    MaterialResult r;
    r.name = description.materials[k].name;
    const json& materials = raw["materials"];
    if (!materials.is_object() || !materials.contains(r.name)) {
      r.skipped = "a Lambert from a mesh's material library";
      results.push_back(std::move(r));
      continue;
    }
    const json& entry = materials[r.name];
    r.type = entry.value("type", "");
    if (!reducible(r.type)) {
      r.skipped = r.type + ": an analytic model already";
      results.push_back(std::move(r));
      continue;
    }
    std::printf("\n%s (%s):\n", r.name.c_str(), r.type.c_str());
    std::fflush(stdout);
    const fs::path file = resolveFrom(scene_dir, entry["file"].get<std::string>());
    try {
      r.candidates = makeCandidates(r.name, entry, file, description.materials[k].material, work, settings);
    } catch (const Error& e) {
      // E.g. one material of a .btfz database, which the candidates do not read yet: kept as it is.
      r.skipped = std::string("no smaller forms could be made: ") + e.what();
      std::printf("  %s\n", r.skipped.c_str());
      results.push_back(std::move(r));
      continue;
    }
    const std::uint64_t full_bytes = r.candidates.back().bytes;
    Progress progress("rendering " + r.name, r.candidates.size());
    for (const MaterialCandidate& c : r.candidates) {
      RenderedError e{std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
      Speed speed;
      if (c.material) {
        speed = measureSpeed(*c.material);
        if (c.kind == "full") {
          e = {0, 0};  // the reference itself, sample for sample
        } else {
          render::SceneDescription d = cosine;
          d.materials[k].material = c.material;
          d.materials[k].sampled = withSampler(SamplerChoice::Cosine, c.material, SamplerOptions{});
          e = renderedError(render(std::move(d), spp, o.seed), reference, first_hit, int(k));
        }
      }
      r.errors.push_back(e);
      r.relmse.push_back(e.judged(o.measure == "seen"));
      r.speed.push_back(speed);
      progress.advance();
    }
    // The smallest within the budget (and smaller than the full material).
    std::vector<std::size_t> order(r.candidates.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return r.candidates[a].bytes < r.candidates[b].bytes; });
    for (const std::size_t i : order) {
      const MaterialCandidate& c = r.candidates[i];
      if (!c.material || !(r.relmse[i] <= o.budget)) continue;
      if (c.kind != "full" && c.bytes >= full_bytes) continue;
      r.chosen = int(i);
      break;
    }
    for (std::size_t i = 0; i < r.candidates.size(); ++i) {
      const MaterialCandidate& c = r.candidates[i];
      std::printf("  %-46s %12llu B  %9s eval/s  %9s samples/s  relmse %-9s (seen %-9s) %s%s\n", c.label.c_str(),
                  static_cast<unsigned long long>(c.bytes), fixed(r.speed[i].eval_per_s, 3).c_str(),
                  fixed(r.speed[i].samples_per_s, 3).c_str(), c.material ? fixed(r.errors[i].image, 3).c_str() : "-",
                  c.material ? fixed(r.errors[i].seen, 3).c_str() : "-",
                  int(i) == r.chosen ? "<- chosen " : "", c.note.c_str());
    }
    results.push_back(std::move(r));
  }

  // The lean scene: chosen representations, the scene's samplers.
  render::SceneDescription lean = description;
  for (std::size_t k = 0; k < results.size(); ++k) {
    const MaterialResult& r = results[k];
    if (r.chosen < 0) continue;
    const MaterialCandidate& c = r.candidates[std::size_t(r.chosen)];
    if (c.kind == "full") continue;
    render::SceneMaterial& m = lean.materials[k];
    m.material = c.material;
    // The scene's sampler where it applies to the new form (a tabulated sampler does to any BRDF);
    // a VQ form is a BTF, which takes only its own sampler and the warps.
    const auto choice = parseSamplerChoice(m.sampler);
    const bool tabulating = choice && (*choice == SamplerChoice::Tabulated || *choice == SamplerChoice::DpCdf ||
                                       *choice == SamplerChoice::Quadtree || *choice == SamplerChoice::OctreeBound);
    const bool keep = choice && !(c.kind == "vq" && tabulating) && !(*choice == SamplerChoice::OctreeBound && c.kind != "octree");
    if (!keep) m.sampler = "material";
    m.sampled = withSampler(*parseSamplerChoice(m.sampler), m.material, SamplerOptions{});
  }

  if (o.samplers) {
    std::printf("\nsamplers: noise at %d spp against %d spp\n", spp, spp * o.reference_spp_factor);
    const Image converged = render(lean, spp * o.reference_spp_factor, o.seed + 1);
    for (std::size_t k = 0; k < results.size(); ++k) {
      MaterialResult& r = results[k];
      if (r.chosen < 0) continue;
      const MaterialCandidate& c = r.candidates[std::size_t(r.chosen)];
      // A BTF (kept, or VQ-compressed) takes only its own sampler and the warps; a fit of it is a BRDF.
      const bool btf_like = c.kind == "vq" || (c.kind == "full" && r.type == "btf");
      // DP-CDF at the scene format's tolerance (SamplerOptions' default): scenes name a sampler, not
      // its options.
      std::vector<std::string> tries = {"cosine", "material"};
      if (!btf_like) tries.insert(tries.end(), {"dp-cdf", "tabulated"});
      if (c.kind == "octree" || (c.kind == "full" && r.type == "octree")) tries.insert(tries.begin() + 2, "octree-bound");
      Progress progress("samplers of " + r.name, tries.size());
      for (const std::string& name : tries) {
        MaterialResult::SamplerTry t;
        t.name = name;
        render::SceneDescription d = lean;
        d.materials[k].sampled = withSampler(*parseSamplerChoice(name), d.materials[k].material, SamplerOptions{});
        if (const auto* binned = dynamic_cast<const BinnedSampler*>(d.materials[k].sampled.get())) t.bytes = binned->stats().bytes;
        if (const auto* bound = dynamic_cast<const OctreeBoundSampler*>(d.materials[k].sampled.get())) t.bytes = bound->bytes();
        d.materials[k].sampler = name;
        t.error = renderedError(render(std::move(d), spp, o.seed + 2), converged, first_hit, int(k));
        t.relmse = t.error.judged(o.measure == "seen");
        r.samplers.push_back(t);
        progress.advance();
      }
      // Within the budget: the fewest bytes, and of equal bytes (the warps and the material's own
      // sampler hold none) the least noise. None within: the least noise.
      int best = 0;
      for (int i = 0; i < int(r.samplers.size()); ++i) {
        const MaterialResult::SamplerTry& t = r.samplers[std::size_t(i)];
        if (t.relmse < r.samplers[std::size_t(best)].relmse) best = i;
        if (!(t.relmse <= o.budget)) continue;
        if (r.chosen_sampler >= 0) {
          const MaterialResult::SamplerTry& c = r.samplers[std::size_t(r.chosen_sampler)];
          if (t.bytes > c.bytes || (t.bytes == c.bytes && t.relmse >= c.relmse)) continue;
        }
        r.chosen_sampler = i;
        r.sampler_within_budget = true;
      }
      if (r.chosen_sampler < 0) r.chosen_sampler = best;
      const std::string& chosen = r.samplers[std::size_t(r.chosen_sampler)].name;
      lean.materials[k].sampler = chosen;
      lean.materials[k].sampled = withSampler(*parseSamplerChoice(chosen), lean.materials[k].material, SamplerOptions{});
      std::printf("  %s:", r.name.c_str());
      for (std::size_t i = 0; i < r.samplers.size(); ++i)
        std::printf(" %s %s%s;", r.samplers[i].name.c_str(), fixed(r.samplers[i].relmse, 3).c_str(),
                    int(i) == r.chosen_sampler ? " (chosen)" : "");
      std::printf("%s\n", r.sampler_within_budget ? "" : " none within the budget: kept the least noisy");
    }
  }

  // The lean scene file and its materials, staged in `work` and moved into place together.
  const fs::path staged = work / "chosen";
  fs::create_directories(staged);
  json lean_json = raw;
  for (auto& [name, m] : lean_json["materials"].items()) {
    rebase(m, "file", scene_dir, out_dir);
    rebase(m, "fits_dir", scene_dir, out_dir);
  }
  if (lean_json.contains("shapes"))
    for (json& s : lean_json["shapes"]) rebase(s, "file", scene_dir, out_dir);
  if (lean_json.contains("lights"))
    for (json& l : lean_json["lights"]) rebase(l, "file", scene_dir, out_dir);
  std::uint64_t full_total = 0, lean_total = 0;
  for (std::size_t k = 0; k < results.size(); ++k) {
    const MaterialResult& r = results[k];
    if (r.chosen < 0) continue;
    const MaterialCandidate& c = r.candidates[std::size_t(r.chosen)];
    full_total += r.candidates.back().bytes;
    lean_total += c.bytes;
    json entry = lean_json["materials"][r.name];
    if (c.kind != "full") {
      fs::copy_file(c.file, staged / c.file.filename(), fs::copy_options::overwrite_existing);
      entry = c.entry;
      entry["file"] = (fs::path(stem + "-materials") / c.file.filename()).string();
    }
    entry["sampler"] = lean.materials[k].sampler;
    lean_json["materials"][r.name] = entry;
  }
  lean_json["comment"] = "btf fit-scene " + o.scene + " --budget " + fixed(o.budget, 6) + ": each measured material replaced by the "
                         "smallest representation whose rendered relmse in this scene is within the budget";
  fs::remove_all(materials_dir, ec);
  fs::rename(staged, materials_dir);
  writeFileAtomically(output, [&](std::ofstream& out) { out << lean_json.dump(2) << "\n"; });

  // The lean scene as a whole, against the reference (common random numbers again).
  const render::SceneDescription lean_cosine = withCosineSampling(lean);
  render::RenderResult lean_render;
  {
    render::RenderSettings s = render.settings;
    s.spp = spp;
    s.seed = o.seed;
    const render::Scene scene(lean_cosine);
    lean_render = render.integrator->render(scene, s);
  }
  const render::ImageComparison whole = render::compareImages(lean_render.color, reference);
  render::RenderResult reference_result;
  reference_result.color = reference;
  render::writeRenderOutputs(reference_result, out_dir / (stem + "-reference.exr"), 0.0f);
  render::writeRenderOutputs(lean_render, out_dir / (stem + "-lean.exr"), 0.0f);
  writeImage(out_dir / (stem + "-error.png"), render::errorHeatMap(lean_render.color, reference, 0.2));

  // Tables and the chart.
  writeFileAtomically(out_dir / (stem + ".csv"), [&](std::ofstream& out) {
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
  writeFileAtomically(out_dir / (stem + "-samplers.csv"), [&](std::ofstream& out) {
    out << "material,sampler,bytes,relmse_noise_image,relmse_noise_seen,chosen,within_budget\n";
    for (const MaterialResult& r : results)
      for (std::size_t i = 0; i < r.samplers.size(); ++i)
        out << r.name << ',' << r.samplers[i].name << ',' << r.samplers[i].bytes << ',' << fixed(r.samplers[i].error.image, 6) << ','
            << fixed(r.samplers[i].error.seen, 6) << ','
            << (int(i) == r.chosen_sampler) << ',' << r.sampler_within_budget << '\n';
  });
  const tools::GnuplotOutcome chart = drawChart(out_dir, stem, results, o.budget);

  std::printf("\n");
  std::vector<std::string> kept_full;
  for (const MaterialResult& r : results) {
    if (!r.skipped.empty()) continue;
    const MaterialCandidate& c = r.candidates[std::size_t(r.chosen)];
    std::printf("  %-12s %s, %llu B (of %llu), relmse %s; sampler %s\n", r.name.c_str(), c.label.c_str(),
                static_cast<unsigned long long>(c.bytes), static_cast<unsigned long long>(r.candidates.back().bytes),
                fixed(r.relmse[std::size_t(r.chosen)], 3).c_str(),
                r.chosen_sampler >= 0 ? r.samplers[std::size_t(r.chosen_sampler)].name.c_str() : "as in the scene");
    if (c.kind == "full") kept_full.push_back(r.name);
  }
  // Materials left as they are, one line per reason (a mesh's library names its parts
  // "file:name": the name is enough here).
  std::map<std::string, std::string> kept;
  for (const MaterialResult& r : results)
    if (!r.skipped.empty()) {
      const std::size_t colon = r.name.rfind(':');
      std::string& names = kept[r.skipped];
      names += (names.empty() ? "" : ", ") + (colon == std::string::npos ? r.name : r.name.substr(colon + 1));
    }
  for (const auto& [why, names] : kept) std::printf("  kept as they are (%s): %s\n", why.c_str(), names.c_str());
  std::printf("measured materials: %llu B lean against %llu B full (1/%.1f); the lean scene renders at relmse %s of the reference\n",
              static_cast<unsigned long long>(lean_total), static_cast<unsigned long long>(full_total),
              lean_total > 0 ? double(full_total) / double(lean_total) : 0.0, fixed(whole.relmse, 3).c_str());
  if (!kept_full.empty()) {
    std::printf("could not be reduced within the budget (kept the full material):");
    for (const std::string& n : kept_full) std::printf(" %s", n.c_str());
    std::printf("\n");
  }
  if (whole.relmse > o.budget)
    std::printf("note: each material is within the budget alone; together their errors add up to more than it\n");
  std::printf("wrote %s, %s/, %s.csv, %s-samplers.csv, %s-reference.exr, %s-lean.exr, %s-error.png", output.string().c_str(),
              materials_dir.string().c_str(), stem.c_str(), stem.c_str(), stem.c_str(), stem.c_str(), stem.c_str());
  for (const auto& f : chart.files) std::printf(", %s", f.filename().c_str());
  std::printf("\n");
  if (!chart.message.empty()) std::printf("%s\n", chart.message.c_str());
}

}  // namespace

void registerFitSceneCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("fit-scene",
                                 "For each measured material of a scene, the smallest representation and the cheapest sampler "
                                 "whose rendered error stays within a budget; writes the lean scene, tables and a chart");
  auto o = std::make_shared<FitSceneOptions>();
  cmd->add_option("SCENE", o->scene, "Scene file (.json)")->required();
  cmd->add_option("-o,--output", o->output, "The lean scene (.json); tables, chart and renders go beside it")->required();
  cmd->add_option("--budget", o->budget, "Largest rendered relmse against the reference, per material")->capture_default_str();
  cmd->add_option("--spp", o->spp, "Samples per pixel of every render (default: the scene's)")->check(CLI::Range(1, 1 << 20));
  cmd->add_option("--reference-spp-factor", o->reference_spp_factor, "The sampler pass's reference has this many times the spp")
      ->check(CLI::Range(2, 1024))
      ->capture_default_str();
  cmd->add_option("--fits", o->fits, "Analytic fits to try: family[:lobes][:linear|log], comma-separated")->capture_default_str();
  cmd->add_option("--tolerances", o->tolerances, "Octree tolerances to try (BRDFs)")->capture_default_str();
  cmd->add_option("--epsilons", o->epsilons, "VQ tolerances to try")->capture_default_str();
  cmd->add_flag("!--no-samplers", o->samplers, "Skip the sampler pass (keep the scene's samplers)");
  cmd->add_option("--measure", o->measure,
                  "What the budget bounds: the relmse of the image, or also (seen) the relmse over the pixels where the "
                  "material is seen first")
      ->check(CLI::IsMember({"image", "seen"}))
      ->capture_default_str();
  cmd->add_option("--seed", o->seed, "Seed of the renders")->capture_default_str();
  cmd->add_option("--threads", o->threads, "Worker threads (0: all cores); the results do not depend on it")->check(CLI::Range(0, 1024));
  cmd->callback([o] { runFitScene(*o); });
}

}  // namespace btf::cli
