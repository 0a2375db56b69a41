// Dataset compression in parts (compress/vq_dataset.h), the steps btf.dask sends to a cluster:
// each takes and returns plain values and byte strings, so that it runs in any worker process on
// any host and its result travels through the scheduler without a shared folder. Private to the
// package (names start with "_dataset_"); btf.dask is the interface.
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bindings.h"
#include "btf/compress/vq_dataset.h"
#include "btf/core/error.h"
#include "btf/io/btf_subset.h"
#include "btf/material/registry.h"

namespace btf::python {

namespace dataset_bindings {

// One material of a part: an input (path or spec) under a name, whole or one texel rectangle of it.
struct PartItem {
  std::string path, name;
  std::optional<BtfRect> rect;
};

std::shared_ptr<const BtfSource> openInput(const std::string& path) {
  IdentifiedMaterial material = identifyMaterial(path, {});
  std::shared_ptr<const BtfSource> source = materialBtf(material);
  if (std::dynamic_pointer_cast<const VqBtf>(source))
    throw FileError(path, "is already compressed (.btfz); compress the original, or join compressed files with btf.merge");
  return source;
}

std::vector<PartItem> itemsOf(const py::handle& items) {
  std::vector<PartItem> out;
  for (const auto& item : items) {
    const auto t = py::reinterpret_borrow<py::tuple>(item);
    if (t.size() != 3) throw py::value_error("a part item is (path, name, rect or None)");
    PartItem p{t[0].cast<std::string>(), t[1].cast<std::string>(), std::nullopt};
    if (!t[2].is_none()) {
      const auto r = t[2].cast<std::vector<int>>();
      if (r.size() != 4) throw py::value_error("a tile is (x, y, width, height)");
      p.rect = BtfRect{r[0], r[1], r[2], r[3]};
    }
    out.push_back(std::move(p));
  }
  if (out.empty()) throw py::value_error("a part needs at least one material");
  return out;
}

VqOptions optionsOf(const py::dict& d) {
  VqOptions o;
  o.epsilon = d["epsilon"].cast<float>();
  o.chroma_epsilon = d["chroma_epsilon"].cast<float>();
  o.energy_floor = d["energy_floor"].cast<float>();
  o.levels = d["levels"].cast<int>();
  o.level3_exceptions = d["level3_exceptions"].cast<bool>();
  o.threads = d["threads"].cast<int>();
  return o;
}

py::bytes bytesOf(const std::vector<std::byte>& b) { return py::bytes(reinterpret_cast<const char*>(b.data()), b.size()); }
std::span<const std::byte> spanOf(const std::string& s) { return {reinterpret_cast<const std::byte*>(s.data()), s.size()}; }

// The sources of a part, opened (tiles as views of their input, opened once per input).
struct OpenedPart {
  std::vector<std::shared_ptr<const BtfSource>> inputs;
  std::vector<std::unique_ptr<BtfSubset>> tiles;
  std::vector<const BtfSource*> sources;
  std::vector<std::string> names;
};
void openPart(const std::vector<PartItem>& items, OpenedPart& part) {
  std::string last_path;
  for (const PartItem& item : items) {
    if (part.inputs.empty() || item.path != last_path) part.inputs.push_back(openInput(item.path));
    last_path = item.path;
    const BtfSource& input = *part.inputs.back();
    if (item.rect) {
      part.tiles.push_back(std::make_unique<BtfSubset>(input, *item.rect, input.views()));
      part.sources.push_back(part.tiles.back().get());
    } else {
      part.sources.push_back(&input);
    }
    part.names.push_back(item.name);
  }
}

py::dict describeInput(const std::string& path) {
  std::shared_ptr<const BtfSource> s;
  std::string description;
  {
    py::gil_scoped_release release;
    IdentifiedMaterial material = identifyMaterial(path, {});
    description = material.description;
    s = materialBtf(material);
  }
  if (std::dynamic_pointer_cast<const VqBtf>(s))
    throw FileError(path, "is already compressed (.btfz); compress the original, or join compressed files with btf.merge");
  py::dict d;
  d["path"] = path;
  d["name"] = s->name();
  d["description"] = description;
  d["width"] = s->width();
  d["height"] = s->height();
  d["views"] = s->views().count();
  d["values"] = double(s->entryCount());
  return d;
}

py::bytes mapPart(const py::handle& items_in, const py::dict& options_in) {
  const std::vector<PartItem> items = itemsOf(items_in);
  const VqOptions options = optionsOf(options_in);
  std::vector<std::byte> out;
  {
    py::gil_scoped_release release;
    OpenedPart part;
    openPart(items, part);
    out = VqCodebooks::of(compressVqDatabase(part.sources, part.names, options)).toBytes();
  }
  return bytesOf(out);
}

py::bytes mergeCodebooks(const std::vector<std::string>& parts_in, const std::vector<std::string>& labels) {
  std::vector<std::byte> out;
  {
    py::gil_scoped_release release;
    std::vector<VqCodebooks> parts;
    for (std::size_t i = 0; i < parts_in.size(); ++i)
      parts.push_back(VqCodebooks::fromBytes(spanOf(parts_in[i]), i < labels.size() ? labels[i] : "part " + std::to_string(i + 1)));
    out = mergeVqCodebooks(parts, labels).toBytes();
  }
  return bytesOf(out);
}

py::bytes recodePart(const py::handle& items_in, const py::dict& options_in, const std::string& seed_bytes) {
  const std::vector<PartItem> items = itemsOf(items_in);
  const VqOptions options = optionsOf(options_in);
  std::vector<std::byte> out;
  {
    py::gil_scoped_release release;
    const VqCodebooks seed = VqCodebooks::fromBytes(spanOf(seed_bytes), "the merged codebooks");
    OpenedPart part;
    openPart(items, part);
    VqDatabase db = compressVqDatabase(part.sources, part.names, options, seed);
    out = vqDatabaseBytes(db);
  }
  return bytesOf(out);
}

// The join: the re-coded parts merged (and, with `tiled`, the tiles joined into one material),
// written atomically to `out`.
py::dict joinParts(const std::vector<std::string>& parts_in, const std::vector<std::string>& labels, const std::string& out,
                   const py::object& tiled) {
  std::optional<std::vector<BtfRect>> rects;
  std::string tiled_name;
  int width = 0, height = 0;
  if (!tiled.is_none()) {
    const auto d = tiled.cast<py::dict>();
    tiled_name = d["name"].cast<std::string>();
    width = d["width"].cast<int>();
    height = d["height"].cast<int>();
    rects.emplace();
    for (const auto& r : d["rects"]) {
      const auto v = r.cast<std::vector<int>>();
      rects->push_back({v.at(0), v.at(1), v.at(2), v.at(3)});
    }
  }
  py::dict report;
  std::vector<std::string> names;
  std::vector<std::size_t> shared;
  std::uint64_t bytes = 0;
  double raw = 0;
  {
    py::gil_scoped_release release;
    std::vector<VqDatabase> parts;
    for (std::size_t i = 0; i < parts_in.size(); ++i)
      parts.push_back(vqDatabaseFromBytes(spanOf(parts_in[i]), i < labels.size() ? labels[i] : "part " + std::to_string(i + 1)));
    VqDatabase merged = mergeVqDatabases(parts, labels);
    VqDatabase db = rects ? joinVqTiles(merged, *rects, width, height, tiled_name) : std::move(merged);
    db.write(out);
    names = db.names();
    shared = db.sharedEntries();
    bytes = db.compressedBytes();
    raw = db.rawBytesU8();
  }
  report["output"] = out;
  report["materials"] = names;
  report["shared_entries"] = shared;
  report["bytes"] = bytes;
  report["ratio_u8"] = bytes ? raw / double(bytes) : 0.0;
  return report;
}

// Per material of the written database: rel_rmse (RGB, as `btf compare`), the luminance rel_rmse and
// its bound (vq_btf.h), against its input.
py::list materialErrors(const std::string& path, const std::vector<std::pair<std::string, std::string>>& inputs) {
  py::list out;
  for (const auto& [name, input] : inputs) {
    double rel = 0, lum = 0, bound = 0;
    {
      py::gil_scoped_release release;
      const VqBtf m = VqBtf::read(path, name);
      const std::shared_ptr<const BtfSource> reference = openInput(input);
      const BtfErrorStats error = compareBtf(*reference, m);
      rel = error.rel_rmse;
      lum = error.luminance_rel_rmse;
      bound = vqLuminanceBound(m.options());
    }
    py::dict d;
    d["name"] = name;
    d["input"] = input;
    d["rel_rmse"] = rel;
    d["luminance_rel_rmse"] = lum;
    d["luminance_bound"] = bound;
    out.append(d);
  }
  return out;
}

}  // namespace dataset_bindings

void bindDataset(py::module_& m) {
  using namespace dataset_bindings;
  m.def("_dataset_describe", &describeInput, py::arg("path"),
        "Opens an input as compression would (btf.Error / FileError naming it): name, size, views.");
  m.def("_dataset_tiles", [](int width, int height, int parts) {
    std::vector<std::vector<int>> out;
    for (const BtfRect& r : vqTiles(width, height, parts)) out.push_back({r.x, r.y, r.width, r.height});
    return out;
  });
  m.def("_dataset_map", &mapPart, py::arg("items"), py::arg("options"),
        "Map: compresses a part's materials alone; returns their shared codebooks as bytes.");
  m.def("_dataset_merge_codebooks", &mergeCodebooks, py::arg("parts"), py::arg("labels"),
        "Reduce: the parts' codebooks merged within the tolerance, as bytes.");
  m.def("_dataset_recode", &recodePart, py::arg("items"), py::arg("options"), py::arg("seed"),
        "Re-code: the part compressed from the merged codebooks; returns its database as bytes.");
  m.def("_dataset_join", &joinParts, py::arg("parts"), py::arg("labels"), py::arg("out"), py::arg("tiled") = py::none(),
        "Join: the re-coded parts merged losslessly (tiles into one material) and written atomically.");
  m.def("_dataset_errors", &materialErrors, py::arg("path"), py::arg("inputs"),
        "Per material (name, input): rel_rmse, luminance_rel_rmse and its bound.");
  m.def("_dataset_codebook_entries", [](const std::string& bytes) {
    return VqCodebooks::fromBytes(spanOf(bytes)).entries();
  });
}

}  // namespace btf::python
