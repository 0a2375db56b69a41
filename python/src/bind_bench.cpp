// btf._bench: the C++ side of tools/bench/python_overhead.py. Each helper times the library's own
// call over the same arrays that Python passes to Material.eval / Material.sample, so that one run
// compares the binding's cost per sample with the C++ loop's.
#include <algorithm>
#include <chrono>
#include <limits>
#include <optional>
#include <vector>

#include "bindings.h"

namespace btf::python {
namespace {

// The fastest of `repeats` runs of `body`, in seconds.
template <class Body>
double fastestSeconds(int repeats, Body&& body) {
  if (repeats < 1) throw py::value_error("repeats: expected at least 1, got " + std::to_string(repeats));
  double best = std::numeric_limits<double>::infinity();
  for (int r = 0; r < repeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    body();
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return best;
}

}  // namespace

void bindBench(py::module_& m) {
  py::module_ bench = m.def_submodule(
      "_bench", "C++-side timings of the calls the bindings make, for tools/bench/python_overhead.py.");
  bench.def(
      "eval_stream_seconds",
      [](const PyMaterial& self, const py::handle& wo_in, const py::handle& wi_in, int repeats) {
        const glm::vec3 wo = toDirection(wo_in, "wo");
        const Rows wi = toRows(wi_in, "wi", 3);
        std::vector<Rgb> out(wi.count);
        const Material& material = *self.material;
        py::gil_scoped_release release;
        return fastestSeconds(repeats, [&] {
          material.evalMany(wo, std::span<const glm::vec3>(wi.vec3(), wi.count), out);
        });
      },
      py::arg("material"), py::arg("wo"), py::arg("wi"), py::arg("repeats") = 5,
      "eval_stream_seconds(material, wo, wi, repeats=5) -> float: the fastest of `repeats` runs of "
      "Material::evalMany(wo, wi) in C++ (wi (N, 3) float32 rows, into a preallocated buffer), in seconds.");
  bench.def(
      "sample_loop_seconds",
      [](const PyMaterial& self, const py::handle& wo_in, const py::handle& u_in, int repeats) {
        const glm::vec3 wo = toDirection(wo_in, "wo");
        const Rows u = toRows(u_in, "u", 2);
        std::vector<std::optional<BsdfSample>> out(u.count);
        const Material& material = *self.material;
        py::gil_scoped_release release;
        return fastestSeconds(repeats, [&] {
          for (std::size_t k = 0; k < u.count; ++k) out[k] = material.sample(wo, glm::vec2(0.0f), u.vec2()[k]);
        });
      },
      py::arg("material"), py::arg("wo"), py::arg("u"), py::arg("repeats") = 5,
      "sample_loop_seconds(material, wo, u, repeats=5) -> float: the fastest of `repeats` runs of a C++ loop of "
      "Material::sample(wo, u[k]) over u (N, 2) float32 rows (libbtf has no stream form of sample), in seconds.");
}

}  // namespace btf::python
