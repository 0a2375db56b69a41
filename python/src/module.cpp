// btf._core: the module, libbtf's errors as Python exceptions, and the conversions that every area
// shares (bindings.h).
#include <pybind11/pybind11.h>

#include <exception>
#include <string>

#include "bindings.h"
#include "btf/core/error.h"
#include "btf/core/math.h"

namespace btf::python {

Rows toRows(const py::handle& object, const char* name, int width) {
  Rows rows;
  if (py::isinstance<py::array>(object)) {
    const auto array = py::reinterpret_borrow<py::array>(object);
    rows.float64 = array.dtype().is(py::dtype::of<double>());
  }
  try {
    rows.data = FloatArray::ensure(object);
  } catch (const py::error_already_set&) {
    rows.data = FloatArray();
  }
  if (!rows.data) {
    PyErr_Clear();
    throw py::value_error(std::string(name) + ": expected an array of numbers of shape (N, " + std::to_string(width) +
                          ") or (" + std::to_string(width) + ",)");
  }
  const FloatArray& a = rows.data;
  if (a.ndim() == 1 && a.shape(0) == width) {
    rows.single = true;
    rows.count = 1;
  } else if (a.ndim() == 2 && a.shape(1) == width) {
    rows.count = std::size_t(a.shape(0));
  } else {
    std::string shape = "(";
    for (py::ssize_t d = 0; d < a.ndim(); ++d) shape += (d ? ", " : "") + std::to_string(a.shape(d));
    shape += a.ndim() == 1 ? ",)" : ")";
    throw py::value_error(std::string(name) + ": expected an array of shape (N, " + std::to_string(width) + ") or (" +
                          std::to_string(width) + ",), got shape " + shape);
  }
  return rows;
}

std::size_t broadcastRows(std::initializer_list<NamedRows> args) {
  std::size_t count = 1;
  const char* first = nullptr;
  for (const NamedRows& a : args) {
    if (!a.rows || a.rows->single) continue;
    if (!first) {
      count = a.rows->count;
      first = a.name;
    } else if (a.rows->count != count) {
      throw py::value_error(std::string(first) + " and " + a.name + " have different row counts (" +
                            std::to_string(count) + " and " + std::to_string(a.rows->count) +
                            "): give N rows of each, or one row to use for all");
    }
  }
  return count;
}

FloatArray newFloatArray(const std::vector<py::ssize_t>& shape) { return FloatArray(shape); }

py::array inPrecision(FloatArray array, bool float64) {
  if (!float64) return array;
  return py::array_t<double>(array);
}

py::array ownedFloatArray(std::vector<float>&& values, const std::vector<py::ssize_t>& shape) {
  auto* owner = new std::vector<float>(std::move(values));
  py::capsule free_when_done(owner, [](void* p) { delete static_cast<std::vector<float>*>(p); });
  return py::array_t<float>(shape, owner->data(), free_when_done);
}

py::array ownedRgbArray(std::vector<Rgb>&& values, std::vector<py::ssize_t> shape) {
  auto* owner = new std::vector<Rgb>(std::move(values));
  py::capsule free_when_done(owner, [](void* p) { delete static_cast<std::vector<Rgb>*>(p); });
  shape.push_back(3);
  return py::array_t<float>(shape, reinterpret_cast<float*>(owner->data()), free_when_done);
}

glm::vec3 toDirection(const py::handle& object, const char* name) {
  if (py::isinstance<py::float_>(object) || py::isinstance<py::int_>(object)) {
    const double theta_deg = object.cast<double>();
    if (!(theta_deg >= 0 && theta_deg <= 90))
      throw py::value_error(std::string(name) + ": theta must be within [0, 90] degrees, got " + std::to_string(theta_deg));
    return sphericalDirection(float(theta_deg) * kPi / 180.0f, 0.0f);
  }
  const Rows rows = toRows(object, name, 3);
  if (!rows.single)
    throw py::value_error(std::string(name) + ": expected one direction, shape (3,), or theta in degrees");
  return rows.vec3()[0];
}

glm::vec2 toUv(const py::handle& object) {
  if (object.is_none()) return {0.0f, 0.0f};
  const Rows rows = toRows(object, "uv", 2);
  if (!rows.single) throw py::value_error("uv: expected one surface position, shape (2,)");
  return rows.vec2()[0];
}

std::string toPath(const py::handle& object) {
  return py::str(py::module_::import("os").attr("fspath")(object)).cast<std::string>();
}

namespace {

// The exception classes, kept for the translator (module lifetime).
PyObject* g_error_type = nullptr;
PyObject* g_file_error_type = nullptr;

}  // namespace

void bindErrors(py::module_& m) {
  g_error_type = PyErr_NewExceptionWithDoc(
      "btf.Error",
      "A failure reported by libbtf (btf::Error). str(e) is the library's complete sentence, naming what failed.",
      PyExc_RuntimeError, nullptr);
  // A file's existence or contents: also an OSError, so that `except OSError` catches it.
  py::tuple bases = py::make_tuple(py::handle(g_error_type), py::handle(PyExc_OSError));
  g_file_error_type = PyErr_NewExceptionWithDoc(
      "btf.FileError",
      "A problem with a file's existence or contents (btf::FileError). str(e) reads '<path>: <problem>'; the "
      "attributes `path` and `problem` hold the two parts.",
      bases.ptr(), nullptr);
  m.add_object("Error", py::handle(g_error_type));
  m.add_object("FileError", py::handle(g_file_error_type));
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const FileError& e) {
      py::object error = py::reinterpret_steal<py::object>(PyObject_CallFunction(g_file_error_type, "s", e.what()));
      if (!error) return;  // the call set its own exception
      error.attr("path") = e.path().string();
      error.attr("problem") = e.problem();
      PyErr_SetObject(g_file_error_type, error.ptr());
    } catch (const Error& e) {
      PyErr_SetString(g_error_type, e.what());
    }
  });
}

}  // namespace btf::python

PYBIND11_MODULE(_core, m) {
  namespace bp = btf::python;
  m.doc() = "libbtf's C++ core: materials, samplers, BTFs, compression, rendering and fits (see the btf package).";
  bp::bindErrors(m);
  bp::bindMaterials(m);
  bp::bindSampling(m);
  bp::bindBtf(m);
  bp::bindRender(m);
  bp::bindFit(m);
  bp::bindDataset(m);
  bp::bindBench(m);
}
