// btf.fit: an analytic model fitted to a MERL-layout table (fit/analytic_fit.h), as `btf fit`. The
// result's parameters are those of the fit file the library writes (fit/fit_file.h), so they read
// the same as a file or a scene's inline model, for every family the fitter knows.
#include <atomic>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <unistd.h>

#include "bindings.h"
#include "btf/core/error.h"
#include "btf/fit/analytic_fit.h"
#include "btf/fit/fit_file.h"
#include "btf/material/model_family.h"
#include "btf/material/registry.h"
#include "btf/material/tabulated_brdf.h"

namespace btf::python {
namespace {

struct PyFit {
  AnalyticFit fit;
  std::string source;  // what was fitted, as the fit file names it
};

// The fit file's JSON as a Python dict: written to a temporary file by the library's writer.
py::dict fitFileDict(const PyFit& self) {
  static std::atomic<unsigned> counter{0};
  const std::filesystem::path path = std::filesystem::temp_directory_path() /
                                     ("libbtf-python-fit-" + std::to_string(::getpid()) + "-" +
                                      std::to_string(counter++) + ".json");
  writeFitFile(path, self.fit, self.source);
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  in.close();
  std::error_code ec;
  std::filesystem::remove(path, ec);
  return py::module_::import("json").attr("loads")(text.str());
}

PyFit fitTable(const py::handle& data, const std::optional<std::string>& model, int lobes, bool per_channel, int starts,
               int max_iterations, const std::string& objective, double energy_weight) {
  AnalyticFitOptions options;
  if (model) {  // a model named is fitted alone, as `btf fit --model M`
    options.family = parseModelFamily(*model, kFittableFamilies);
    options.fallback.reset();
  }
  options.lobes = lobes;
  options.per_channel = per_channel;
  options.starts = starts;
  options.max_iterations = max_iterations;
  options.objective = parseFitObjective(objective);
  options.energy_weight = energy_weight;
  PyFit result;
  if (py::isinstance<PyMaterial>(data)) {
    const PyMaterial& material = data.cast<const PyMaterial&>();
    result.source = material.material->name();
    py::gil_scoped_release release;
    result.fit = fitAnalytic(tabulate(*material.material), options);
  } else {
    result.source = toPath(data);
    py::gil_scoped_release release;
    result.fit = fitAnalytic(openTable(result.source), options);
  }
  return result;
}

py::list albedoChecks(const AnalyticFitReport& report) {
  py::list list;
  for (const AlbedoCheck& a : report.albedo) {
    py::dict entry;
    entry["theta_o_deg"] = a.theta_o_deg;
    entry["data"] = py::make_tuple(a.data.r, a.data.g, a.data.b);
    entry["fit"] = py::make_tuple(a.fit.r, a.fit.g, a.fit.b);
    entry["rel_error"] = a.rel_error;
    list.append(entry);
  }
  return list;
}

}  // namespace

void bindFit(py::module_& m) {
  py::class_<PyFit>(m, "FitResult", R"doc(An analytic model fitted by btf.fit.
  model       the family ('ggx', 'ward', ...)
  parameters  dict of the fitted parameters, as a fit file or a scene writes them
              (btf.create({"type": r.model, **r.parameters}) builds the model)
  material    the fitted model as a btf.Material
  rel_rmse    rel_rmse of f cos(theta_i) against the table (within 80 deg of the normal)
  albedo      list of {theta_o_deg, data, fit, rel_error}: directional albedos compared
  warnings    what is wrong with the fit (no convergence, rel_rmse or albedo off), one line each
  converged, iterations, cost, samples, excluded, starts, seconds: the solver's report
  save(path)  writes the fit file (`btf fit -o`), usable as a material anywhere)doc")
      .def_property_readonly("model", [](const PyFit& f) { return std::string(modelFamilyName(f.fit.parameters.family)); })
      .def_property_readonly("parameters", [](const PyFit& f) {
        const py::dict file = fitFileDict(f);  // the accessor below must not outlive it
        return py::object(file["parameters"]);
      })
      .def_property_readonly("material", [](const PyFit& f) { return PyMaterial{f.fit.material}; })
      .def_property_readonly("rel_rmse", [](const PyFit& f) { return f.fit.report.rel_rmse; })
      .def_property_readonly("albedo", [](const PyFit& f) { return albedoChecks(f.fit.report); })
      .def_property_readonly("warnings", [](const PyFit& f) { return f.fit.report.warnings; })
      .def_property_readonly("fallback", [](const PyFit& f) { return f.fit.report.fallback; })
      .def_property_readonly("converged", [](const PyFit& f) { return f.fit.report.converged; })
      .def_property_readonly("iterations", [](const PyFit& f) { return f.fit.report.iterations; })
      .def_property_readonly("cost", [](const PyFit& f) { return f.fit.report.cost; })
      .def_property_readonly("samples", [](const PyFit& f) { return f.fit.report.samples; })
      .def_property_readonly("excluded", [](const PyFit& f) { return f.fit.report.excluded; })
      .def_property_readonly("starts", [](const PyFit& f) { return f.fit.report.starts; })
      .def_property_readonly("seconds", [](const PyFit& f) { return f.fit.report.seconds; })
      .def_property_readonly("source", [](const PyFit& f) { return f.source; })
      .def("to_dict", &fitFileDict, "to_dict() -> dict: the whole fit file (model, parameters, the fit's report).")
      .def(
          "save", [](const PyFit& f, const py::handle& path) { writeFitFile(toPath(path), f.fit, f.source); },
          py::arg("path"), "save(path): writes the fit file (JSON, atomically), as `btf fit -o path`.")
      .def("__repr__", [](const PyFit& f) {
        return "<btf.FitResult " + std::string(modelFamilyName(f.fit.parameters.family)) +
               " rel_rmse=" + std::to_string(f.fit.report.rel_rmse) + ">";
      });

  const AnalyticFitOptions defaults;  // the library's default fit, as `btf fit`'s
  m.def("fit", &fitTable, py::arg("data"), py::arg("model") = py::none(),
        py::arg("lobes") = defaults.lobes, py::arg("per_channel") = defaults.per_channel, py::arg("starts") = defaults.starts,
        py::arg("max_iterations") = defaults.max_iterations,
        py::arg("objective") = std::string(fitObjectiveName(defaults.objective)),
        py::arg("energy_weight") = defaults.energy_weight,
        R"doc(fit(data, model=None, lobes=1, per_channel=False, starts=6, max_iterations=100,
    objective='linear', energy_weight=1.0) -> FitResult

Fits an analytic model to an isotropic BRDF table with Ceres, as `btf fit` (the defaults are its
default fit).
  data           a path or spec opened as a MERL-layout table (a MERL .binary as stored, an
                 RGL file or model tabulated), or a btf.Material (tabulated first)
  model          a fittable family: abc, sgd, ggx, ggx2, ward, lafortune; None: the default fit
                 (abc, and sgd too where abc's fit is degenerate; FitResult.fallback says so)
  lobes          lafortune: 1 to 3;  per_channel: each channel its own lobe shapes
  starts         initial guesses screened;  max_iterations: per start
  objective      'linear' (the rel_rmse measure itself) or 'log' (robust, log-compressed)
  energy_weight  weight of the directional-albedo term (0 leaves it out)
Deterministic; runs in parallel over the starts.)doc");
}

}  // namespace btf::python
