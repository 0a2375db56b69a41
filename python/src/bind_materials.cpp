// btf.Material and the registry's ways in (btf.open, btf.create): eval, pdf and sample vectorised
// over numpy rows, with the loops in C++ and the GIL released; directional albedo.
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>

#include "bindings.h"
#include "btf/core/error.h"
#include "btf/material/albedo.h"
#include "btf/material/material_params.h"
#include "btf/material/registry.h"

namespace btf::python {
namespace {

// A Python value as JSON: dicts with string keys, lists and tuples, numbers, bools, strings, None,
// numpy arrays and scalars (through tolist()), paths (os.fspath).
nlohmann::json materialJsonOf(const py::handle& value, const std::string& where) {
  if (value.is_none()) return nullptr;
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>();
  if (py::isinstance<py::int_>(value)) return value.cast<long long>();
  if (py::isinstance<py::float_>(value)) return value.cast<double>();
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::isinstance<py::dict>(value)) {
    nlohmann::json object = nlohmann::json::object();
    for (const auto& [k, v] : py::reinterpret_borrow<py::dict>(value)) {
      if (!py::isinstance<py::str>(k)) throw py::type_error(where + ": keys must be strings, got " + py::repr(k).cast<std::string>());
      const std::string key = k.cast<std::string>();
      object[key] = materialJsonOf(v, where + "/" + key);
    }
    return object;
  }
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    nlohmann::json array = nlohmann::json::array();
    std::size_t i = 0;
    for (const auto& item : value) array.push_back(materialJsonOf(item, where + "/" + std::to_string(i++)));
    return array;
  }
  if (py::hasattr(value, "tolist")) return materialJsonOf(value.attr("tolist")(), where);  // numpy arrays and scalars
  if (py::hasattr(value, "__fspath__")) return toPath(value);
  throw py::type_error(where + ": cannot be a material parameter: " + py::repr(value).cast<std::string>() +
                       " (expected a number, bool, string, list or dict)");
}

std::string materialRepr(const PyMaterial& m) { return "<btf.Material " + m.material->name() + ">"; }

// eval(wi, wo, uv): one wo and one uv for all rows go through evalMany (the stream call), else a
// loop of eval.
py::array materialEval(const PyMaterial& self, const py::handle& wi_in, const py::handle& wo_in, const py::handle& uv_in,
                       const py::handle& out_in) {
  const Rows wi = toRows(wi_in, "wi", 3), wo = toRows(wo_in, "wo", 3);
  std::optional<Rows> uv;
  if (!uv_in.is_none()) uv = toRows(uv_in, "uv", 2);
  const std::size_t n = broadcastRows({{&wi, "wi"}, {&wo, "wo"}, {uv ? &*uv : nullptr, "uv"}});
  const bool single = wi.single && wo.single && (!uv || uv->single);
  FloatArray out;
  if (out_in.is_none()) {
    out = single ? newFloatArray({3}) : newFloatArray({py::ssize_t(n), 3});
  } else {
    // The caller's buffer, written in place: float32, C-contiguous, writeable, of the result's shape.
    const auto given = py::reinterpret_borrow<py::array>(out_in);
    const bool fits = py::isinstance<py::array_t<float>>(out_in) && (given.flags() & py::array::c_style) &&
                      given.writeable() && given.ndim() == (single ? 1 : 2) &&
                      (single ? given.shape(0) == 3 : given.shape(0) == py::ssize_t(n) && given.shape(1) == 3);
    if (!fits)
      throw py::value_error("out: expected a writeable, C-contiguous float32 array of shape " +
                            std::string(single ? "(3,)" : "(" + std::to_string(n) + ", 3)"));
    out = py::reinterpret_borrow<FloatArray>(out_in);
  }
  Rgb* f = reinterpret_cast<Rgb*>(out.mutable_data());
  const Material& material = *self.material;
  {
    py::gil_scoped_release release;
    if (wo.single && (!uv || uv->single)) {
      const glm::vec2 at = uv ? uv->vec2()[0] : glm::vec2(0.0f);
      // Here wi.single means every argument is one row (n == 1).
      if (wi.single) f[0] = material.eval(wi.vec3()[0], wo.vec3()[0], at);
      else material.evalMany(wo.vec3()[0], std::span<const glm::vec3>(wi.vec3(), n), std::span<Rgb>(f, n), at);
    } else {
      const glm::vec3 *pi = wi.vec3(), *po = wo.vec3();
      const glm::vec2* pu = uv ? uv->vec2() : nullptr;
      for (std::size_t k = 0; k < n; ++k)
        f[k] = material.eval(pi[wi.single ? 0 : k], po[wo.single ? 0 : k],
                             pu ? pu[uv->single ? 0 : k] : glm::vec2(0.0f));
    }
  }
  if (!out_in.is_none()) return out;
  return inPrecision(std::move(out), wi.float64 || wo.float64);
}

py::object materialPdf(const PyMaterial& self, const py::handle& wi_in, const py::handle& wo_in, const py::handle& uv_in) {
  const Rows wi = toRows(wi_in, "wi", 3), wo = toRows(wo_in, "wo", 3);
  std::optional<Rows> uv;
  if (!uv_in.is_none()) uv = toRows(uv_in, "uv", 2);
  const std::size_t n = broadcastRows({{&wi, "wi"}, {&wo, "wo"}, {uv ? &*uv : nullptr, "uv"}});
  const bool single = wi.single && wo.single && (!uv || uv->single);
  FloatArray out = newFloatArray({py::ssize_t(n)});
  float* p = out.mutable_data();
  const Material& material = *self.material;
  {
    py::gil_scoped_release release;
    const glm::vec3 *pi = wi.vec3(), *po = wo.vec3();
    const glm::vec2* pu = uv ? uv->vec2() : nullptr;
    for (std::size_t k = 0; k < n; ++k)
      p[k] = material.pdf(pi[wi.single ? 0 : k], po[wo.single ? 0 : k], pu ? pu[uv->single ? 0 : k] : glm::vec2(0.0f));
  }
  if (single) return py::float_(double(p[0]));
  return inPrecision(std::move(out), wi.float64 || wo.float64);
}

py::object materialSample(const PyMaterial& self, const py::handle& wo_in, const py::handle& u_in, const py::handle& uv_in) {
  const Rows wo = toRows(wo_in, "wo", 3), u = toRows(u_in, "u", 2);
  std::optional<Rows> uv;
  if (!uv_in.is_none()) uv = toRows(uv_in, "uv", 2);
  const std::size_t n = broadcastRows({{&wo, "wo"}, {&u, "u"}, {uv ? &*uv : nullptr, "uv"}});
  FloatArray wi = newFloatArray({py::ssize_t(n), 3}), weight = newFloatArray({py::ssize_t(n), 3}),
             pdf = newFloatArray({py::ssize_t(n)});
  py::array_t<bool> valid({py::ssize_t(n)});
  glm::vec3* out_wi = reinterpret_cast<glm::vec3*>(wi.mutable_data());
  Rgb* out_weight = reinterpret_cast<Rgb*>(weight.mutable_data());
  float* out_pdf = pdf.mutable_data();
  bool* out_valid = valid.mutable_data();
  const Material& material = *self.material;
  {
    py::gil_scoped_release release;
    const glm::vec3* po = wo.vec3();
    const glm::vec2 *pu = u.vec2(), *puv = uv ? uv->vec2() : nullptr;
    for (std::size_t k = 0; k < n; ++k) {
      const std::optional<BsdfSample> s = material.sample(po[wo.single ? 0 : k], puv ? puv[uv->single ? 0 : k] : glm::vec2(0.0f),
                                                          pu[u.single ? 0 : k]);
      if (s) {
        out_wi[k] = s->wi;
        out_weight[k] = s->weight;
        out_pdf[k] = s->pdf;
        out_valid[k] = true;
      } else {
        out_wi[k] = glm::vec3(0.0f);
        out_weight[k] = Rgb(0.0f);
        out_pdf[k] = 0.0f;
        out_valid[k] = false;
      }
    }
  }
  const bool float64 = wo.float64 || u.float64;
  py::object samples = py::module_::import("btf._core").attr("Samples");
  return samples(inPrecision(std::move(wi), float64), inPrecision(std::move(weight), float64),
                 inPrecision(std::move(pdf), float64), valid);
}

py::array rgbArray(const Rgb& c) {
  FloatArray out = newFloatArray({3});
  float* p = out.mutable_data();
  p[0] = c.r, p[1] = c.g, p[2] = c.b;
  return out;
}

py::array materialAlbedo(const PyMaterial& self, const py::handle& wo_in, std::optional<std::uint32_t> samples,
                         std::uint64_t seed) {
  const glm::vec3 wo = toDirection(wo_in, "wo");
  const Material& material = *self.material;
  Rgb value;
  {
    py::gil_scoped_release release;
    if (!samples && !material.isAnisotropic() && wo.z < 1.0f) {
      value = integrateAlbedoHalfVector(material, std::acos(std::clamp(wo.z, -1.0f, 1.0f)));
    } else {
      value = estimateAlbedo(material, wo, samples.value_or(1u << 20), seed).value;
    }
  }
  return rgbArray(value);
}

py::tuple materialEstimateAlbedo(const PyMaterial& self, const py::handle& wo_in, std::uint32_t samples, std::uint64_t seed) {
  const glm::vec3 wo = toDirection(wo_in, "wo");
  AlbedoEstimate estimate;
  {
    py::gil_scoped_release release;
    estimate = estimateAlbedo(*self.material, wo, samples, seed);
  }
  return py::make_tuple(rgbArray(estimate.value), rgbArray(estimate.standard_error));
}

}  // namespace

void bindMaterials(py::module_& m) {
  m.attr("Samples") = py::module_::import("collections").attr("namedtuple")(
      "Samples", py::make_tuple("wi", "weight", "pdf", "valid"), py::arg("module") = "btf");
  m.attr("Samples").attr("__doc__") =
      "Material.sample's result: wi (N, 3) sampled light directions; weight (N, 3) = f(wi, wo) cos(theta_i) / pdf; "
      "pdf (N,) the solid-angle density of wi (equal to Material.pdf(wi, wo)); valid (N,) False where the draw "
      "returned no direction (wi, weight and pdf are 0 there).";

  py::class_<PyMaterial>(m, "Material", R"doc(A reflectance model: an analytic model, a measured table (MERL, RGL), an octree
table, a fit, a compressed BTF, or any of them behind a sampler (btf.with_sampler).

Build one with btf.open(path_or_spec) or btf.create(params).

Conventions: directions are unit vectors in the local shading frame (+z is the normal,
theta from +z, phi from +x); wi is the light direction, wo the view, both pointing away
from the surface. f is in 1/sr, per RGB channel.

Arrays: rows of directions (N, 3), uniforms (N, 2), surface positions uv (N, 2); one row
of shape (3,) or (2,) is used for all N. float32 and float64 are accepted; libbtf computes
in float32, and results are float64 when a direction (or u) argument was float64, else
float32. The loops run in C++ without the GIL.)doc")
      .def_property_readonly("name", [](const PyMaterial& s) { return s.material->name(); },
                             "Short description, e.g. 'ggx(alpha=0.2)'.")
      .def_property_readonly("is_anisotropic", [](const PyMaterial& s) { return s.material->isAnisotropic(); },
                             "True when f depends on the azimuth of the half vector, not only on relative angles.")
      .def_property_readonly("is_reciprocal", [](const PyMaterial& s) { return s.material->isReciprocal(); },
                             "True when eval(wi, wo) == eval(wo, wi) by construction.")
      .def("eval", &materialEval, py::arg("wi"), py::arg("wo"), py::arg("uv") = py::none(), py::arg("out") = py::none(),
           R"doc(eval(wi, wo, uv=None, out=None) -> array (N, 3) or (3,)

Reflectance f(wi, wo) in 1/sr per RGB channel; 0 below the horizon.
  wi  light directions, (N, 3) or (3,)
  wo  view directions, (N, 3) or (3,); one wo for all rows uses the material's stream
      call (Material::evalMany), the fastest path
  uv  surface positions (N, 2) or (2,), for BTFs; None: (0, 0)
  out a float32 C-contiguous array of the result's shape to write into and return (no
      new array: repeated calls on large N skip the allocation and its page faults)
Returns (3,) when every argument is one row.)doc")
      .def("pdf", &materialPdf, py::arg("wi"), py::arg("wo"), py::arg("uv") = py::none(),
           R"doc(pdf(wi, wo, uv=None) -> array (N,) or float

Solid-angle density with which sample(wo) returns wi; equals the pdf sample() reports,
bit for bit.)doc")
      .def("sample", &materialSample, py::arg("wo"), py::arg("u"), py::arg("uv") = py::none(),
           R"doc(sample(wo, u, uv=None) -> btf.Samples(wi, weight, pdf, valid)

Draws light directions for view directions wo from uniforms u in [0, 1)^2.
  wo  (N, 3) or (3,)      u  (N, 2) or (2,)      uv  (N, 2), (2,) or None
Returns wi (N, 3), weight (N, 3) = f cos(theta_i) / pdf, pdf (N,), valid (N,) bool:
False where the draw fell where the material reflects nothing (the other fields are 0).)doc")
      .def("albedo", &materialAlbedo, py::arg("wo"), py::arg("samples") = py::none(), py::arg("seed") = 0,
           R"doc(albedo(wo, samples=None, seed=0) -> array (3,)

Directional albedo rho(wo) = integral of f(wi, wo) cos(theta_i) dwi per channel.
  wo       a direction (3,), or theta_o in degrees (at phi = 0)
  samples  None: deterministic half-vector quadrature for an isotropic material
           (Monte Carlo with 2^20 samples for an anisotropic one); a number: Monte Carlo
           with the material's own sampling, that many samples
  seed     of the Monte Carlo estimate (the result does not depend on the thread count))doc")
      .def("estimate_albedo", &materialEstimateAlbedo, py::arg("wo"), py::arg("samples") = 1 << 20,
           py::arg("seed") = 0,
           R"doc(estimate_albedo(wo, samples=1048576, seed=0) -> (value (3,), standard_error (3,))

Monte Carlo directional albedo with the material's own importance sampling, and one
standard error per channel. wo: a direction (3,) or theta_o in degrees.)doc")
      .def("__repr__", &materialRepr);

  m.def(
      "open",
      [](const py::handle& path_or_spec, const std::string& material, std::optional<std::string> lookup) {
        OpenOptions options;
        options.database_material = material;
        if (lookup) {
          options.lookup = parseTableLookup(*lookup);
          if (!options.lookup)
            throw py::value_error("lookup: expected 'nearest', 'interpolated' or 'truncated', got '" + *lookup + "'");
        }
        const std::string path = toPath(path_or_spec);
        py::gil_scoped_release release;
        return PyMaterial{openMaterial(path, options)};
      },
      py::arg("path_or_spec"), py::arg("material") = "", py::arg("lookup") = py::none(),
      R"doc(open(path_or_spec, material='', lookup=None) -> Material

Opens any material the library knows: a file (format recognised by content, then by
extension: MERL .binary, RGL .bsdf, a btf fit .json, .octree, .btfz, an image-folder or
Bonn .btf BTF) or a spec such as 'merl-fit:sgd:alum-bronze'.
  material  which material of a .btfz database ('' when it holds one)
  lookup    'nearest', 'interpolated' or 'truncated' for table types (None: the type's default)
Raises btf.FileError naming the path for a missing or unreadable file.)doc");

  m.def(
      "create",
      [](const py::dict& params, const std::string& origin) {
        const std::string text = materialJsonOf(params, "").dump();
        const MaterialParams set = MaterialParams::parse(text, origin);
        py::gil_scoped_release release;
        return PyMaterial{createMaterial(set)};
      },
      py::arg("params"), py::arg("origin") = "btf.create()",
      R"doc(create(params, origin='btf.create()') -> Material

Builds a material from a parameter set, the same JSON object a scene file holds under
"materials", e.g. {"type": "ggx", "diffuse": [0.5, 0.1, 0.1], "f0": 0.04, "alpha": 0.2}.
Values may be numbers, bools, strings, lists, dicts, numpy arrays or paths. Relative file
names resolve against the folder of `origin` (the current folder by default); errors name
`origin` and the key: "btf.create(): /alpha: expected a positive number, got -1".
`btf info --types` (or btf.material_types()) lists the types and their keys.)doc");

  m.def(
      "material_types",
      [] {
        py::dict types;
        for (const MaterialType* t : materialTypes())
          types[py::str(t->name)] = py::dict(py::arg("summary") = t->summary, py::arg("keys") = t->keys,
                                             py::arg("spec_keys") = t->spec_keys);
        return types;
      },
      "material_types() -> dict: every registered material type by name, with its summary, the keys its parameter "
      "sets take and its spec keys.");
}

}  // namespace btf::python
