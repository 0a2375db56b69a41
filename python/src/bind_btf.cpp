// BTFs from Python: btf.BtfSource (views streamed one at a time into numpy arrays, without a copy),
// btf.open_btf, and VQ compression with its reports: btf.compress, btf.decompress, btf.merge,
// btf.compare. The reports carry the fields and names of the `btf` verbs' --json output.
#include <charconv>
#include <chrono>
#include <cstdlib>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "bindings.h"
#include "btf/compress/compressed_btf.h"
#include "btf/compress/vq_btf.h"
#include "btf/compress/vq_database.h"
#include "btf/core/error.h"
#include "btf/io/btf_images.h"
#include "btf/io/btf_quality.h"
#include "btf/material/registry.h"

namespace btf::python {
namespace {

// A BTF input of compress and compare: a BtfSource object, or a path or spec the registry opens as
// a BTF (a BRDF as a one-texel BTF).
struct BtfArgument {
  std::string label;        // the path, or the source's name
  std::string description;  // the format's words, as the verbs print them
  std::shared_ptr<const BtfSource> source;
};

BtfArgument btfArgumentOf(const py::handle& object, const std::string& database_material = {}) {
  if (py::isinstance<PyBtfSource>(object)) {
    const auto& s = object.cast<const PyBtfSource&>();
    return {s.source->name(), "BtfSource", s.source};
  }
  const std::string path = toPath(object);
  OpenOptions options;
  options.database_material = database_material;
  py::gil_scoped_release release;
  IdentifiedMaterial material = identifyMaterial(path, options);
  std::string description = material.description;
  if (!isBtfType(*material.type)) description += " as a one-texel BTF at 81 x 81 directions";
  return {path, description, materialBtf(material)};
}

std::vector<py::object> argumentList(const py::handle& object) {
  std::vector<py::object> list;
  if (py::isinstance<py::str>(object) || py::hasattr(object, "__fspath__") || py::isinstance<PyBtfSource>(object))
    list.push_back(py::reinterpret_borrow<py::object>(object));
  else
    for (const auto& item : object) list.push_back(py::reinterpret_borrow<py::object>(item));
  if (list.empty()) throw py::value_error("inputs: expected at least one BTF (a path, spec or BtfSource)");
  return list;
}

// JSON has no infinity; neither does this report (psnr_db of equal data): "inf", as the verbs write.
py::object measure(double v) {
  if (std::isfinite(v)) return py::float_(v);
  if (std::isnan(v)) return py::str("nan");
  return py::str(v > 0 ? "inf" : "-inf");
}

// A float option as the number written (0.05, not 0.0500000007: the float's shortest form).
double optionValue(float value) {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, value).ptr;
  return std::strtod(std::string(text, end).c_str(), nullptr);
}

void addQuality(const BtfSource& reference, const BtfSource& test, py::dict& report) {
  BtfQuality q;
  {
    py::gil_scoped_release release;
    q = compareBtfQuality(reference, test);
  }
  report["rel_rmse"] = measure(q.error.rel_rmse);
  report["psnr_db"] = measure(q.error.psnr_db);
  report["rel_rmse_display"] = measure(q.ssim.rel_rmse_display);
  report["mean_ssim"] = q.ssim.mean_ssim;
  report["min_image_ssim"] = q.ssim.min_image_ssim;
  report["ssim_white"] = q.ssim.white;
  report["noise_rel_rmse"] = q.noise.rel_rmse;
  report["rel_rmse_over_noise"] = q.noise.rel_rmse > 0 ? q.error.rel_rmse / q.noise.rel_rmse : 0.0;
}

std::string checkedBtfzOutput(const py::handle& out) {
  const std::string path = toPath(out);
  if (std::filesystem::path(path).extension() != ".btfz") throw FileError(path, "the output must end in .btfz");
  return path;
}

py::dict compressInputs(const py::handle& inputs_in, const py::handle& out_in, float epsilon, float chroma_epsilon,
                        float energy_floor, int levels, bool level1_cut, bool level3_exceptions, int threads,
                        bool verify, bool compare_alone) {
  const std::string out = checkedBtfzOutput(out_in);
  std::vector<BtfArgument> inputs;
  for (const py::object& item : argumentList(inputs_in)) {
    inputs.push_back(btfArgumentOf(item));
    if (std::dynamic_pointer_cast<const VqBtf>(inputs.back().source))
      throw FileError(inputs.back().label, "is already compressed (.btfz); decompress it first, compress the original, "
                                           "or join compressed files with btf.merge");
  }
  VqOptions vq;
  vq.epsilon = epsilon;
  vq.chroma_epsilon = chroma_epsilon;
  vq.energy_floor = energy_floor;
  vq.levels = levels;
  vq.level1_cut = level1_cut;
  vq.level3_exceptions = level3_exceptions;
  vq.threads = threads;
  py::dict report;
  report["output"] = out;
  report["epsilon"] = optionValue(vq.epsilon);
  report["chroma_epsilon"] = optionValue(vq.chroma_epsilon);
  report["energy_floor"] = optionValue(vq.energy_floor);
  report["level1_cut"] = vq.level1_cut;
  report["level3_exceptions"] = vq.level3_exceptions;
  report["levels"] = vq.levels;

  if (inputs.size() == 1) {
    if (compare_alone) throw Error("compare_alone needs several inputs (it compares their database with each compressed alone)");
    const BtfSource& source = *inputs.front().source;
    std::optional<VqBtf> compressed;
    double seconds = 0;
    {
      py::gil_scoped_release release;
      const auto start = std::chrono::steady_clock::now();
      compressed.emplace(compressVq(source, vq));
      seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      compressed->write(out);
    }
    const std::uint64_t bytes = std::filesystem::file_size(out);
    report["input"] = inputs.front().label;
    report["input_kind"] = inputs.front().description;
    report["texels"] = py::make_tuple(source.width(), source.height());
    report["views"] = source.views().views();
    report["codebook_entries"] = compressed->stats().codebook_entries;
    report["bytes"] = bytes;
    report["ratio_u8"] = double(source.entryCount()) * 3.0 / double(bytes);
    report["ratio_f32"] = double(source.entryCount()) * 12.0 / double(bytes);
    report["compression_s"] = seconds;
    if (verify) {
      std::optional<VqBtf> reread;
      {
        py::gil_scoped_release release;
        reread.emplace(VqBtf::read(out));
      }
      addQuality(source, *reread, report);
    }
    return report;
  }

  // Several inputs: one database with shared codebooks (compress/vq_database.h).
  std::vector<const BtfSource*> sources;
  std::vector<std::string> names;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    sources.push_back(inputs[i].source.get());
    names.push_back(inputs[i].source->name());
    for (std::size_t j = 0; j < i; ++j)
      if (names[j] == names[i])
        throw Error("inputs " + inputs[j].label + " and " + inputs[i].label + " are both named '" + names[i] +
                    "': a database needs distinct material names");
  }
  std::optional<VqDatabase> database, reread;
  {
    py::gil_scoped_release release;
    database.emplace(compressVqDatabase(sources, names, vq));
    database->write(out);
    if (verify) reread.emplace(VqDatabase::read(out));
  }
  const std::uint64_t bytes = std::filesystem::file_size(out);
  report["shared_codebook_entries"] = database->sharedEntries();
  report["bytes"] = bytes;
  report["ratio_u8"] = database->rawBytesU8() / double(bytes);
  report["compression_s"] = database->seconds();
  const VqDatabase& stored = verify ? *reread : *database;
  py::list materials;
  std::uint64_t alone_total = 0;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const VqBtf& m = stored.materials()[i];
    py::dict entry;
    entry["name"] = names[i];
    entry["input"] = inputs[i].label;
    entry["input_kind"] = inputs[i].description;
    entry["texels"] = py::make_tuple(m.width(), m.height());
    entry["views"] = m.views().views();
    entry["codebook_entries"] = m.stats().codebook_entries;
    if (verify) addQuality(*sources[i], m, entry);
    if (compare_alone) {
      std::uint64_t alone = 0;
      {
        py::gil_scoped_release release;
        alone = compressVq(*sources[i], vq).stats().compressed_bytes;
      }
      entry["alone_bytes"] = alone;
      alone_total += alone;
    }
    materials.append(entry);
  }
  report["materials"] = materials;
  if (compare_alone) {
    report["alone_bytes"] = alone_total;
    report["saving"] = double(alone_total) / double(bytes);
  }
  return report;
}

PyBtfSource decompressFile(const py::handle& path_in, const py::handle& out_in, const std::string& material,
                           const std::string& format) {
  const std::string path = toPath(path_in);
  if (std::filesystem::path(path).extension() != ".btfz") throw FileError(path, "is not a .btfz file");
  BtfImageWriteOptions options;
  if (format == "exr") options.format = BtfImageFormat::Exr;
  else if (format == "png16") options.format = BtfImageFormat::Png16;
  else if (format == "png8") options.format = BtfImageFormat::Png8;
  else throw py::value_error("format: expected 'exr', 'png16' or 'png8', got '" + format + "'");
  const std::string out = out_in.is_none() ? std::string() : toPath(out_in);
  py::gil_scoped_release release;
  const std::shared_ptr<const BtfSource> source = readCompressedBtf(path, material);
  if (!out.empty()) writeBtfImageFolder(*source, out, options);
  return PyBtfSource{source};
}

py::dict mergeFiles(const py::handle& inputs_in, const py::handle& out_in) {
  const std::string out = checkedBtfzOutput(out_in);
  std::vector<std::string> paths;
  for (const py::object& item : argumentList(inputs_in)) paths.push_back(toPath(item));
  std::vector<VqDatabase> parts;
  std::uint64_t in_bytes = 0;
  std::optional<VqDatabase> merged;
  {
    py::gil_scoped_release release;
    for (const std::string& path : paths) {
      if (std::filesystem::path(path).extension() != ".btfz") throw FileError(path, "is not a .btfz file");
      parts.push_back(VqDatabase::read(path));
      in_bytes += std::filesystem::file_size(path);
    }
    merged.emplace(mergeVqDatabases(parts, paths));
    merged->write(out);
  }
  const std::uint64_t bytes = std::filesystem::file_size(out);
  py::dict report;
  report["output"] = out;
  report["inputs"] = paths;
  report["materials"] = merged->names();
  report["bytes"] = bytes;
  report["input_bytes"] = in_bytes;
  report["shared_codebook_entries"] = merged->sharedEntries();
  return report;
}

py::dict compareBtfs(const py::handle& test_in, const py::handle& reference_in, const std::string& material) {
  auto open = [&](const py::handle& object) {
    const bool database = !py::isinstance<PyBtfSource>(object) &&
                          std::filesystem::path(toPath(object)).extension() == ".btfz";
    return btfArgumentOf(object, database ? material : std::string());
  };
  const BtfArgument test = open(test_in), reference = open(reference_in);
  py::dict report;
  report["test"] = test.label;
  report["reference"] = reference.label;
  report["texels"] = py::make_tuple(reference.source->width(), reference.source->height());
  report["views"] = reference.source->views().views();
  addQuality(*reference.source, *test.source, report);
  report.attr("pop")("rel_rmse_over_noise");
  return report;
}

py::array viewDirections(const BtfSource& s) {
  const BtfDirectionSet& set = s.directions();
  FloatArray out = newFloatArray({py::ssize_t(set.viewCount()), 3});
  glm::vec3* p = reinterpret_cast<glm::vec3*>(out.mutable_data());
  for (int v = 0; v < set.viewCount(); ++v) p[v] = set.view(v);
  return out;
}

py::array lightDirections(const BtfSource& s, int view) {
  const BtfDirectionSet& set = s.directions();
  if (view < 0 || view >= set.viewCount())
    throw py::index_error("view " + std::to_string(view) + " is outside the direction set (0 .. " +
                          std::to_string(set.viewCount() - 1) + ")");
  const std::span<const glm::vec3> lights = set.lightDirections(view);
  FloatArray out = newFloatArray({py::ssize_t(lights.size()), 3});
  std::copy(lights.begin(), lights.end(), reinterpret_cast<glm::vec3*>(out.mutable_data()));
  return out;
}

py::array loadView(const PyBtfSource& self, int view) {
  const BtfSource& s = *self.source;
  if (view < 0 || view >= s.directions().viewCount())
    throw py::index_error("view " + std::to_string(view) + " is outside the direction set (0 .. " +
                          std::to_string(s.directions().viewCount() - 1) + ")");
  s.views().require(view, s.name());
  std::vector<Rgb> values;
  {
    py::gil_scoped_release release;
    s.loadView(view, values);
  }
  const py::ssize_t lights = s.directions().lightCount(view);
  return ownedRgbArray(std::move(values), {lights, py::ssize_t(s.height()), py::ssize_t(s.width())});
}

}  // namespace

void bindBtf(py::module_& m) {
  py::class_<PyBtfSource>(m, "BtfSource", R"doc(A BTF: RGB reflectance (1/sr) over texels x (view, light) direction pairs, read one
view at a time (a BTF larger than memory is never whole in memory).

Open one with btf.open_btf(path) (an image folder, a Bonn .btf, a .btfz, or a BRDF as a
one-texel BTF) or btf.decompress(path).
  width, height        texels
  views                the view indices held (all of the set's unless the data is partial)
  view_directions      (V, 3) every view direction of the set, indexed by view
  light_directions(v)  (L, 3) the light directions of view v
  load_view(v)         (L, height, width, 3) float32: the view's values, light-major)doc")
      .def_property_readonly("width", [](const PyBtfSource& s) { return s.source->width(); })
      .def_property_readonly("height", [](const PyBtfSource& s) { return s.source->height(); })
      .def_property_readonly("name", [](const PyBtfSource& s) { return s.source->name(); })
      .def_property_readonly("views", [](const PyBtfSource& s) { return s.source->views().views(); },
                             "The view indices the BTF holds, ascending.")
      .def_property_readonly("direction_set", [](const PyBtfSource& s) { return s.source->directions().name(); },
                             "The name of the direction set (e.g. the 81-direction UBO2003 set).")
      .def_property_readonly("view_directions", [](const PyBtfSource& s) { return viewDirections(*s.source); },
                             "(V, 3) float32: every view direction of the set (local frame, +z the normal).")
      .def("light_directions", [](const PyBtfSource& s, int view) { return lightDirections(*s.source, view); },
           py::arg("view"), "light_directions(view) -> (L, 3) float32: the light directions of that view, in order.")
      .def_property_readonly("white", [](const PyBtfSource& s) { return s.source->white(); },
                             "The value the encoding saturates at (an 8- or 16-bit folder's largest code), or None.")
      .def_property_readonly("entry_count", [](const PyBtfSource& s) { return s.source->entryCount(); },
                             "RGB entries of the held views: texels x (view, light) pairs.")
      .def("load_view", &loadView, py::arg("view"),
           R"doc(load_view(view) -> array (lights, height, width, 3) float32

The view's values, light-major, in the set's light order: out[light, y, x] is the RGB
reflectance of texel (x, y). The array owns the library's buffer (no copy).
Raises btf.Error for a view the BTF does not hold, IndexError outside the set.)doc")
      .def("__repr__", [](const PyBtfSource& s) {
        return "<btf.BtfSource " + s.source->name() + ": " + std::to_string(s.source->width()) + " x " +
               std::to_string(s.source->height()) + " texels, " + s.source->views().describe() + ">";
      });

  m.def(
      "open_btf",
      [](const py::handle& path, const std::string& material) {
        const std::string p = toPath(path);
        OpenOptions options;
        options.database_material = material;
        py::gil_scoped_release release;
        return PyBtfSource{openBtf(p, options)};
      },
      py::arg("path_or_spec"), py::arg("material") = "",
      R"doc(open_btf(path_or_spec, material='') -> BtfSource

The data as a BTF: an image folder, a Bonn .btf, a .btfz (`material` picks one of a
database), or any BRDF path or spec as a one-texel BTF at the 81 x 81 directions.)doc");

  m.def("compress", &compressInputs, py::arg("inputs"), py::arg("out"), py::arg("epsilon") = 0.02f,
        py::arg("chroma_epsilon") = 0.01f, py::arg("energy_floor") = 1.0f, py::arg("levels") = 3,
        py::arg("level1_cut") = false, py::arg("level3_exceptions") = true, py::arg("threads") = 0,
        py::arg("verify") = true, py::arg("compare_alone") = false,
        R"doc(compress(inputs, out, epsilon=0.02, chroma_epsilon=0.01, energy_floor=1.0, levels=3,
         level1_cut=False, level3_exceptions=True, threads=0, verify=True,
         compare_alone=False) -> dict

Multi-level vector quantization into a .btfz file, as `btf compress`. `inputs` is one
BTF or a list (a path, a spec, or a BtfSource; a BRDF becomes a one-texel BTF); several
make one database whose codebooks they share.
  epsilon            relative L2 tolerance per level (0: near-lossless)
  chroma_epsilon     absolute tolerance of the chromaticity per light (>= 0.001)
  energy_floor       absolute floor of the tolerance, in RMS norms of a vector's batch
  levels             1 (1D functions), 2 (+ light slices), 3 (+ texels)
  level1_cut         code level-1 entries in a principal basis, cut to what the
                     tolerance needs (smaller on noisy measured data)
  level3_exceptions  let texels take a nearly matching level-3 entry with own codes
  threads            0: all cores; the output does not depend on it
  verify             decode the written file and report its errors against the input
  compare_alone      several inputs: also compress each alone (alone_bytes, saving)
Returns the report of `btf compress --json`: bytes, ratio_u8, ratio_f32, codebook_entries,
compression_s, and with verify rel_rmse, psnr_db, rel_rmse_display, mean_ssim,
min_image_ssim, noise_rel_rmse; a database's per material under "materials".)doc");

  m.def("decompress", &decompressFile, py::arg("path"), py::arg("out") = py::none(), py::arg("material") = "",
        py::arg("format") = "exr",
        R"doc(decompress(path, out=None, material='', format='exr') -> BtfSource

Reads a .btfz (`material` picks one of a database) as a BtfSource that decodes on
demand; with `out`, also writes it as an image folder there (format 'exr', 'png16' or
'png8'), as `btf decompress`.)doc");

  m.def("merge", &mergeFiles, py::arg("inputs"), py::arg("out"),
        R"doc(merge(inputs, out) -> dict

Joins .btfz files (single materials or databases compressed with the same options) into
one database, losslessly, as `btf merge`. Returns output, materials, bytes, input_bytes
and shared_codebook_entries.)doc");

  m.def("compare", &compareBtfs, py::arg("test"), py::arg("reference"), py::arg("material") = "",
        R"doc(compare(test, reference, material='') -> dict

How far BTF `test` is from BTF `reference` over the reference's views, as `btf compare
--json`: rel_rmse, psnr_db, rel_rmse_display, mean_ssim, min_image_ssim, ssim_white,
noise_rel_rmse (the reference's noise floor). Each argument is a path, a spec or a
BtfSource; `material` picks one of a .btfz database.)doc");
}

}  // namespace btf::python
