#include "btfz_directions.h"

#include <string>
#include <vector>

#include "btf/core/error.h"

namespace btf {
namespace {

nlohmann::json anglesJson(std::span<const BtfAngles> list) {
  nlohmann::json out = nlohmann::json::array();
  for (const BtfAngles& a : list) out.push_back({a.theta_deg, a.phi_deg});
  return out;
}

std::vector<BtfAngles> anglesOf(const nlohmann::json& list, const std::filesystem::path& path, const std::string& what,
                                const char* which) {
  if (!list.is_array()) throw FileError(path, what + "'s " + which + " are not a list of angles");
  std::vector<BtfAngles> out;
  for (const auto& pair : list) {
    if (!pair.is_array() || pair.size() != 2 || !pair[0].is_number() || !pair[1].is_number())
      throw FileError(path, what + "'s " + which + " hold " + pair.dump() + ", not a (theta, phi) pair");
    out.push_back({pair[0].get<float>(), pair[1].get<float>()});
  }
  return out;
}

}  // namespace

void addDirectionSetHeader(const BtfViewSet& views, nlohmann::json& header) {
  const BtfDirectionSet& set = views.directions();
  if (!set.isUbo2003()) {
    nlohmann::json lights = nlohmann::json::array();
    for (int v = 0; v < (set.sharedLights() ? 1 : set.viewCount()); ++v) lights.push_back(anglesJson(set.lights(v)));
    std::vector<BtfAngles> view_angles;
    for (int v = 0; v < set.viewCount(); ++v) view_angles.push_back(set.viewAngles(v));
    nlohmann::json directions{{"name", set.name()}, {"views", anglesJson(view_angles)}, {"lights", std::move(lights)}};
    if (set.nominal() && set.nominal()->isUbo2003()) directions["nominal"] = "ubo2003";
    header["directions"] = std::move(directions);
  }
  if (!views.complete()) header["views"] = views.views();
}

BtfViewSet readDirectionSetHeader(const nlohmann::json& header, const std::filesystem::path& path, const char* what) {
  const std::string name = what;
  BtfDirectionSetPtr set = BtfDirectionSet::ubo2003();
  if (const auto it = header.find("directions"); it != header.end()) {
    const nlohmann::json& d = *it;
    if (!d.is_object() || !d.contains("name") || !d.at("name").is_string() || !d.contains("views") || !d.contains("lights") ||
        !d.at("lights").is_array())
      throw FileError(path, name + "'s directions are not a name, views and light lists");
    std::vector<std::vector<BtfAngles>> lights;
    for (const auto& list : d.at("lights")) lights.push_back(anglesOf(list, path, name, "lights"));
    std::vector<BtfAngles> view_angles = anglesOf(d.at("views"), path, name, "views");
    if (lights.size() == 1) lights.resize(view_angles.size(), lights.front());
    BtfDirectionSetPtr nominal;
    if (d.contains("nominal")) {
      if (d.at("nominal") != "ubo2003") throw FileError(path, name + "'s nominal set " + d.at("nominal").dump() + " is unknown");
      nominal = BtfDirectionSet::ubo2003();
    }
    set = BtfDirectionSet::known(std::make_shared<const BtfDirectionSet>(d.at("name").get<std::string>(),
                                                                         std::move(view_angles), std::move(lights),
                                                                         std::move(nominal)));
  }
  if (!header.contains("views")) return BtfViewSet::all(set);
  const nlohmann::json& held = header.at("views");
  if (!held.is_array()) throw FileError(path, name + "'s views are not a list of view indices");
  std::vector<int> list;
  for (const auto& v : held) {
    if (!v.is_number_integer() || v < 0 || v >= set->viewCount())
      throw FileError(path, name + "'s views hold " + v.dump() + ", not a view of its " + std::to_string(set->viewCount()));
    list.push_back(v.get<int>());
  }
  return BtfViewSet(std::move(list), set);
}

}  // namespace btf
