#include "btf_command.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "btf/core/error.h"
#include "btf/io/bonn_btf.h"
#include "btf/io/btf_images.h"
#include "synthetic_btf.h"
#include "btf_patterns.h"
#include "camera_btf.h"

namespace btf::datagen {
namespace fs = std::filesystem;
namespace {

BtfImageFormat parseFormat(const std::string& name) {
  if (name == "png") return BtfImageFormat::Png8;
  if (name == "png16") return BtfImageFormat::Png16;
  if (name == "exr") return BtfImageFormat::Exr;
  throw Error("unknown image format '" + name + "' (choose png, png16 or exr)");
}

std::uintmax_t folderBytes(const fs::path& folder) {
  std::uintmax_t bytes = 0;
  for (const fs::directory_entry& entry : fs::recursive_directory_iterator(folder))
    if (entry.is_regular_file()) bytes += entry.file_size();
  return bytes;
}

}  // namespace

CLI::App* addBtfCommand(CLI::App& app, BtfCommandOptions& o) {
  CLI::App* cmd = app.add_subcommand(
      "btf",
      "Synthetic BTF: a procedural microgeometry observed from the directions of an image-based BTF\n"
      "measurement (parallax, masking, self-shadowing): the 81 x 81 of UBO2003 and UTIA, the 151 x 151 of the\n"
      "Bonn dome, or a scattered set; written as an image folder (UBO2003 or UTIA layout) or a Bonn .btf file");
  cmd->add_option("--pattern", o.pattern, "Sample: fabric, stones, paint, leather or print (a printed paper, low-rank like measured prints)")
      ->check(CLI::IsMember(synthetic::btfPatternNames()))
      ->capture_default_str();
  cmd->add_option("--size", o.size, "Texels along each side (16 for tests, 256 for benchmarks)")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  cmd->add_option("--seed", o.seed, "Seed of the pattern")->capture_default_str();
  cmd->add_option("--format", o.format,
                  "Image format: png (8-bit), png16 or exr (float, exact); PNG values are scaled by btf.json's value_scale.\n"
                  "Glossy samples peak far above their body (paint's flakes ~180, stones ~25 vs ~0.1-1): prefer\n"
                  "png16 or exr for them, or clip the peaks with --value-scale")
      ->check(CLI::IsMember({"png", "png16", "exr"}))
      ->capture_default_str();
  cmd->add_option("--value-scale", o.value_scale,
                  "PNG only: the value of the largest code; larger values saturate as in an 8-bit camera\n"
                  "(default: the BTF's largest value, found by a first pass over the data)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--directions", o.directions,
                  "Direction set: ubo2003 (81 x 81 on rings of 15 degrees), dome (151 x 151, the Bonn dome of UBO2014)\n"
                  "or scattered (40 views x 60 lights on spirals, each view its own lights)")
      ->check(CLI::IsMember({"ubo2003", "dome", "scattered"}))
      ->capture_default_str();
  cmd->add_option("--layout", o.layout,
                  "ubo2003 or utia: an image folder (81 directions only); dfmf, fmf or pvf: a Bonn .btf file\n"
                  "(any set; factorised by a truncated SVD at --components)")
      ->check(CLI::IsMember({"ubo2003", "utia", "dfmf", "fmf", "pvf"}))
      ->capture_default_str();
  cmd->add_option("--components", o.components, "A .btf file's components per factorisation")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  cmd->add_option("-o,--output", o.output,
                  "Output folder (created; replaces an older BTF folder), or .btf file for --layout dfmf/fmf/pvf")
      ->required();
  cmd->add_flag("--camera", o.camera,
                "Record it as a measurement's camera does: registration error, sensor noise, 8-bit sRGB PNG clipped at\n"
                "an auto-exposed white (the camera the print pattern is calibrated with; docs/design-notes.md); with\n"
                "--layout dfmf, fmf or pvf the .btf file factorises what the camera recorded");
  cmd->add_flag("--json", o.json, "Machine-readable summary");
  return cmd;
}

void runBtfCommand(const BtfCommandOptions& o) {
  const synthetic::BtfPattern pattern = synthetic::parseBtfPattern(o.pattern);
  const BtfImageFormat format = parseFormat(o.format);
  const fs::path output = o.output;
  const bool bonn_layout = o.layout == "dfmf" || o.layout == "fmf" || o.layout == "pvf";
  const fs::path parent = output.has_filename() ? output.parent_path() : output.parent_path().parent_path();
  // Fail before the work, not after it.
  if (o.value_scale > 0 && format == BtfImageFormat::Exr)
    throw Error("--value-scale applies to PNG only (EXR stores the values themselves)");
  if (o.camera && !bonn_layout && (format != BtfImageFormat::Png8 || o.value_scale > 0))
    throw Error("--camera writes 8-bit sRGB PNGs at its own exposure: it takes neither --format png16/exr nor --value-scale");
  if (!parent.empty() && !fs::is_directory(parent)) throw FileError(output, "folder " + parent.string() + " does not exist");

  const bool bonn = bonn_layout;
  if (bonn && output.extension() != ".btf")
    throw FileError(output, "--layout " + o.layout + " writes a Bonn .btf file: name it so (e.g. " +
                                output.stem().string() + ".btf)");
  if (!bonn && o.directions != "ubo2003")
    throw Error("the " + o.layout + " image-folder layout holds the 81 UBO2003 directions; write the " + o.directions +
                " set as a Bonn .btf file (--layout dfmf, fmf or pvf)");

  const auto start = std::chrono::steady_clock::now();
  synthetic::SyntheticBtfOptions synthetic_options;
  synthetic_options.directions = o.directions == "dome"        ? BtfDirectionSet::uboDome1()
                                 : o.directions == "scattered" ? synthetic::scatteredDirectionSet(40, 60)
                                                               : BtfDirectionSet::ubo2003();
  const std::unique_ptr<synthetic::SyntheticBtf> btf =
      synthetic::makeSyntheticBtf(pattern, o.size, o.size, o.seed, synthetic_options);
  if (bonn) {
    // With --camera the file factorises what the measured camera recorded (its noise, registration
    // error and 8-bit codes), as a measurement's .btf file factorises its images.
    std::unique_ptr<synthetic::CameraBtf> camera;
    if (o.camera) camera = std::make_unique<synthetic::CameraBtf>(*btf, synthetic::measuredCameraOptions(*btf, o.seed));
    const BtfSource& recorded = camera ? static_cast<const BtfSource&>(*camera) : *btf;
    std::uint64_t file_bytes = 0;
    if (o.layout == "pvf") {
      writeBonnBtfPvf(recorded, output, o.components, 2);
      file_bytes = fs::file_size(output);
    } else {
      BonnBtfWriteOptions bonn_options;
      bonn_options.layout = o.layout == "fmf" ? BonnBtfLayout::Fmf : BonnBtfLayout::Dfmf;
      bonn_options.max_components = o.components;
      file_bytes = writeBonnBtf(recorded, output, bonn_options).bytes;
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (o.json) {
      std::cout << nlohmann::json{{"output", o.output}, {"pattern", o.pattern},       {"size", o.size},
                                  {"seed", o.seed},     {"layout", o.layout},         {"directions", btf->directions().describe()},
                                  {"bytes", file_bytes}, {"components", o.components}, {"seconds", seconds},
                                  {"camera", o.camera}}
                       .dump(2)
                << "\n";
      return;
    }
    std::printf("wrote %s: %s, %d x %d texels, %s, Bonn %s at %d components, %.1f MiB, %.1f s\n", o.output.c_str(),
                recorded.name().c_str(), o.size, o.size, btf->directions().describe().c_str(), o.layout.c_str(), o.components,
                double(file_bytes) / (1024.0 * 1024.0), seconds);
    return;
  }
  BtfImageWriteOptions options;
  options.format = format;
  options.layout = o.layout == "utia" ? BtfImageLayout::Utia : BtfImageLayout::Ubo2003;
  if (o.value_scale > 0) options.value_scale = o.value_scale;
  if (o.camera) {
    // The camera's values are decoded 8-bit sRGB codes of its white: written with that white as the
    // PNGs' value_scale, the files hold exactly the camera's codes.
    const synthetic::CameraOptions camera_options = synthetic::measuredCameraOptions(*btf, o.seed);
    const synthetic::CameraBtf camera(*btf, camera_options);
    options.value_scale = camera_options.white;
    writeBtfImageFolder(camera, output, options);
  } else {
    writeBtfImageFolder(*btf, output, options);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const BtfImageFolder written = BtfImageFolder::open(output);
  const std::uintmax_t bytes = folderBytes(output);

  if (o.json) {
    const nlohmann::json out{{"output", o.output},       {"pattern", o.pattern},    {"size", o.size},
                             {"seed", o.seed},           {"format", o.format},      {"name", btf->name()},
                             {"images", kBtfDirectionCount * kBtfDirectionCount},   {"bytes", bytes},
                             {"value_scale", written.valueScale()},                 {"seconds", seconds},
                             {"camera", o.camera}};
    std::cout << out.dump(2) << "\n";
    return;
  }
  std::printf("wrote %s: %s, %d x %d texels, 81 x 81 images (%s), %.1f MiB, value_scale %g, %.1f s\n", o.output.c_str(),
              btf->name().c_str(), o.size, o.size, o.format.c_str(), double(bytes) / (1024.0 * 1024.0),
              double(written.valueScale()), seconds);
}

}  // namespace btf::datagen
