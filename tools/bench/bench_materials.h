// The materials of `btf bench sampling`, by name:
// - a btf-datagen preset (e.g. "chrome"): the preset tabulated into a MERL-layout table and read
//   back as a TabulatedBrdf (interpolated), i.e. what the generator writes, without the file;
// - "<merl-name>:<model>" (model sgd, abc or lafortune; "<merl-name>" alone means sgd): a published
//   MERL fit (loadMerlFits("") finds the tables);
// - an RGL file stem (e.g. "paper_white_rgb"): ../shared/data/real/rgl_bsdf/<stem>.bsdf as an RglBrdf,
//   whose own sampler is the Dupuy-Jakob warp of the file.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "btf/material/material.h"

namespace btf::cli {

struct BenchMaterial {
  std::string name;
  std::shared_ptr<const Material> material;
};

// The default list: every generator preset, two MERL fits, and every RGL file found.
// With `quick`, one preset only.
std::vector<std::string> defaultBenchMaterialNames(bool quick);

// Builds one material by name; throws btf::Error naming what is known for an unknown name.
BenchMaterial loadBenchMaterial(const std::string& name);

}  // namespace btf::cli
