#include "btf/io/merl_exr_stack.h"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "btf/core/error.h"

namespace btf {
namespace {

constexpr const char* kLayoutAttribute = "btf:layout";
constexpr const char* kLayoutDescription =
    "MERL half/diff slice: x = phi_d index (1 deg, [0,180)), y = theta_d index (1 deg, [0,90)), "
    "RGB f in 1/sr, negative = unmeasured";
constexpr const char* kThetaHalfIndexAttribute = "btf:theta_h_index";

std::string partName(int theta_h) {
  char name[32];
  std::snprintf(name, sizeof name, "theta_h_%02d", theta_h);
  return name;
}

}  // namespace

std::vector<StackLayer> merlToExrStack(const MerlTable& table) {
  std::vector<StackLayer> layers;
  for (int th = 0; th < MerlTable::kThetaHalfRes; ++th) {
    StackLayer layer;
    layer.name = partName(th);
    layer.attributes[kLayoutAttribute] = std::string(kLayoutDescription);
    layer.attributes[kThetaHalfIndexAttribute] = th;
    layer.attributes["btf:theta_h_deg"] = float(MerlTable::thetaHalfOf(th) * 180.0 / std::numbers::pi);
    layer.image = Image(MerlTable::kPhiDiffRes, MerlTable::kThetaDiffRes, 3);
    for (int td = 0; td < MerlTable::kThetaDiffRes; ++td)
      for (int pd = 0; pd < MerlTable::kPhiDiffRes; ++pd)
        for (int c = 0; c < 3; ++c)
          layer.image.at(pd, td, c) = float(table.raw(c, MerlTable::index(th, td, pd)) * MerlTable::kChannelScale[c]);
    layers.push_back(std::move(layer));
  }
  return layers;
}

MerlTable exrStackToMerl(const std::filesystem::path& path, const std::vector<StackLayer>& layers) {
  if (layers.size() != std::size_t(MerlTable::kThetaHalfRes))
    throw FileError(path, "has " + std::to_string(layers.size()) + " parts; a btf convert stack has " +
                              std::to_string(MerlTable::kThetaHalfRes) + " (one per theta_h index)");
  MerlTable table;
  for (int th = 0; th < MerlTable::kThetaHalfRes; ++th) {
    const StackLayer& layer = layers[th];
    const auto index = layer.attributes.find(kThetaHalfIndexAttribute);
    if (index == layer.attributes.end() || index->second != ImageAttribute(th))
      throw FileError(path, "part " + std::to_string(th) + " lacks the attribute " + kThetaHalfIndexAttribute + " = " +
                                std::to_string(th) + " (not written by btf convert?)");
    const Image& image = layer.image;
    if (image.width != MerlTable::kPhiDiffRes || image.height != MerlTable::kThetaDiffRes || image.channels != 3)
      throw FileError(path, "part " + layer.name + " is " + std::to_string(image.width) + "x" +
                                std::to_string(image.height) + "x" + std::to_string(image.channels) +
                                ", expected 180x90 RGB (phi_d x theta_d)");
    for (int td = 0; td < MerlTable::kThetaDiffRes; ++td) {
      for (int pd = 0; pd < MerlTable::kPhiDiffRes; ++pd) {
        for (int c = 0; c < 3; ++c) {
          const float f = image.at(pd, td, c);
          if (!std::isfinite(f))
            throw FileError(path, "part " + layer.name + " holds a non-finite value at phi_d " + std::to_string(pd) +
                                      ", theta_d " + std::to_string(td) + " (unmeasured samples must be negative)");
          table.raw(c, MerlTable::index(th, td, pd)) = double(f) / MerlTable::kChannelScale[c];
        }
      }
    }
  }
  return table;
}

}  // namespace btf
