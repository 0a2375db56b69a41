// `btf-datagen btf`: a synthetic BTF (btf_patterns.h) measured by the virtual gonioreflectometer and
// written as an image folder (btf/io/btf_images.h).
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
};

// Adds the subcommand to `app`; its options land in `options`.
CLI::App* addBtfCommand(CLI::App& app, BtfCommandOptions& options);
void runBtfCommand(const BtfCommandOptions& options);

}  // namespace btf::datagen
