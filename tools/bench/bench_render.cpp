// `btf bench render -o DIR`: what the renderer costs and how well each sampler spends it.
//  1. rays/s of the path tracer (one thread) against a bare loop of Embree queries (rtcIntersect1
//     and rtcOccluded1 through EmbreeScene) over exactly the rays of that render;
//  2. 1 -> 2 thread scaling of rendering and of photon tracing;
//  3. photons/s, and kNN queries/s of the photon map's kd-B-tree against nanoflann and FLANN on the
//     same photons and queries;
//  4. equal time and equal quality of the samplers: relmse against a high-spp reference as spp
//     grows, with the seconds each took (CSV, and a gnuplot chart of relmse against seconds).
#include "bench_render.h"

#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <thread>

#include "bench_photon_search.h"
#include "btf/core/error.h"
#include "btf/io/atomic_file.h"
#include "btf/render/embree_scene.h"
#include "btf/render/image_metrics.h"
#include "btf/render/photon_map.h"
#include "btf/render/render_output.h"
#include "btf/render/scene_loader.h"
#include "comma_list.h"
#include "gnuplot_charts.h"

namespace btf::cli {
namespace fs = std::filesystem;
// Named after the file: the unity build compiles the commands together, and their helpers share
// names (Args, Row).
namespace bench_render {
namespace {

struct Args {
  std::string output = "bench-render";
  std::string scene = std::string(BTF_SCENES_DIR) + "/cornell-glossy.json";
  int resolution = 128;
  std::string samplers = "material,cosine,tabulated,dp-cdf,quadtree";
  std::string spps = "1,2,4,8,16,32";
  int reference_spp = 512;
  std::size_t photons = 1'000'000;
  std::size_t queries = 200'000;
  bool quick = false;
};

double seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

render::SceneDescription loadScene(const Args& a, const std::string& sampler) {
  render::SceneLoadOptions load;
  load.sampler_override = sampler;
  render::SceneDescription d = render::loadSceneDescription(a.scene, load);
  d.camera.width = d.camera.height = a.resolution;
  return d;
}

render::RenderResult renderWith(const render::Scene& scene, int spp, int threads, std::uint64_t seed = 1) {
  std::optional<tbb::global_control> limit;
  if (threads > 0) limit.emplace(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
  render::RenderSettings settings;
  settings.spp = spp;
  settings.seed = seed;
  return render::makePathTracer()->render(scene, settings);
}


void runBenchRender(const Args& a) {
  const fs::path out(a.output);
  std::error_code ec;
  fs::create_directories(out, ec);
  if (!fs::is_directory(out)) throw FileError(out, "cannot create the output folder");
  std::ostringstream report;  // the same figures as printed, kept as summary.txt
  auto say = [&](const char* format, auto... values) {
    char line[512];
    std::snprintf(line, sizeof(line), format, values...);
    std::fputs(line, stdout);
    report << line;
  };

  // 1. The render loop against bare BVH queries over the same rays, one thread each.
  const render::Scene scene(loadScene(a, "material"));
  say("scene %s at %d x %d\n", a.scene.c_str(), a.resolution, a.resolution);
  std::vector<render::TracedRay> rays;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    render::RenderSettings settings;
    settings.spp = a.quick ? 1 : 4;
    render::renderPathTracedRecording(scene, settings, rays);
  }
  const int spp_rays = a.quick ? 1 : 4;
  const render::RenderResult single = renderWith(scene, spp_rays, 1);
  const double render_rate = double(single.stats.rays()) / single.stats.seconds;
  const auto bare_start = std::chrono::steady_clock::now();
  std::size_t hits = 0;
  render::RayHit hit;
  for (const render::TracedRay& r : rays) hits += r.shadow ? scene.embree().occluded(r.ray) : scene.embree().intersect(r.ray, hit);
  const double bare_rate = double(rays.size()) / seconds(bare_start);
  say("\n1. Rays per second, one thread, %zu rays of a %d-spp render (%zu hit or occluded)\n", rays.size(), spp_rays, hits);
  say("   path tracer            %8.3f M rays/s (shading, sampling, NEE and MIS included)\n", render_rate * 1e-6);
  say("   bare Embree loop       %8.3f M rays/s (rtcIntersect1 / rtcOccluded1 on the same rays)\n", bare_rate * 1e-6);
  say("   ratio                  %8.3f\n", render_rate / bare_rate);

  // 2. Thread scaling of rendering and photon tracing.
  // Runs of a fraction of a second scale poorly for reasons that are not the renderer's (the
  // worker thread's start, the last tiles' imbalance): enough samples for about a second on one
  // thread, and the fastest of three runs at each thread count (other tenants of a virtual
  // machine steal time from one run or another).
  int scaling_spp = a.quick ? 2 : 8;
  if (!a.quick) {
    const double probe = renderWith(scene, scaling_spp, 1).stats.seconds;
    scaling_spp = std::clamp(int(std::ceil(scaling_spp * 1.0 / std::max(probe, 1e-3))), scaling_spp, 1024);
  }
  auto fastestRender = [&](int threads) {
    double best = renderWith(scene, scaling_spp, threads).stats.seconds;
    for (int run = 1; run < (a.quick ? 1 : 3); ++run) best = std::min(best, renderWith(scene, scaling_spp, threads).stats.seconds);
    return best;
  };
  const double render_1 = fastestRender(1), render_2 = fastestRender(2);
  const std::uint64_t photon_count = a.quick ? 50'000 : 400'000;
  struct PhotonTimes {
    double trace, build;
    std::size_t stored;
  };
  auto photonSeconds = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    const render::PhotonMap map(scene, photon_count, render::RenderSettings{});
    return PhotonTimes{map.traceSeconds(), map.buildSeconds(), map.size()};
  };
  auto fastestPhotons = [&](int threads) {
    PhotonTimes best = photonSeconds(threads);
    for (int run = 1; run < (a.quick ? 1 : 3); ++run) {
      const PhotonTimes again = photonSeconds(threads);
      if (again.trace + again.build < best.trace + best.build) best = again;
    }
    return best;
  };
  const PhotonTimes p1 = fastestPhotons(1), p2 = fastestPhotons(2);
  say("\n2. Scaling from 1 to 2 threads (this machine: %u hardware threads)\n", std::thread::hardware_concurrency());
  say("   render, %d spp          %6.2f s -> %6.2f s: %.2fx\n", scaling_spp, render_1, render_2, render_1 / render_2);
  say("   photon tracing, %llu    %6.2f s -> %6.2f s: %.2fx (%.3f M photons/s emitted on 2 threads, %zu stored)\n",
      static_cast<unsigned long long>(photon_count), p1.trace, p2.trace, p1.trace / p2.trace,
      double(photon_count) / p2.trace * 1e-6, p1.stored);
  say("   photon map, traced + built %6.2f s -> %6.2f s: %.2fx (collecting and the kd-tree: %.2f s -> %.2f s)\n",
      p1.trace + p1.build, p2.trace + p2.build, (p1.trace + p1.build) / (p2.trace + p2.build), p1.build, p2.build);

  // 3. Photon search structures on identical photons and queries.
  const std::size_t n = a.quick ? 100'000 : a.photons, q = a.quick ? 20'000 : a.queries;
  const auto figures = measurePhotonSearch(n, q, 50, 1);
  say("\n3. Photon search, %zu photons, %zu queries, k = 50 and a fixed radius holding ~50 (one thread)\n", n, q);
  say("   %-10s %10s %14s %16s %12s\n", "structure", "build s", "kNN queries/s", "radius queries/s", "index MB");
  double best_peer = 0, ours = 0;
  for (const PhotonSearchFigures& f : figures) {
    say("   %-10s %10.3f %14.0f %16.0f %12.2f\n", f.structure.c_str(), f.build_seconds, f.knn_queries_per_s,
        f.radius_queries_per_s, double(f.bytes) / 1e6);
    if (f.structure == "kd-b-tree") ours = f.knn_queries_per_s;
    else best_peer = std::max(best_peer, f.knn_queries_per_s);
  }
  say("   kd-b-tree kNN / best peer: %.2fx\n", ours / best_peer);

  // 4. Samplers at equal time: relmse against a high-spp reference with the material's own sampler.
  const int reference_spp = a.quick ? 16 : a.reference_spp;
  say("\n4. Samplers: relmse against a %d-spp reference (material sampler, seed 1000), all threads\n", reference_spp);
  const render::RenderResult reference = renderWith(scene, reference_spp, 0, 1000);
  render::writeRenderOutputs(reference, out / "reference.exr");
  std::vector<int> spps;
  for (const std::string& s : splitCommaList(a.spps)) spps.push_back(std::stoi(s));
  if (a.quick) spps = {1, 2};
  std::ostringstream csv, data;
  csv << "sampler,spp,seconds,relmse,rel_rmse,efficiency\n";
  say("   %-10s %5s %9s %10s %10s %12s\n", "sampler", "spp", "seconds", "relmse", "rel_rmse", "1/(relmse s)");
  std::map<std::string, double> efficiency_at_max;
  const std::vector<std::string> samplers = splitCommaList(a.samplers);
  for (const std::string& sampler : samplers) {
    const auto t_build = std::chrono::steady_clock::now();
    const render::Scene sampled(loadScene(a, sampler));
    const double build = seconds(t_build);
    data << "$" << (sampler == "dp-cdf" ? std::string("dpcdf") : sampler) << " << EOD\n";
    for (const int spp : spps) {
      const render::RenderResult r = renderWith(sampled, spp, 0);
      const render::ImageComparison c = render::compareImages(r.color, reference.color);
      const double eff = 1.0 / (c.relmse * r.stats.seconds);
      say("   %-10s %5d %9.3f %10.5f %10.5f %12.1f\n", sampler.c_str(), spp, r.stats.seconds, c.relmse, c.rel_rmse, eff);
      csv << sampler << "," << spp << "," << r.stats.seconds << "," << c.relmse << "," << c.rel_rmse << "," << eff << "\n";
      data << r.stats.seconds << " " << c.relmse << "\n";
      efficiency_at_max[sampler] = eff;
      if (spp == spps.back()) render::writeRenderOutputs(r, out / (sampler + ".exr"));
    }
    data << "EOD\n";
    say("   %-10s tables built in %.2f s (scene load included)\n", sampler.c_str(), build);
  }
  if (efficiency_at_max.count("material")) {
    say("   efficiency at %d spp relative to the material's own sampler:", spps.back());
    for (const auto& [s, e] : efficiency_at_max) say(" %s %.2f", s.c_str(), e / efficiency_at_max["material"]);
    say("\n");
  }
  writeFileAtomically(out / "samplers.csv", [&](std::ofstream& f) { f << csv.str(); });
  writeFileAtomically(out / "summary.txt", [&](std::ofstream& f) { f << report.str(); });

  std::string plot = "set title " + tools::gnuplotQuote("Equal time: relmse against render time (" + fs::path(a.scene).stem().string() + ")") +
                     "\nset xlabel 'seconds'\nset ylabel 'relmse'\nset logscale xy\nset grid\nset key top right\nplot ";
  for (std::size_t i = 0; i < samplers.size(); ++i)
    plot += std::string(i ? ", " : "") + "$" + (samplers[i] == "dp-cdf" ? std::string("dpcdf") : samplers[i]) +
            " using 1:2 with linespoints lw 2 title " + tools::gnuplotQuote(samplers[i]);
  const tools::GnuplotOutcome charts = tools::drawGnuplotCharts(out, "samplers.gnuplot", data.str(), {{"samplers", plot + "\n"}});
  if (!charts.message.empty()) say("   (%s)\n", charts.message.c_str());
  say("\nwrote %s (samplers.csv, summary.txt, reference.exr, one render per sampler%s)\n", out.string().c_str(),
      charts.files.empty() ? "" : ", samplers.png/.svg");
}

}  // namespace
}  // namespace bench_render

void addBenchRenderCommand(CLI::App& bench) {
  auto a = std::make_shared<bench_render::Args>();
  auto* cmd = bench.add_subcommand("render",
                                   "Renderer: rays/s against a bare Embree loop, 1 -> 2 thread scaling, photons/s, kNN of the "
                                   "photon kd-B-tree against nanoflann and FLANN, and the samplers at equal time (CSV, chart)");
  cmd->add_option("-o,--output", a->output, "Output folder")->capture_default_str();
  cmd->add_option("--scene", a->scene, "Scene file")->capture_default_str();
  cmd->add_option("--resolution", a->resolution, "Image width and height")->check(CLI::Range(8, 4096))->capture_default_str();
  cmd->add_option("--samplers", a->samplers, "Samplers compared (comma-separated)")->capture_default_str();
  cmd->add_option("--spp", a->spps, "Samples per pixel of the sampler comparison (comma-separated)")->capture_default_str();
  cmd->add_option("--reference-spp", a->reference_spp, "Samples per pixel of the reference")->check(CLI::Range(1, 1 << 20))->capture_default_str();
  cmd->add_option("--photons", a->photons, "Photons of the search comparison")->capture_default_str();
  cmd->add_option("--queries", a->queries, "Queries of the search comparison")->capture_default_str();
  cmd->add_flag("--quick", a->quick, "Tiny sizes: checks that everything runs, measures nothing");
  cmd->callback([a] { bench_render::runBenchRender(*a); });
}

}  // namespace btf::cli
