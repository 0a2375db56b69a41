// `btf-datagen btf`: a synthetic BTF (btf_patterns.h) measured by the virtual gonioreflectometer on
// a direction set (the 81 UBO2003 directions, the 151 of the Bonn dome, or a scattered one) and
// written as an image folder (UBO2003 or UTIA layout, btf/io/btf_images.h) or a Bonn .btf file
// (btf/io/bonn_btf.h).
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>

namespace btf::datagen {

struct BtfCommandOptions {
  std::string pattern = "fabric";
  int size = 64;
  std::uint64_t seed = 1;
  std::string format = "png";
  std::string output;
  float value_scale = 0;  // PNG: value of the largest code; 0 = the BTF's largest value (lossless range)
  bool json = false;
  bool camera = false;  // through synthetic::measuredCameraOptions: jitter, noise, 8-bit sRGB PNG
  std::string directions = "ubo2003";  // "ubo2003", "dome", "scattered"
  std::string layout = "ubo2003";      // "ubo2003", "utia" (folders); "dfmf", "fmf", "pvf" (.btf files)
  int components = 32;                 // of a .btf file's factorisation
};

// Adds the subcommand to `app`; its options land in `options`.
CLI::App* addBtfCommand(CLI::App& app, BtfCommandOptions& options);
void runBtfCommand(const BtfCommandOptions& options);

}  // namespace btf::datagen
