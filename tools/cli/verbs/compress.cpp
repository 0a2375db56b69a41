// `btf compress IN OUT.btfz`: multi-level VQ of a BTF (an image folder, or a BRDF file as a
// one-texel BTF), then a check of the written file against the input (rel_rmse, psnr_db, ratios).
// `btf compress IN1 IN2 ... OUT.btfz`: a database of materials with shared codebooks.
#include <chrono>
#include <filesystem>

#include <unistd.h>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "btf/compress/compress_form.h"
#include "btf/compress/compressed_btf.h"
#include "btf/compress/factor_btf.h"
#include "btf/compress/vq_btf.h"
#include "btf/io/bonn_btf.h"
#include "btf/compress/vq_database.h"
#include "btf/core/error.h"
#include "btf/io/btf_images.h"
#include "btf/io/btf_quality.h"
#include "material_input.h"
#include "process.h"
#include "commands.h"

namespace btf::cli {
namespace {

struct CompressArgs {
  std::vector<std::string> in;
  std::string out;
  std::string form = "auto";
  std::string color_model = "auto";
  VqOptions vq;
  FactorOptions factor;
  bool allow_larger = false;
  bool verify = true;
  bool json = false;
  bool compare_alone = false;
  float epsilon() const { return vq.epsilon; }
};

// docs/design-notes.md#measures: ratio_u8 counts 3 bytes per RGB entry of the raw data, ratio_f32 12 bytes.
double rawBytes(const BtfSource& s, double bytes_per_entry) { return double(s.entryCount()) * bytes_per_entry; }

// The error of a compressed material against its input, decoded from the file just written so that
// the figures are those of what a reader gets.
void addErrors(const BtfSource& input, const BtfSource& reread, nlohmann::json& report) {
  const BtfQuality q = compareBtfQuality(input, reread);
  report["rel_rmse"] = q.error.rel_rmse;
  report["psnr_db"] = q.error.psnr_db;
  report["rel_rmse_display"] = q.ssim.rel_rmse_display;
  report["mean_ssim"] = q.ssim.mean_ssim;
  report["min_image_ssim"] = q.ssim.min_image_ssim;
  report["ssim_white"] = q.ssim.white;
  report["noise_rel_rmse"] = q.noise.rel_rmse;
  report["rel_rmse_over_noise"] = q.noise.rel_rmse > 0 ? q.error.rel_rmse / q.noise.rel_rmse : 0.0;
}

std::vector<BtfInput> openInputs(const std::vector<std::string>& paths) {
  std::vector<BtfInput> inputs;
  for (const std::string& path : paths) {
    inputs.push_back(openBtfInput(path));
    if (inputs.back().compressed)
      throw FileError(path, "is already compressed (.btfz); decompress it first, compress the original, or join "
                            "compressed files with `btf merge`");
  }
  return inputs;
}

// Bytes of the input as the user has it: a file's size, or the files of a folder.
std::uint64_t inputBytes(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_regular_file(path, ec)) return std::filesystem::file_size(path);
  std::uint64_t bytes = 0;
  if (std::filesystem::is_directory(path, ec))
    for (const auto& entry : std::filesystem::recursive_directory_iterator(path))
      if (entry.is_regular_file()) bytes += entry.file_size();
  return bytes;
}

// The output is written beside its final name and renamed only once it is judged: a Bonn input's
// .btfz must not be larger than the .btf it came from (that file is already a compressed form).
struct PendingOutput {
  std::filesystem::path final_path, path;
  explicit PendingOutput(const std::string& out)
      : final_path(out), path(std::filesystem::path(out).concat(".pending-" + std::to_string(::getpid()) + ".btfz")) {}
  ~PendingOutput() {
    std::error_code ec;
    std::filesystem::remove(path, ec);
  }
  void commit() { std::filesystem::rename(path, final_path); }
};

void runCompress(const CompressArgs& args) {
  const std::vector<BtfInput> inputs = openInputs(args.in);
  const BtfSource& source = *inputs.front().source;
  const bool bonn = isBonnBtfFile(args.in.front());
  const std::uint64_t input_bytes = inputBytes(args.in.front());
  const auto start = std::chrono::steady_clock::now();
  CompressForm form = parseCompressForm(args.form);
  // A Bonn file is a factorisation already, which the codebooks may not beat: auto measures there.
  // Image folders and BRDFs hold every value, and VQ, the toolkit's form, is far below their bytes.
  if (form == CompressForm::Auto && !bonn) form = CompressForm::Vq;
  FactorOptions factor = args.factor;
  nlohmann::json choice_report;
  std::shared_ptr<const FactorBtf> chosen_whole;  // the chosen form, when the choice compressed it whole
  // The candidates: what --form and --color-model leave open.
  std::vector<FormCandidate> candidates;
  if (form != CompressForm::Factor) candidates.push_back({CompressForm::Vq});
  if (form != CompressForm::Vq)
    for (const FactorColorModel model : {FactorColorModel::Linear, FactorColorModel::LogLuminance})
      if (args.color_model == "auto" || args.color_model == factorColorModelName(model))
        candidates.push_back({CompressForm::Factor, model});
  if (candidates.size() == 1) {
    form = candidates.front().form;
    factor.color_model = candidates.front().color_model;
  } else {
    const FormChoice choice = chooseCompressForm(source, args.vq, args.factor, candidates);
    form = choice.chosen.form;
    factor.color_model = choice.chosen.color_model;
    chosen_whole = choice.chosenTrial().compressed;
    choice_report = {{"reason", choice.reason}, {"sample", {choice.sample_width, choice.sample_height}}};
    for (const FormTrial& t : choice.trials) {
      nlohmann::json trial{{"form", formCandidateName(t.candidate)}, {"seconds", t.seconds}, {"whole", t.whole()}};
      if (t.failure.empty())
        trial.update({{"sample_bytes", t.sample_bytes}, {"sample_rel_rmse", t.sample_rel_rmse},
                      {"projected_bytes", t.projected_bytes}});
      else
        trial["failure"] = t.failure;
      choice_report["trials"].push_back(trial);
    }
    if (!args.json) std::printf("form: %s\n", choice.reason.c_str());
  }
  PendingOutput pending(args.out);
  nlohmann::json form_report;
  std::vector<std::size_t> entries;
  if (form == CompressForm::Factor) {
    const FactorBtf compressed = chosen_whole ? *chosen_whole : compressFactor(source, factor);
    compressed.write(pending.path);
    const FactorStats& st = compressed.stats();
    form_report = {{"color_model", factorColorModelName(factor.color_model)},
                   {"components", st.components},
                   {"coefficient_step", st.coefficient_step},
                   {"estimated_rel_rmse", st.estimated_rel_rmse},
                   {"truncation_rel_rmse", st.truncation_rel_rmse},
                   {"from_source_factors", st.from_source_factors},
                   {"max_components", args.factor.max_components},
                   {"max_chroma_components", args.factor.max_chroma_components},
                   {"power_iterations", args.factor.power_iterations}};
    if (st.measured_rel_rmse >= 0)
      form_report.update({{"measured_rel_rmse", st.measured_rel_rmse}, {"step_refinements", st.refinements}});
  } else {
    const VqBtf compressed = compressVq(source, args.vq);
    compressed.write(pending.path);
    entries = compressed.stats().codebook_entries;
    form_report = {{"chroma_epsilon", args.vq.chroma_epsilon},
                   {"energy_floor", args.vq.energy_floor},
                   {"level1_cut", args.vq.level1_cut},
                   {"level3_exceptions", args.vq.level3_exceptions},
                   {"levels", args.vq.levels},
                   {"codebook_entries", entries}};
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::uint64_t bytes = std::filesystem::file_size(pending.path);
  const std::string form_name = form == CompressForm::Factor ? "factor " + factorColorModelName(factor.color_model) : "vq";
  if (bonn && bytes > input_bytes && !args.allow_larger)
    throw FileError(args.out, "not written: the " + form_name + " form at epsilon " +
                                  std::to_string(args.epsilon()) + " takes " + std::to_string(bytes) + " bytes, more than the " +
                                  std::to_string(input_bytes) + " of " + args.in.front() +
                                  " (already a factorised form); raise --epsilon, try --form factor, or pass "
                                  "--allow-larger");
  pending.commit();

  nlohmann::json report{{"input", args.in.front()},
                        {"input_kind", inputs.front().description},
                        {"input_bytes", input_bytes},
                        {"output", args.out},
                        {"form", form_name},
                        {"texels", {source.width(), source.height()}},
                        {"views", source.views().views()},
                        {"epsilon", args.epsilon()},
                        {"bytes", bytes},
                        {"ratio_input", input_bytes > 0 ? double(input_bytes) / double(bytes) : 0.0},
                        {"ratio_u8", rawBytes(source, 3) / double(bytes)},
                        {"ratio_f32", rawBytes(source, 12) / double(bytes)},
                        {"compression_s", seconds},
                        {"peak_memory_bytes", tools::peakMemoryBytes()}};
  report.update(form_report);
  if (!choice_report.is_null()) report["form_choice"] = choice_report;
  if (args.verify) addErrors(source, *readCompressedBtf(args.out), report);
  if (args.json) {
    std::cout << report.dump(2) << '\n';
    return;
  }
  std::printf("%s: %d x %d texels x %s x %s (%s), %llu bytes\n", args.in.front().c_str(), source.width(), source.height(),
              source.views().describe().c_str(), source.directions().describeLights().c_str(),
              inputs.front().description.c_str(), static_cast<unsigned long long>(input_bytes));
  std::printf("wrote %s (%s form): %llu bytes, %.2f x smaller than the input, ratio_u8 %.1f, ratio_f32 %.1f, %.2f s, "
              "peak memory %.0f MiB\n",
              args.out.c_str(), form_name.c_str(), static_cast<unsigned long long>(bytes),
              report["ratio_input"].get<double>(), report["ratio_u8"].get<double>(), report["ratio_f32"].get<double>(),
              seconds, double(report["peak_memory_bytes"].get<std::uint64_t>()) / (1 << 20));
  if (form == CompressForm::Factor) {
    const auto& k = form_report["components"];
    std::printf("components per colour channel: %d %d %d; estimated rel_rmse %.5f (truncation alone %.5f)%s\n",
                k[0].get<int>(), k[1].get<int>(), k[2].get<int>(), form_report["estimated_rel_rmse"].get<double>(),
                form_report["truncation_rel_rmse"].get<double>(),
                form_report.value("from_source_factors", false) ? "; the input's own factors, re-coded" : "");
    if (form_report.contains("measured_rel_rmse"))
      std::printf("step checked on every entry: rel_rmse %.5f after %d refinement(s)\n",
                  form_report["measured_rel_rmse"].get<double>(), form_report["step_refinements"].get<int>());
  } else {
    std::printf("codebook entries per level:");
    for (std::size_t n : entries) std::printf(" %zu", n);
    std::printf("\n");
  }
  if (args.verify) {
    std::printf("rel_rmse %.5f, psnr_db %.2f (decoded from the file against the input)\n",
                report["rel_rmse"].get<double>(), report["psnr_db"].get<double>());
    std::printf("displayed (sRGB, white %g): rel_rmse %.5f, mean SSIM %.4f (worst image %.4f)\n",
                report["ssim_white"].get<double>(), report["rel_rmse_display"].get<double>(),
                report["mean_ssim"].get<double>(), report["min_image_ssim"].get<double>());
    std::printf("the input's noise floor: rel_rmse %.4f (the error is %.2f x it)\n", report["noise_rel_rmse"].get<double>(),
                report["rel_rmse_over_noise"].get<double>());
  }
}

// Several inputs: one database with shared codebooks (compress/vq_database.h). With
// --compare-alone each material is also compressed on its own (same options), and the database is
// set against the sum of those files.
void runCompressDatabase(const CompressArgs& args) {
  const std::vector<BtfInput> inputs = openInputs(args.in);
  std::vector<const BtfSource*> sources;
  std::vector<std::string> names;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    sources.push_back(inputs[i].source.get());
    names.push_back(inputs[i].source->name());
    for (std::size_t j = 0; j < i; ++j)
      if (names[j] == names[i])
        throw Error("inputs " + args.in[j] + " and " + args.in[i] + " are both named '" + names[i] +
                    "': a database needs distinct material names (rename a folder or file; a fit is named NAME-MODEL)");
  }
  VqDatabase database = compressVqDatabase(sources, names, args.vq);
  database.write(args.out);
  const std::uint64_t bytes = std::filesystem::file_size(args.out);
  nlohmann::json report{{"output", args.out},
                        {"epsilon", args.vq.epsilon},
                        {"chroma_epsilon", args.vq.chroma_epsilon},
                        {"energy_floor", args.vq.energy_floor},
                        {"level1_cut", args.vq.level1_cut},
                        {"level3_exceptions", args.vq.level3_exceptions},
                        {"levels", args.vq.levels},
                        {"shared_codebook_entries", database.sharedEntries()},
                        {"bytes", bytes},
                        {"ratio_u8", database.rawBytesU8() / double(bytes)},
                        {"compression_s", database.seconds()}};
  const VqDatabase reread = args.verify ? VqDatabase::read(args.out) : VqDatabase(database.materials());
  std::uint64_t alone_total = 0;
  nlohmann::json list = nlohmann::json::array();
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const VqBtf& m = reread.materials()[i];
    nlohmann::json entry{{"name", names[i]},
                         {"input", args.in[i]},
                         {"input_kind", inputs[i].description},
                         {"texels", {m.width(), m.height()}},
                         {"views", m.views().views()},
                         {"codebook_entries", m.stats().codebook_entries}};
    if (args.verify) addErrors(*sources[i], m, entry);
    if (args.compare_alone) {
      const VqBtf alone = compressVq(*sources[i], args.vq);
      entry["alone_bytes"] = alone.stats().compressed_bytes;
      alone_total += alone.stats().compressed_bytes;
    }
    list.push_back(std::move(entry));
  }
  report["materials"] = std::move(list);
  if (args.compare_alone) {
    report["alone_bytes"] = alone_total;
    report["saving"] = double(alone_total) / double(bytes);
  }
  if (args.json) {
    std::cout << report.dump(2) << '\n';
    return;
  }
  std::printf("wrote %s: a database of %zu materials, %llu bytes, ratio_u8 %.1f, %.2f s\n", args.out.c_str(),
              inputs.size(), static_cast<unsigned long long>(bytes), report["ratio_u8"].get<double>(), database.seconds());
  std::printf("shared codebook entries (level 1, level 2):");
  for (std::size_t n : database.sharedEntries()) std::printf(" %zu", n);
  std::printf("\n%-28s %-12s %10s", "material", "texels", "views");
  if (args.verify) std::printf(" %9s %9s %9s", "rel_rmse", "psnr_db", "SSIM");
  if (args.compare_alone) std::printf(" %12s", "alone bytes");
  std::printf("\n");
  for (const auto& e : report["materials"]) {
    const std::string texels = std::to_string(e["texels"][0].get<int>()) + " x " + std::to_string(e["texels"][1].get<int>());
    std::printf("%-28s %-12s %10zu", e["name"].get<std::string>().c_str(), texels.c_str(), e["views"].size());
    if (args.verify)
      std::printf(" %9.5f %9.2f %9.4f", e["rel_rmse"].get<double>(), e["psnr_db"].get<double>(), e["mean_ssim"].get<double>());
    if (args.compare_alone) std::printf(" %12llu", static_cast<unsigned long long>(e["alone_bytes"].get<std::uint64_t>()));
    std::printf("\n");
  }
  if (args.compare_alone)
    std::printf("each compressed alone: %llu bytes in all; the shared codebooks save a factor %.2f\n",
                static_cast<unsigned long long>(alone_total), report["saving"].get<double>());
}

}  // namespace

void registerCompressCommand(CLI::App& app) {
  auto args = std::make_shared<CompressArgs>();
  auto* cmd = app.add_subcommand(
      "compress",
      "Compress a BTF (image folder, or a BRDF .binary/.bsdf/.exr or merl-fit:MODEL:NAME as a one-texel BTF) by "
      "multi-level vector quantization into a .btfz file, then report the file's errors against the input. Several "
      "inputs make one database whose level-1 and level-2 codebooks the materials share");
  // One positional list, the last of which is the output (CLI11 gives a list positional every
  // argument, so IN... OUT cannot be two options).
  cmd->add_option("IN... OUT", args->in,
                  "Image folders, BRDF files or merl-fit:MODEL:NAME (e.g. merl-fit:sgd:alum-bronze), then the output "
                  ".btfz, written atomically")
      ->required()
      ->expected(2, -1);
  cmd->add_option("--form", args->form,
                  "auto: on a Bonn .btf (already a factorised form), measure both forms on a crop and keep the smaller; on "
                  "any other input, vq. vq: multi-level vector "
                  "quantization; factor: a quantized low-rank factorisation (the form of a Bonn .btf, coded to the error "
                  "asked for)")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "vq", "factor"}));
  cmd->add_option("--epsilon", args->vq.epsilon,
                  "The error asked for: VQ's relative L2 tolerance per level (0: near-lossless); the factor form's "
                  "rel_rmse of the values")
      ->capture_default_str()
      ->check(CLI::Range(0.0f, 1.0f));
  cmd->add_option("--chroma-epsilon", args->vq.chroma_epsilon, "Absolute tolerance of the chromaticity (R/Y, B/Y) per light")
      ->capture_default_str()
      ->check(CLI::Range(kVqMinChromaEpsilon, 1.0f));
  cmd->add_option("--energy-floor", args->vq.energy_floor,
                  "Absolute floor of the tolerance, in RMS norms of a vector's batch: vectors darker than it get "
                  "epsilon times the floor rather than epsilon times their own norm (0: purely relative)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--level1-cut", args->vq.level1_cut,
               "Code level-1 entries in a principal basis of their ring, each cut to the leading coefficients its "
               "tolerance needs: smaller files at equal error on noisy measured data, larger on clean synthetic data");
  cmd->add_flag("!--no-level3-exceptions", args->vq.level3_exceptions,
               "Store every level-3 entry whole: no texel takes a nearly matching entry with its own codes in a few "
               "views (larger files, smaller decoded tables)");
  cmd->add_option("--levels", args->vq.levels, "Quantization levels: 1 (1D functions), 2 (+ light slices), 3 (+ texels)")
      ->capture_default_str()
      ->check(CLI::Range(1, 3));
  cmd->add_option("--color-model", args->color_model,
                  "Factor form: linear (principal colour axes) or log-luminance (Bonn's DFMF model: log Y, U/Y, V/Y; "
                  "for materials whose highlights stand far above their body); auto measures both")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "linear", "log-luminance"}));
  cmd->add_option("--max-components", args->factor.max_components,
                  "Factor form: components sketched for the luminance-like channel, the most it can keep")
      ->capture_default_str()
      ->check(CLI::Range(1, 4096));
  cmd->add_option("--max-chroma-components", args->factor.max_chroma_components,
                  "Factor form: components sketched for each of the two colour channels")
      ->capture_default_str()
      ->check(CLI::Range(1, 4096));
  cmd->add_option("--power-iterations", args->factor.power_iterations,
                  "Factor form: refinements of the sketched basis (each two more passes over the input)")
      ->capture_default_str()
      ->check(CLI::Range(0, 8));
  cmd->add_flag("--allow-larger", args->allow_larger,
                "Write the file even when it is larger than a Bonn .btf input (by default it is refused)");
  cmd->add_option("--threads", args->vq.threads, "Worker threads (0: all cores); the output does not depend on it")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("!--no-verify", args->verify, "Skip decoding the file and comparing it with the input");
  cmd->add_flag("--json", args->json, "Print the report as JSON");
  cmd->add_flag("--compare-alone", args->compare_alone,
                "With several inputs: also compress each alone and report what the shared codebooks save");
  cmd->callback([args] {
    args->out = args->in.back();
    args->in.pop_back();
    if (std::filesystem::path(args->out).extension() != ".btfz")
      throw FileError(args->out, "the output must end in .btfz");
    if (args->in.size() == 1 && args->compare_alone)
      throw Error("--compare-alone needs several inputs (it compares their database with each compressed alone)");
    args->factor.epsilon = args->vq.epsilon;
    args->factor.threads = args->vq.threads;
    if (args->form != "vq" && args->vq.epsilon == 0.0f) {
      if (args->form == "factor") throw Error("--form factor needs --epsilon > 0 (the error it codes to)");
      args->form = "vq";  // near-lossless: the codebooks' form
    }
    if (args->in.size() > 1 && (args->form == "factor" || args->color_model != "auto"))
      throw Error("--form factor and --color-model take one input; several inputs make a VQ database with shared "
                  "codebooks");
    if (args->in.size() == 1) runCompress(*args);
    else runCompressDatabase(*args);
  });
}

}  // namespace btf::cli
