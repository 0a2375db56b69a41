// The direction set and ring layout of a VQ-compressed BTF in its .btfz header (vq_sections.h).
//
// Files on the 81-direction UBO2003 set (every file written before other sets were read) carry
// neither: their set and rings are implied. Any other set is stored whole, as angles in degrees
// (a float printed as the double it is reads back bit for bit), with the layout the codebooks
// were built on, so that a later change to how layouts are derived cannot misread an older file.
#include <nlohmann/json.hpp>

#include "btf/core/error.h"
#include "btfz_directions.h"
#include "vq_sections.h"

namespace btf {
namespace {

std::vector<int> intsOf(const nlohmann::json& object, const char* key, const std::filesystem::path& path) {
  const auto it = object.find(key);
  if (it == object.end() || !it->is_array()) throw FileError(path, std::string("VQ header's rings have no \"") + key + "\" list");
  std::vector<int> out;
  for (const auto& v : *it) {
    if (!v.is_number_integer() || v < 0 || v > BtfDirectionSet::kMaxDirections)
      throw FileError(path, std::string("VQ header's rings' \"") + key + "\" hold " + v.dump());
    out.push_back(v.get<int>());
  }
  return out;
}

}  // namespace

bool vqHasOwnDirections(const VqBtf::Impl& m) { return !m.views.directions().isUbo2003(); }

double vqRawValues(const VqBtf::Impl& m) {
  double pairs = 0;
  for (const int v : m.views.views()) pairs += double(m.views.directions().lightCount(v));
  return double(m.width) * double(m.height) * pairs * 3.0;
}

void addVqDirectionsHeader(const VqBtf::Impl& m, nlohmann::json& header) {
  addDirectionSetHeader(m.views, header);
  if (vqHasOwnDirections(m)) header["rings"] = {{"sizes", m.layout.sizes()}, {"order", m.layout.order()}};
}

void readVqDirectionsHeader(const nlohmann::json& header, const std::filesystem::path& path, VqBtf::Impl& m) {
  m.views = readDirectionSetHeader(header, path, "VQ header");
  const BtfDirectionSet& set = m.views.directions();
  BtfRingLayout layout = BtfRingLayout::ubo2003();
  if (header.contains("directions")) {
    const auto rings = header.find("rings");
    if (rings == header.end() || !rings->is_object()) throw FileError(path, "VQ header has directions but no rings");
    layout = BtfRingLayout(intsOf(*rings, "sizes", path), intsOf(*rings, "order", path));
    for (int v = 0; v < set.viewCount(); ++v)
      if (set.lightCount(v) != layout.lightCount())
        throw FileError(path, "VQ header's rings hold " + std::to_string(layout.lightCount()) + " lights, its view " +
                                  std::to_string(v) + " has " + std::to_string(set.lightCount(v)));
  } else if (header.contains("rings")) {
    throw FileError(path, "VQ header has rings but no directions");
  }
  m.setLayout(std::move(layout));
}

}  // namespace btf
