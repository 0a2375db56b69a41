// `btf compress IN OUT.btfz`: multi-level VQ of a BTF (an image folder, or a BRDF file as a
// one-texel BTF), then a check of the written file against the input (rel_rmse, psnr_db, ratios).
// `btf decompress IN.btfz OUT_DIR`: the image folder of a .btfz (EXR or PNG).
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "btf/compress/vq_btf.h"
#include "btf/core/error.h"
#include "btf/io/btf_images.h"
#include "btf/io/btf_quality.h"
#include "btf_input.h"
#include "commands.h"

namespace btf::cli {
namespace {

struct CompressArgs {
  std::string in, out;
  VqOptions vq;
  bool verify = true;
  bool json = false;
};

// ARCHITECTURE.md: ratio_u8 counts 3 bytes per RGB entry of the raw data, ratio_f32 12 bytes.
double rawBytes(const BtfSource& s, double bytes_per_entry) { return double(s.entryCount()) * bytes_per_entry; }

void runCompress(const CompressArgs& args) {
  const BtfInput input = openBtfInput(args.in);
  if (input.kind == BtfInputKind::Compressed)
    throw FileError(args.in, "is already compressed (.btfz); decompress it first or compress the original");
  const auto start = std::chrono::steady_clock::now();
  const VqBtf compressed = compressVq(*input.source, args.vq);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  compressed.write(args.out);
  const std::uint64_t bytes = std::filesystem::file_size(args.out);

  nlohmann::json report{{"input", args.in},
                        {"input_kind", input.description},
                        {"output", args.out},
                        {"texels", {input.source->width(), input.source->height()}},
                        {"views", input.source->views().views()},
                        {"epsilon", args.vq.epsilon},
                        {"chroma_epsilon", args.vq.chroma_epsilon},
                        {"levels", args.vq.levels},
                        {"codebook_entries", compressed.stats().codebook_entries},
                        {"bytes", bytes},
                        {"ratio_u8", rawBytes(*input.source, 3) / double(bytes)},
                        {"ratio_f32", rawBytes(*input.source, 12) / double(bytes)},
                        {"compression_s", seconds}};
  if (args.verify) {
    // Decode from the file just written, so the figures are those of what a reader gets.
    const VqBtf reread = VqBtf::read(args.out);
    const BtfErrorStats e = compareBtf(*input.source, reread);
    report["rel_rmse"] = e.rel_rmse;
    report["psnr_db"] = e.psnr_db;
    const BtfSsimStats ssim = compareBtfSsim(*input.source, reread);
    report["rel_rmse_display"] = ssim.rel_rmse_display;
    report["mean_ssim"] = ssim.mean_ssim;
    report["min_image_ssim"] = ssim.min_image_ssim;
    report["ssim_white"] = ssim.white;
    const BtfNoiseFloor noise = estimateBtfNoiseFloor(*input.source);
    report["noise_rel_rmse"] = noise.rel_rmse;
    report["rel_rmse_over_noise"] = noise.rel_rmse > 0 ? e.rel_rmse / noise.rel_rmse : 0.0;
  }
  if (args.json) {
    std::cout << report.dump(2) << '\n';
    return;
  }
  std::printf("%s: %d x %d texels x %s x 81 lights (%s)\n", args.in.c_str(), input.source->width(),
              input.source->height(), input.source->views().describe().c_str(), input.description.c_str());
  std::printf("wrote %s: %llu bytes, ratio_u8 %.1f, ratio_f32 %.1f, %.2f s\n", args.out.c_str(),
              static_cast<unsigned long long>(bytes), report["ratio_u8"].get<double>(), report["ratio_f32"].get<double>(),
              seconds);
  std::printf("codebook entries per level:");
  for (std::size_t n : compressed.stats().codebook_entries) std::printf(" %zu", n);
  std::printf("\n");
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

void runDecompress(const std::string& in, const std::string& out, const std::string& format_name) {
  BtfImageWriteOptions options;
  if (format_name == "exr") options.format = BtfImageFormat::Exr;
  else if (format_name == "png8" || format_name == "png") options.format = BtfImageFormat::Png8;
  else if (format_name == "png16") options.format = BtfImageFormat::Png16;
  else throw Error("unknown --format '" + format_name + "' (expected exr, png8 or png16)");
  if (std::filesystem::path(in).extension() != ".btfz") throw FileError(in, "is not a .btfz file");
  const VqBtf compressed = VqBtf::read(in);
  writeBtfImageFolder(compressed, out, options);
  std::printf("wrote %s: %d x %d texels, %s, %d %s images\n", out.c_str(), compressed.width(), compressed.height(),
              compressed.views().describe().c_str(), compressed.views().count() * kBtfDirectionCount,
              btfImageFormatName(options.format).c_str());
}

}  // namespace

void registerCompressCommands(CLI::App& app) {
  auto args = std::make_shared<CompressArgs>();
  auto* cmd = app.add_subcommand(
      "compress",
      "Compress a BTF (image folder, or a BRDF .binary/.bsdf/.exr as a one-texel BTF) by multi-level vector "
      "quantization into a .btfz file, then report rel_rmse and psnr_db of the file against the input");
  cmd->add_option("IN", args->in, "Image folder, or a BRDF file")->required();
  cmd->add_option("OUT", args->out, "Output .btfz, written atomically")->required();
  cmd->add_option("--epsilon", args->vq.epsilon, "Relative L2 tolerance per level (0: near-lossless)")
      ->capture_default_str()
      ->check(CLI::Range(0.0f, 1.0f));
  cmd->add_option("--chroma-epsilon", args->vq.chroma_epsilon, "Absolute tolerance of the chromaticity (R/Y, B/Y) per light")
      ->capture_default_str()
      ->check(CLI::Range(kVqMinChromaEpsilon, 1.0f));
  cmd->add_option("--levels", args->vq.levels, "Quantization levels: 1 (1D functions), 2 (+ light slices), 3 (+ texels)")
      ->capture_default_str()
      ->check(CLI::Range(1, 3));
  cmd->add_option("--threads", args->vq.threads, "Worker threads (0: all cores); the output does not depend on it")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("!--no-verify", args->verify, "Skip decoding the file and comparing it with the input");
  cmd->add_flag("--json", args->json, "Print the report as JSON");
  cmd->callback([args] {
    if (std::filesystem::path(args->out).extension() != ".btfz")
      throw FileError(args->out, "the output must end in .btfz");
    runCompress(*args);
  });

  auto in = std::make_shared<std::string>(), out = std::make_shared<std::string>();
  auto format = std::make_shared<std::string>("exr");
  auto* dec = app.add_subcommand("decompress", "Write the image folder (one image per view and light) of a .btfz file");
  dec->add_option("IN", *in, "Input .btfz")->required();
  dec->add_option("OUT", *out, "Output folder, written atomically (a temporary folder renamed at the end)")->required();
  dec->add_option("--format", *format, "exr (float), png8 or png16 (scaled; btf.json holds the scale)")->capture_default_str();
  dec->callback([in, out, format] { runDecompress(*in, *out, *format); });
}

}  // namespace btf::cli
