// The Python module btf._core: one bind function per area, each in its own source, called in this
// order by module.cpp. Shared here: the wrappers that hold libbtf's objects for Python and the
// conversions between numpy arrays and libbtf's vectors.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <glm/glm.hpp>

#include <cstddef>
#include <initializer_list>
#include <memory>
#include <string>
#include <vector>

#include "btf/core/rgb.h"
#include "btf/io/btf_data.h"
#include "btf/material/material.h"

namespace btf::python {

namespace py = pybind11;

void bindErrors(py::module_& m);     // module.cpp: btf.Error, btf.FileError
void bindMaterials(py::module_& m);  // bind_materials.cpp: Material, open, create, albedo
void bindSampling(py::module_& m);   // bind_sampling.cpp: with_sampler, sampler_names, chi2_test
void bindBtf(py::module_& m);        // bind_btf.cpp: BtfSource, open_btf, compress, decompress, merge, compare
void bindRender(py::module_& m);     // bind_render.cpp: render
void bindFit(py::module_& m);        // bind_fit.cpp: fit
void bindDataset(py::module_& m);    // bind_dataset.cpp: dataset map-reduce compression
void bindBench(py::module_& m);      // bind_bench.cpp: btf._bench, C++-side timings

// A material as Python holds it (pybind11 holders cannot be shared_ptr<const T>).
struct PyMaterial {
  std::shared_ptr<const Material> material;
};
// A BTF as Python holds it.
struct PyBtfSource {
  std::shared_ptr<const BtfSource> source;
};

// Directions and uniforms arrive as 3- and 2-wide float rows: the same bytes as glm::vec3/vec2 and
// btf::Rgb, which the conversions below rely on.
static_assert(sizeof(glm::vec3) == 3 * sizeof(float) && alignof(glm::vec3) == alignof(float));
static_assert(sizeof(glm::vec2) == 2 * sizeof(float) && alignof(glm::vec2) == alignof(float));
static_assert(sizeof(Rgb) == 3 * sizeof(float) && alignof(Rgb) == alignof(float));

using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;

// Rows of `width` floats from a numpy array or a sequence: shape (N, width), or (width,) for one
// row (`single`). float64 (and integer) input is converted to float32, libbtf's precision;
// `float64` records that the caller passed float64, so results come back in it.
struct Rows {
  FloatArray data;
  std::size_t count = 0;
  bool single = false;
  bool float64 = false;
  const float* at(std::size_t i) const { return data.data() + i * std::size_t(data.ndim() == 1 ? 0 : data.shape(1)); }
  const glm::vec3* vec3() const { return reinterpret_cast<const glm::vec3*>(data.data()); }
  const glm::vec2* vec2() const { return reinterpret_cast<const glm::vec2*>(data.data()); }
};
// Throws ValueError naming the argument and the expected shape.
Rows toRows(const py::handle& object, const char* name, int width);

// The row count of arguments broadcast together (null entries are absent arguments): a single row
// takes any count, N rows need N. Throws ValueError naming the arguments for differing counts.
struct NamedRows {
  const Rows* rows;
  const char* name;
};
std::size_t broadcastRows(std::initializer_list<NamedRows> args);

// A float32 array of that shape, and the array as the caller's precision (float64 when asked).
FloatArray newFloatArray(const std::vector<py::ssize_t>& shape);
py::array inPrecision(FloatArray array, bool float64);

// A numpy array that owns `values` (moved into a capsule): no copy of the data.
py::array ownedFloatArray(std::vector<float>&& values, const std::vector<py::ssize_t>& shape);
py::array ownedRgbArray(std::vector<Rgb>&& values, std::vector<py::ssize_t> shape);

// A direction argument: a 3-vector, or a number = theta in degrees at phi = 0.
glm::vec3 toDirection(const py::handle& object, const char* name);

// An optional surface position (None: (0, 0)) for calls that take one uv.
glm::vec2 toUv(const py::handle& object);

// A path argument: str or os.PathLike.
std::string toPath(const py::handle& object);

}  // namespace btf::python
