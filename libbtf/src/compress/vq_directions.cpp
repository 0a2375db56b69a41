// The direction set and ring layout of a VQ-compressed BTF in its .btfz header (vq_sections.h).
//
// Files on the 81-direction UBO2003 set (every file written before other sets were read) carry
// neither: their set and rings are implied. Any other set is stored whole, as angles in degrees
// (a float printed as the double it is reads back bit for bit), with the layout the codebooks
// were built on, so that a later change to how layouts are derived cannot misread an older file.
#include <nlohmann/json.hpp>

#include "btf/core/error.h"
#include "vq_sections.h"

namespace btf {
namespace {

nlohmann::json anglesJson(std::span<const BtfAngles> list) {
  nlohmann::json out = nlohmann::json::array();
  for (const BtfAngles& a : list) out.push_back({a.theta_deg, a.phi_deg});
  return out;
}

std::vector<BtfAngles> anglesOf(const nlohmann::json& list, const std::filesystem::path& path, const char* what) {
  if (!list.is_array()) throw FileError(path, std::string("VQ header's ") + what + " are not a list of angles");
  std::vector<BtfAngles> out;
  for (const auto& pair : list) {
    if (!pair.is_array() || pair.size() != 2 || !pair[0].is_number() || !pair[1].is_number())
      throw FileError(path, std::string("VQ header's ") + what + " hold " + pair.dump() + ", not a (theta, phi) pair");
    out.push_back({pair[0].get<float>(), pair[1].get<float>()});
  }
  return out;
}

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
  const BtfDirectionSet& set = m.views.directions();
  if (vqHasOwnDirections(m)) {
    nlohmann::json lights = nlohmann::json::array();
    for (int v = 0; v < (set.sharedLights() ? 1 : set.viewCount()); ++v) lights.push_back(anglesJson(set.lights(v)));
    std::vector<BtfAngles> views;
    for (int v = 0; v < set.viewCount(); ++v) views.push_back(set.viewAngles(v));
    nlohmann::json directions{{"name", set.name()}, {"views", anglesJson(views)}, {"lights", std::move(lights)}};
    if (set.nominal() && set.nominal()->isUbo2003()) directions["nominal"] = "ubo2003";
    header["directions"] = std::move(directions);
    header["rings"] = {{"sizes", m.layout.sizes()}, {"order", m.layout.order()}};
  }
  // The views held, only when some are missing (absent: all of them).
  if (!m.views.complete()) header["views"] = m.views.views();
}

void readVqDirectionsHeader(const nlohmann::json& header, const std::filesystem::path& path, VqBtf::Impl& m) {
  BtfDirectionSetPtr set = BtfDirectionSet::ubo2003();
  BtfRingLayout layout = BtfRingLayout::ubo2003();
  if (const auto it = header.find("directions"); it != header.end()) {
    const nlohmann::json& d = *it;
    if (!d.is_object() || !d.contains("name") || !d.at("name").is_string() || !d.contains("views") || !d.contains("lights") ||
        !d.at("lights").is_array())
      throw FileError(path, "VQ header's directions are not a name, views and light lists");
    std::vector<std::vector<BtfAngles>> lights;
    for (const auto& list : d.at("lights")) lights.push_back(anglesOf(list, path, "lights"));
    std::vector<BtfAngles> views = anglesOf(d.at("views"), path, "views");
    if (lights.size() == 1) lights.resize(views.size(), lights.front());
    BtfDirectionSetPtr nominal;
    if (d.contains("nominal")) {
      if (d.at("nominal") != "ubo2003") throw FileError(path, "VQ header's nominal set " + d.at("nominal").dump() + " is unknown");
      nominal = BtfDirectionSet::ubo2003();
    }
    set = BtfDirectionSet::known(std::make_shared<const BtfDirectionSet>(d.at("name").get<std::string>(), std::move(views),
                                                                         std::move(lights), std::move(nominal)));
    const auto rings = header.find("rings");
    if (rings == header.end() || !rings->is_object()) throw FileError(path, "VQ header has directions but no rings");
    layout = BtfRingLayout(intsOf(*rings, "sizes", path), intsOf(*rings, "order", path));
    for (int v = 0; v < set->viewCount(); ++v)
      if (set->lightCount(v) != layout.lightCount())
        throw FileError(path, "VQ header's rings hold " + std::to_string(layout.lightCount()) + " lights, its view " +
                                  std::to_string(v) + " has " + std::to_string(set->lightCount(v)));
  } else if (header.contains("rings")) {
    throw FileError(path, "VQ header has rings but no directions");
  }
  m.views = header.contains("views") ? BtfViewSet(header.at("views").get<std::vector<int>>(), set) : BtfViewSet::all(set);
  m.setLayout(std::move(layout));
}

}  // namespace btf
