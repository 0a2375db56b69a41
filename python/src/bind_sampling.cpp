// Samplers by name (btf.with_sampler, btf.sampler_names) and the chi-square test of a material's
// sample() against its pdf() (btf.chi2_test).
#include <array>
#include <optional>
#include <string>

#include "bindings.h"
#include "btf/sampling/binned_sampler.h"
#include "btf/sampling/chi2.h"
#include "btf/sampling/parameterization.h"
#include "btf/sampling/sampler_choice.h"

namespace btf::python {
namespace {

constexpr std::array<SamplerChoice, 8> kAllSamplerChoices = {
    SamplerChoice::Uniform,  SamplerChoice::Cosine,      SamplerChoice::Own,    SamplerChoice::Tabulated,
    SamplerChoice::DpCdf,    SamplerChoice::Quadtree,    SamplerChoice::OctreeBound, SamplerChoice::DjWarp};

PyMaterial samplerOver(const PyMaterial& material, const std::string& name, const std::string& parameterization,
                       const py::kwargs& options) {
  const std::optional<SamplerChoice> choice = parseSamplerChoice(name);
  if (!choice) throw py::value_error("unknown sampler '" + name + "' (expected one of " + samplerChoiceNames() + ")");
  SamplerOptions o;
  const std::optional<Parameterization> p = parseParameterization(parameterization);
  if (!p) throw py::value_error("parameterization: expected auto, incident or half, got '" + parameterization + "'");
  o.parameterization = *p;
  for (const auto& [key_object, value] : options) {
    const std::string key = key_object.cast<std::string>();
    if (key == "theta_o_bins") o.theta_o_bins = value.cast<int>();
    else if (key == "phi_o_bins") o.phi_o_bins = value.cast<int>();
    else if (key == "cos_theta_bins") o.cos_theta_bins = value.cast<int>();
    else if (key == "phi_bins") o.phi_bins = value.cast<int>();
    else if (key == "half_vector_bins") o.half_vector_bins = value.cast<int>();
    else if (key == "supersampling") o.supersampling = value.cast<int>();
    else if (key == "defensive_fraction") o.defensive_fraction = value.cast<float>();
    else if (key == "epsilon") o.epsilon = value.cast<float>();
    else if (key == "threshold") o.threshold = value.cast<float>();
    else if (key == "min_depth") o.min_depth = value.cast<int>();
    else if (key == "max_depth") o.max_depth = value.cast<int>();
    else if (key == "quadtree_probes") o.quadtree_probes = value.cast<int>();
    else if (key == "max_tries") o.max_tries = value.cast<int>();
    else
      throw py::type_error("with_sampler: unknown option '" + key +
                           "' (expected theta_o_bins, phi_o_bins, cos_theta_bins, phi_bins, half_vector_bins, "
                           "supersampling, defensive_fraction, epsilon, threshold, min_depth, max_depth, "
                           "quadtree_probes, max_tries)");
  }
  py::gil_scoped_release release;
  return PyMaterial{withSampler(*choice, material.material, o)};
}

Chi2Result runChi2(const PyMaterial& material, const py::handle& wo_in, const py::handle& uv_in, std::uint64_t samples,
                   int theta_bins, int phi_bins, double significance, double min_expected, std::uint64_t seed) {
  const glm::vec3 wo = toDirection(wo_in, "wo");
  const glm::vec2 uv = toUv(uv_in);
  Chi2Options o;
  o.sample_count = samples;
  o.theta_bins = theta_bins;
  o.phi_bins = phi_bins;
  o.significance = significance;
  o.min_expected = min_expected;
  o.seed = seed;
  py::gil_scoped_release release;
  return chi2TestMaterial(*material.material, wo, uv, o);
}

py::array cellsArray(const Chi2Result& r, const std::vector<double>& cells) {
  py::array_t<double> out({py::ssize_t(r.theta_bins), py::ssize_t(r.phi_bins)});
  std::copy(cells.begin(), cells.end(), out.mutable_data());
  return out;
}

}  // namespace

void bindSampling(py::module_& m) {
  m.def(
      "sampler_names",
      [] {
        std::vector<std::string> names;
        for (SamplerChoice c : kAllSamplerChoices) names.emplace_back(toString(c));
        return names;
      },
      "sampler_names() -> list of str: the samplers btf.with_sampler takes (as `btf sample --sampler` and scenes).");

  m.def("with_sampler", &samplerOver, py::arg("material"), py::arg("sampler"), py::arg("parameterization") = "auto",
        R"doc(with_sampler(material, sampler, parameterization='auto', **options) -> Material

The material with another importance sampler: eval() stays the material's, sample() and
pdf() become the sampler's.
  sampler           one of btf.sampler_names(): uniform, cosine, material (its own),
                    tabulated, dp-cdf, quadtree, octree-bound (octree tables), dj-warp
  parameterization  of the tabulated samplers: 'auto' (build both, keep the better),
                    'incident' or 'half'
  options           the tabulated samplers' SamplerOptions: theta_o_bins (32), phi_o_bins
                    (16), cos_theta_bins (64), phi_bins (128), half_vector_bins (128),
                    supersampling (2), defensive_fraction (1e-3), epsilon (DP-CDF
                    tolerance, 1e-3), threshold (4), min_depth (3), max_depth (9),
                    quadtree_probes (4), max_tries (16)
Building the tables takes a moment (parallel, deterministic).)doc");

  py::class_<Chi2Result>(m, "Chi2Result", "The outcome of btf.chi2_test (sampling/chi2.h).")
      .def_readonly("statistic", &Chi2Result::statistic, "The chi-square statistic.")
      .def_readonly("degrees_of_freedom", &Chi2Result::degrees_of_freedom)
      .def_readonly("p_value", &Chi2Result::p_value, "Probability of a statistic at least this large if the sampler is right.")
      .def_readonly("accepted", &Chi2Result::accepted, "p_value >= significance (and no invalid draw).")
      .def_readonly("sample_count", &Chi2Result::sample_count)
      .def_readonly("failed_samples", &Chi2Result::failed_samples, "Draws that returned no direction.")
      .def_readonly("pooled_cells", &Chi2Result::pooled_cells, "Cells merged into the pooled cell.")
      .def_readonly("theta_bins", &Chi2Result::theta_bins)
      .def_readonly("phi_bins", &Chi2Result::phi_bins)
      .def_readonly("message", &Chi2Result::message, "One-line summary.")
      .def_property_readonly("observed", [](const Chi2Result& r) { return cellsArray(r, r.observed); },
                             "Draws per cell, (theta_bins, phi_bins), theta from +z down.")
      .def_property_readonly("expected", [](const Chi2Result& r) { return cellsArray(r, r.expected); },
                             "Draws per cell the pdf predicts, (theta_bins, phi_bins).")
      .def("__bool__", [](const Chi2Result& r) { return r.accepted; })
      .def("__repr__", [](const Chi2Result& r) {
        return "<btf.Chi2Result " + std::string(r.accepted ? "accepted" : "rejected") + ": " + r.message + ">";
      });

  m.def("chi2_test", &runChi2, py::arg("material"), py::arg("wo"), py::arg("uv") = py::none(),
        py::arg("samples") = 1'000'000, py::arg("theta_bins") = 20, py::arg("phi_bins") = 40,
        py::arg("significance") = 0.01, py::arg("min_expected") = 5.0, py::arg("seed") = 1,
        R"doc(chi2_test(material, wo, uv=None, samples=1000000, theta_bins=20, phi_bins=40,
          significance=0.01, min_expected=5.0, seed=1) -> Chi2Result

Chi-square goodness-of-fit test of material.sample(wo) against material.pdf(., wo): the
sphere cut into theta_bins x phi_bins equal-area cells, `samples` draws histogrammed against
the pdf integrated over each cell (cells expecting fewer than min_expected draws pooled).
Accepted when p_value >= significance. wo: a direction (3,) or theta_o in degrees.
Deterministic for a seed, whatever the thread count.)doc");
}

}  // namespace btf::python
