#include "btf/fit/fit_file.h"

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "btf/core/error.h"
#include "btf/io/atomic_file.h"
#include "btf/material/registry.h"

namespace btf {
namespace {

using json = nlohmann::json;

json rgbJson(const Rgb& c) { return json::array({c.r, c.g, c.b}); }

// Readers of one value each; `where` is the key path for the message.
class FitReader {
 public:
  explicit FitReader(const std::filesystem::path& path) : path_(path) {}

  [[noreturn]] void fail(const std::string& problem) const { throw FileError(path_, problem); }

  const json& member(const json& object, const std::string& key, const std::string& where) const {
    if (!object.is_object()) fail(where + ": expected an object");
    const auto it = object.find(key);
    if (it == object.end()) fail(where + ": missing \"" + key + "\"");
    return *it;
  }
  void allowOnly(const json& object, std::initializer_list<const char*> keys, const std::string& where) const {
    if (!object.is_object()) fail(where + ": expected an object, got " + std::string(object.type_name()));
    for (const auto& [key, value] : object.items()) {
      bool known = false;
      for (const char* k : keys) known = known || key == k;
      if (!known) fail(where + ": unknown key \"" + key + "\"");
    }
  }
  // number() in double precision (ABC's B reaches 1e7, where a float keeps 4 digits).
  double real(const json& value, const std::string& where, double lo, double hi) const {
    (void)number(value, where, lo, hi);
    return value.get<double>();
  }
  float number(const json& value, const std::string& where, double lo, double hi) const {
    if (!value.is_number()) fail(where + ": expected a number");
    const double v = value.get<double>();
    if (!std::isfinite(v) || v < lo || v > hi)
      fail(where + ": " + value.dump() + " is outside [" + json(lo).dump() + ", " + json(hi).dump() + "]");
    return float(v);
  }
  Rgb rgb(const json& value, const std::string& where, double hi) const {
    if (!value.is_array() || value.size() != 3) fail(where + ": expected [r, g, b]");
    return {number(value[0], where + "/0", 0, hi), number(value[1], where + "/1", 0, hi), number(value[2], where + "/2", 0, hi)};
  }

 private:
  const std::filesystem::path& path_;
};

// The SGD lobe shape's keys, in the published fits' names and order (the material checks the values).
template <class Shape>
auto sgdShapeKeys(Shape& s) {
  using Value = std::conditional_t<std::is_const_v<Shape>, const double*, double*>;
  return std::array<std::pair<const char*, Value>, 9>{{{"alpha", &s.alpha}, {"p", &s.p}, {"f0", &s.f0}, {"f1", &s.f1},
                                                       {"kap", &s.kap}, {"lambda", &s.lambda}, {"c", &s.c}, {"k", &s.k},
                                                       {"theta0", &s.theta0}}};
}

// The report's albedo checks, informative.
json albedoJson(const std::vector<AlbedoCheck>& checks) {
  json a = json::array();
  for (const AlbedoCheck& c : checks)
    a.push_back({{"theta_o_deg", c.theta_o_deg}, {"data", rgbJson(c.data)}, {"fit", rgbJson(c.fit)}, {"rel_error", c.rel_error}});
  return a;
}

}  // namespace

void writeFitFile(const std::filesystem::path& path, const AnalyticFit& fit, const std::string& source) {
  const AnalyticParameters& p = fit.parameters;
  // What is written is finite (a fit that diverged is an error, not a file).
  const SgdChannel& sgd = p.sgd_shape;
  bool finite = p.diffuse.isFinite() && p.specular.isFinite() && std::isfinite(p.alpha) && p.specular_2.isFinite() &&
                std::isfinite(p.alpha_2) && std::isfinite(p.abc_b) && std::isfinite(p.abc_c) && std::isfinite(p.abc_ior);
  for (const double v : {sgd.alpha, sgd.p, sgd.f0, sgd.f1, sgd.kap, sgd.lambda, sgd.c, sgd.k, sgd.theta0})
    finite = finite && std::isfinite(v);
  for (const LafortuneLobe& lobe : p.lobes)
    finite = finite && lobe.rho.isFinite() && std::isfinite(lobe.c.x) && std::isfinite(lobe.c.y) &&
             std::isfinite(lobe.c.z) && std::isfinite(lobe.exponent);
  if (!finite) throw FileError(path, "not written: the fitted parameters are not finite");
  json parameters = {{"diffuse", rgbJson(p.diffuse)}};
  switch (p.family) {
    case ModelFamily::Ggx:
      parameters["f0"] = rgbJson(p.specular);
      parameters["alpha"] = p.alpha;
      break;
    case ModelFamily::Ggx2:
      parameters["f0"] = rgbJson(p.specular);
      parameters["alpha"] = p.alpha;
      parameters["f0_2"] = rgbJson(p.specular_2);
      parameters["alpha_2"] = p.alpha_2;
      break;
    case ModelFamily::Ward:
      parameters["specular"] = rgbJson(p.specular);
      parameters["alpha"] = p.alpha;
      break;
    case ModelFamily::Abc:
      parameters["a"] = rgbJson(p.specular);
      parameters["b"] = p.abc_b;
      parameters["c"] = p.abc_c;
      parameters["ior"] = p.abc_ior;
      break;
    case ModelFamily::Sgd:
      // The published fits' names (sgd_bagher2012_merl.csv): rho_d is "diffuse", one shape for all channels.
      parameters["rho_s"] = rgbJson(p.specular);
      for (const auto& [key, value] : sgdShapeKeys(p.sgd_shape)) parameters[key] = *value;
      break;
    case ModelFamily::Lafortune: {
      json lobes = json::array();
      for (const LafortuneLobe& lobe : p.lobes)
        lobes.push_back({{"rho", rgbJson(lobe.rho)}, {"c", json::array({lobe.c.x, lobe.c.y, lobe.c.z})}, {"exponent", lobe.exponent}});
      parameters["lobes"] = std::move(lobes);
      break;
    }
    default: throw Error(std::string("a fit file holds no ") + modelFamilyName(p.family) + " model");
  }
  const AnalyticFitReport& r = fit.report;
  const json doc = {{"format", kFitFileFormat},
                    {"version", 1},
                    {"model", modelFamilyName(p.family)},
                    {"parameters", std::move(parameters)},
                    {"fit",
                     {{"source", source},
                      {"rel_rmse", r.rel_rmse},
                      {"converged", r.converged},
                      {"cost", r.cost},
                      {"samples", r.samples},
                      {"excluded", r.excluded},
                      {"starts", r.starts},
                      {"screening_converged", r.screening_converged},
                      {"iterations", r.iterations},
                      {"seconds", r.seconds},
                      {"ceres", r.ceres_report},
                      {"energy_weight", r.energy_weight},
                      {"albedo", albedoJson(r.albedo)},
                      {"warnings", r.warnings},
                      {"fallback", r.fallback}}}};
  writeFileAtomically(path, [&](std::ofstream& out) { out << doc.dump(2) << '\n'; });
}

AnalyticParameters readFitFile(const std::filesystem::path& path) {
  requireReadableFile(path);
  std::ifstream in(path, std::ios::binary);
  json doc;
  try {
    doc = json::parse(in);
  } catch (const json::exception& e) {
    throw FileError(path, std::string("malformed JSON: ") + e.what());
  }
  const FitReader r(path);
  if (!doc.is_object()) r.fail("expected a JSON object (a libbtf fit file)");
  r.allowOnly(doc, {"format", "version", "model", "parameters", "fit"}, "/");
  const json& format = r.member(doc, "format", "/");
  if (format != kFitFileFormat) r.fail("/format: expected \"" + std::string(kFitFileFormat) + "\", got " + format.dump());
  const json& version = r.member(doc, "version", "/");
  if (version != 1) r.fail("/version: " + version.dump() + " is not a version this libbtf reads (1)");
  const json& model = r.member(doc, "model", "/");
  if (!model.is_string()) r.fail("/model: expected a string");
  AnalyticParameters p;
  try {
    p.family = parseModelFamily(model.get<std::string>(), kFittableFamilies);
  } catch (const Error& e) {
    r.fail(std::string("/model: ") + e.what());
  }
  const json& q = r.member(doc, "parameters", "/");
  p.diffuse = r.rgb(r.member(q, "diffuse", "/parameters"), "/parameters/diffuse", 1e6);
  switch (p.family) {
    case ModelFamily::Ggx:
    case ModelFamily::Ggx2: {
      // ggx2 is ggx with a second lobe: the same keys, and the second lobe's under the suffix _2.
      const bool two = p.family == ModelFamily::Ggx2;
      r.allowOnly(q, two ? std::initializer_list<const char*>{"diffuse", "f0", "alpha", "f0_2", "alpha_2"}
                         : std::initializer_list<const char*>{"diffuse", "f0", "alpha"},
                  "/parameters");
      for (const std::string& suffix : two ? std::vector<std::string>{"", "_2"} : std::vector<std::string>{""}) {
        const Rgb f0 = r.rgb(r.member(q, "f0" + suffix, "/parameters"), "/parameters/f0" + suffix, 1);
        const float alpha = r.number(r.member(q, "alpha" + suffix, "/parameters"), "/parameters/alpha" + suffix, 1e-6, 1e3);
        (suffix.empty() ? p.specular : p.specular_2) = f0;
        (suffix.empty() ? p.alpha : p.alpha_2) = alpha;
      }
      break;
    }
    case ModelFamily::Abc:
      r.allowOnly(q, {"diffuse", "a", "b", "c", "ior"}, "/parameters");
      p.specular = r.rgb(r.member(q, "a", "/parameters"), "/parameters/a", 1e6);
      p.abc_b = r.real(r.member(q, "b", "/parameters"), "/parameters/b", 1e-6, 1e10);
      p.abc_c = r.real(r.member(q, "c", "/parameters"), "/parameters/c", -1e3, 1e3);
      p.abc_ior = r.real(r.member(q, "ior", "/parameters"), "/parameters/ior", 1, 100);
      break;
    case ModelFamily::Sgd:
      r.allowOnly(q, {"diffuse", "rho_s", "alpha", "p", "f0", "f1", "kap", "lambda", "c", "k", "theta0"}, "/parameters");
      p.specular = r.rgb(r.member(q, "rho_s", "/parameters"), "/parameters/rho_s", 1e8);
      for (const auto& [key, value] : sgdShapeKeys(p.sgd_shape))
        *value = r.real(r.member(q, key, "/parameters"), std::string("/parameters/") + key, -1e38, 1e38);
      break;
    case ModelFamily::Ward:
      r.allowOnly(q, {"diffuse", "specular", "alpha"}, "/parameters");
      p.specular = r.rgb(r.member(q, "specular", "/parameters"), "/parameters/specular", 1e6);
      p.alpha = r.number(r.member(q, "alpha", "/parameters"), "/parameters/alpha", 1e-6, 1e3);
      break;
    case ModelFamily::Lafortune: {
      r.allowOnly(q, {"diffuse", "lobes"}, "/parameters");
      const json& lobes = r.member(q, "lobes", "/parameters");
      if (!lobes.is_array() || lobes.empty()) r.fail("/parameters/lobes: expected an array of one or more lobes");
      // Bounded as the fitter is: a file of 100,000 lobes would make every evaluation crawl.
      if (lobes.size() > std::size_t(3 * kMaxFitLobes))
        r.fail("/parameters/lobes: " + std::to_string(lobes.size()) + " lobes; a fit has at most " +
               std::to_string(3 * kMaxFitLobes) + " (" + std::to_string(kMaxFitLobes) + " per channel)");
      for (std::size_t i = 0; i < lobes.size(); ++i) {
        const std::string where = "/parameters/lobes/" + std::to_string(i);
        r.allowOnly(lobes[i], {"rho", "c", "exponent"}, where);
        LafortuneLobe lobe;
        lobe.rho = r.rgb(r.member(lobes[i], "rho", where), where + "/rho", 1e6);
        const json& c = r.member(lobes[i], "c", where);
        if (!c.is_array() || c.size() != 3) r.fail(where + "/c: expected [cx, cy, cz]");
        for (int k = 0; k < 3; ++k) lobe.c[k] = r.number(c[std::size_t(k)], where + "/c/" + std::to_string(k), -1e6, 1e6);
        lobe.exponent = r.number(r.member(lobes[i], "exponent", where), where + "/exponent", 0, 1e6);
        p.lobes.push_back(lobe);
      }
      break;
    }
    default: break;  // parseModelFamily admitted only the fittable families
  }
  try {
    (void)makeAnalyticMaterial(p);  // the model's own checks (e.g. a lobe with c = 0)
  } catch (const Error& e) {
    r.fail(std::string("/parameters: ") + e.what());
  }
  return p;
}

BTF_REGISTER_MATERIAL(fitted, {.name = "fitted",
                               .summary = "an analytic model fitted by btf fit (its JSON file)",
                               .keys = {"file"},
                               .formats = {{.description = "analytic model fitted by btf fit",
                                            .extensions = {".json"},
                                            .sniff = [](std::span<const unsigned char> head, std::uintmax_t) {
                                              const std::string_view text(reinterpret_cast<const char*>(head.data()), head.size());
                                              return text.find(std::string("\"") + kFitFileFormat + "\"") != std::string_view::npos;
                                            }}},
                               .create = [](const MaterialParams& p) -> std::shared_ptr<const Material> {
                                 return makeAnalyticMaterial(readFitFile(p.existingPath("file")));
                               }});

}  // namespace btf
