// `btf fit-scene scene.json --budget 0.01 -o lean.json`: for every measured material of a scene,
// the smallest representation, and then the cheapest sampler, whose rendered error in this scene
// stays within the budget, with the others held at reference.
//
// Representations (fit_scene_candidates.h): analytic fits, octree tables, VQ forms, the full
// material. Each is rendered in place of the material, and its error is the relmse
// (render/image_metrics.h) of that image against the reference, over the whole image (or with
// --measure seen, also over the pixels where the material is seen first; see RenderedError).
// Both renders use common random numbers: every material is sampled by the cosine warp, whose
// directions do not depend on f, and Russian roulette is off, so the same pixel sample follows the
// same path in both and the images differ by f alone. Comparing two independent noisy renders
// would put their noise into every candidate's error. The candidates are ranked by bytes, and the
// first one within the budget is kept. The full material renders the reference exactly (relmse
// 0), so a material always has a choice; a material that keeps it "could not be reduced".
//
// Samplers: with the chosen representations in place, each reduced material tries cosine, its own
// sample() (an analytic fit's importance sampler), for octree tables the sampler of the tree's
// node bounds, DP-CDF (at epsilon 1e-3: a scene names its sampler, not the sampler's options) and
// the tabulated sampler (BTFs: the first two). The others keep the scene's samplers. The error is
// now noise: the relmse at the scene's spp (another seed) against a render at
// --reference-spp-factor times the spp. Of the samplers within the budget, the one with the fewest
// bytes is kept, and of equal bytes (the warps and a material's own sampler hold none) the least
// noisy; if none is within the budget, the least noisy is kept and the output says so.
//
// Outputs: the lean scene (paths relative to its folder), the chosen material files in
// <stem>-materials/, <stem>.csv (every candidate: bytes, eval/s, samples/s, rendered relmse),
// <stem>-samplers.csv, the chart <stem>-chart.png/.svg (bytes against rendered error per material,
// chosen points marked) and the reference and lean renders (<stem>-reference.exr, <stem>-lean.exr
// with PNG previews, <stem>-error.png).
#include <tbb/global_control.h>


#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <optional>

#include "btf/core/error.h"
#include "btf/core/progress.h"
#include "btf/io/atomic_file.h"
#include "btf/io/image.h"
#include "btf/render/image_metrics.h"
#include "btf/render/integrator.h"
#include "btf/render/render_output.h"
#include "btf/render/scene_loader.h"
#include "btf/sampling/sampler_choice.h"
#include "comma_list.h"
#include "commands.h"
#include "fit_scene_candidates.h"
#include "fit_scene_measure.h"
#include "fit_scene_report.h"
#include "gnuplot_charts.h"

namespace btf::cli {
namespace {
namespace fs = std::filesystem;

struct FitSceneOptions {
  std::string scene, output;
  double budget = 0.01;
  std::optional<int> spp;
  int reference_spp_factor = 8;
  std::uint64_t seed = 1;
  int threads = 0;
  std::string fits = "lafortune:log,ggx:log,ggx:linear,abc,ggx2,lafortune:2:log";
  std::string tolerances = "0.1,0.03,0.01";
  std::string epsilons = "0.1,0.03";
  bool samplers = true;
  std::string measure = "image";
};


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

  render::SceneDocument document = render::SceneDocument::read(scene_file);
  const render::SceneDescription description = render::loadSceneDescription(document);

  SceneRenderer render;
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
    if (!document.hasMaterial(r.name)) {
      r.skipped = "a Lambert from a mesh's material library";
      results.push_back(std::move(r));
      continue;
    }
    const MaterialParams entry = document.material(r.name);
    r.type = entry.type();
    if (!reducible(r.type)) {
      r.skipped = r.type + ": an analytic model already";
      results.push_back(std::move(r));
      continue;
    }
    std::printf("\n%s (%s):\n", r.name.c_str(), r.type.c_str());
    std::fflush(stdout);
    const fs::path file = entry.path("file").lexically_normal();
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
      FitSpeed speed;
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
    const bool keep = choice && !(c.kind == "vq" && tabulatesOneBrdf(*choice)) &&
                      !(*choice == SamplerChoice::OctreeBound && c.kind != "octree");
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
        t.bytes = samplerTableBytes(*d.materials[k].sampled);
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
  std::uint64_t full_total = 0, lean_total = 0;
  for (std::size_t k = 0; k < results.size(); ++k) {
    const MaterialResult& r = results[k];
    if (r.chosen < 0) continue;
    const MaterialCandidate& c = r.candidates[std::size_t(r.chosen)];
    full_total += r.candidates.back().bytes;
    lean_total += c.bytes;
    MaterialParams entry = document.material(r.name);
    if (c.kind != "full") {
      fs::copy_file(c.file, staged / c.file.filename(), fs::copy_options::overwrite_existing);
      entry = c.entry;
      entry.setOrigin({}, {});  // named from the current directory: where the file will be
      entry.set("file", (materials_dir / c.file.filename()).string());
    }
    entry.set("sampler", lean.materials[k].sampler);
    document.setMaterial(r.name, entry);
  }
  document.setComment("btf fit-scene " + o.scene + " --budget " + fixed(o.budget, 6) + ": each measured material replaced by "
                      "the smallest representation whose rendered relmse in this scene is within the budget");
  fs::remove_all(materials_dir, ec);
  fs::rename(staged, materials_dir);
  document.write(output);

  // The lean scene as a whole, against the reference (common random numbers again).
  const render::RenderResult lean_render = render.result(withCosineSampling(lean), spp, o.seed);
  const render::ImageComparison whole = render::compareImages(lean_render.color, reference);
  render::RenderResult reference_result;
  reference_result.color = reference;
  render::writeRenderOutputs(reference_result, out_dir / (stem + "-reference.exr"), 0.0f);
  render::writeRenderOutputs(lean_render, out_dir / (stem + "-lean.exr"), 0.0f);
  writeImage(out_dir / (stem + "-error.png"), render::errorHeatMap(lean_render.color, reference, 0.2));

  // Tables and the chart.
  writeFitSceneTables(out_dir, stem, results);
  const tools::GnuplotOutcome chart = drawFitSceneChart(out_dir, stem, results, o.budget);

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
