// Writes the seed corpora of the fuzz targets (tests/fuzz/corpus/<target>/): small valid files of
// every kind, made by libbtf's own writers at reduced sizes where the format allows, plus the
// bad-input cases of the command-line tests. Nothing third-party. Built with the fuzz targets;
// run by `tools/fuzz/run.sh --make-corpus`.
//   make_corpus OUT_FOLDER
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "btf/compress/octree_table.h"
#include "btf/compress/factor_btf.h"
#include "btf/compress/vq_btf.h"
#include "btf/compress/vq_database.h"
#include "btf/core/btf_directions.h"
#include "btf/io/bonn_btf.h"
#include "btf/io/btf_data.h"
#include "btf/io/btf_images.h"
#include "btf/io/image.h"
#include "btf/io/rgl_tensor.h"
#include "btf/material/ggx.h"
#include "btf/material/lambert.h"
#include "btf/material/rgl_acquisition.h"

namespace fs = std::filesystem;
using Bytes = std::vector<std::uint8_t>;

namespace {

void put(const fs::path& path, const Bytes& bytes) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}
void put(const fs::path& path, const std::string& text) { put(path, Bytes(text.begin(), text.end())); }
Bytes bytesOf(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), {});
}
Bytes prefix(const Bytes& bytes, std::size_t n) { return Bytes(bytes.begin(), bytes.begin() + std::ptrdiff_t(std::min(n, bytes.size()))); }
template <class T>
void append(Bytes& out, T value) {
  const auto* p = reinterpret_cast<const std::uint8_t*>(&value);
  out.insert(out.end(), p, p + sizeof value);
}

// A smooth, coloured BTF: a diffuse term and a lobe around the mirror direction, varying per texel.
btf::BtfData makeBtf(int width, int height, btf::BtfViewSet views, const char* name) {
  btf::BtfData data(width, height, name, views);
  for (int view : data.views().views())
    for (int light = 0; light < btf::kBtfDirectionCount; ++light) {
      const btf::BtfDirection& v = btf::btfDirections()[std::size_t(view)];
      const btf::BtfDirection& l = btf::btfDirections()[std::size_t(light)];
      const glm::vec3 mirror(-l.w.x, -l.w.y, l.w.z);
      const float lobe = std::pow(std::max(0.0f, glm::dot(v.w, mirror)), 8.0f);
      for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
          const float t = 0.2f + 0.1f * float((x + 2 * y) % 3);
          data.at(x, y, view, light) = btf::Rgb(t + lobe, 0.8f * t + lobe, 0.5f * t + 0.5f * lobe);
        }
    }
  return data;
}

// MERL .binary: a valid table is 33 MB, too large for a seed; the header and the failures around it.
void merl(const fs::path& out) {
  Bytes header;
  for (std::int32_t d : {90, 90, 180}) append(header, d);
  put(out / "empty.binary", Bytes{});
  put(out / "header-only.binary", header);
  Bytes values = header;
  for (double v : {0.1, 0.2, -0.0, 1e-3, 7.5}) append(values, v);
  put(out / "truncated.binary", values);
  Bytes wrong;
  for (std::int32_t d : {180, 90, 90}) append(wrong, d);
  put(out / "wrong-dims.binary", wrong);
  put(out / "short-header.binary", prefix(header, 7));
}

// A tensor_file field of raw little-endian bytes (dtype codes: 1 u8, 10 f32), written by libbtf's
// encoder (btf/io/rgl_tensor.h).
btf::TensorField tensorSeedField(std::string name, btf::TensorDtype dtype, std::vector<std::uint64_t> shape,
                                 const Bytes& data) {
  btf::TensorField f;
  f.name = std::move(name);
  f.dtype = dtype;
  f.shape = std::move(shape);
  for (const std::uint8_t b : data) f.bytes.push_back(std::byte{b});
  return f;
}
Bytes tensorFile(const std::vector<btf::TensorField>& fields) {
  Bytes out;
  for (const std::byte b : btf::encodeTensorFile(fields)) out.push_back(std::to_integer<std::uint8_t>(b));
  return out;
}
Bytes floats(std::size_t n, float base, float step) {
  Bytes b;
  for (std::size_t i = 0; i < n; ++i) append(b, base + step * float(i % 7));
  return b;
}

void rgl(const fs::path& out) {
  // A tiny isotropic RGB material: 2 incidence angles, 4 x 4 tables (the real files hold 32 x 32).
  const std::uint64_t nt = 2, r = 4;
  using D = btf::TensorDtype;
  std::vector<btf::TensorField> fields = {
      tensorSeedField("description", D::UInt8, {5}, Bytes{'s', 'e', 'e', 'd', 0}),
      tensorSeedField("jacobian", D::UInt8, {1}, Bytes{1}),
      tensorSeedField("phi_i", D::Float32, {1}, floats(1, 0.0f, 0.0f)),
      tensorSeedField("theta_i", D::Float32, {nt}, [] { Bytes b; append(b, 0.0f); append(b, 1.2f); return b; }()),
      tensorSeedField("ndf", D::Float32, {r, r}, floats(r * r, 0.5f, 0.1f)),
      tensorSeedField("sigma", D::Float32, {r, r}, floats(r * r, 1.0f, 0.05f)),
      tensorSeedField("vndf", D::Float32, {1, nt, r, r}, floats(nt * r * r, 0.2f, 0.1f)),
      tensorSeedField("luminance", D::Float32, {1, nt, r, r}, floats(nt * r * r, 0.3f, 0.05f)),
      tensorSeedField("rgb", D::Float32, {1, nt, 3, r, r}, floats(nt * 3 * r * r, 0.1f, 0.02f)),
  };
  const Bytes valid = tensorFile(fields);
  put(out / "tiny.bsdf", valid);
  put(out / "truncated.bsdf", prefix(valid, valid.size() - 40));
  put(out / "header-cut.bsdf", prefix(valid, 30));
  fields.pop_back();
  put(out / "missing-rgb.bsdf", tensorFile(fields));
  Bytes nan = valid;
  const float q = std::nanf("");
  std::memcpy(nan.data() + nan.size() - 8, &q, 4);
  put(out / "nan.bsdf", nan);
  // What `btf convert X out.bsdf` writes (virtual acquisition), at the smallest resolutions.
  btf::RglAcquisitionOptions small;
  small.theta_i_count = 3;
  small.resolution = 4;
  small.vndf_resolution = 8;
  small.ndf_resolution = 8;
  put(out / "written-ggx.bsdf",
      tensorFile(btf::acquireRglFields(btf::Ggx(btf::Rgb(0.1f), btf::Rgb(0.9f, 0.6f, 0.5f), 0.2f, 0.2f), small)));
  put(out / "written-lambert.bsdf", tensorFile(btf::acquireRglFields(btf::Lambert(btf::Rgb(0.7f)), small)));
  // A spectral file without `rgb` (as the database's *_spec.bsdf): the reader's spectra path.
  std::vector<btf::TensorField> spectral =
      btf::acquireRglFields(btf::Ggx(btf::Rgb(0.1f), btf::Rgb(0.9f, 0.6f, 0.5f), 0.2f, 0.2f), small);
  std::erase_if(spectral, [](const btf::TensorField& f) { return f.name == "rgb"; });
  put(out / "written-spectral.bsdf", tensorFile(spectral));
}

void btfz(const fs::path& out) {
  const fs::path scratch = out / "scratch.btfz";
  btf::VqOptions options;
  options.epsilon = 0.05f;
  btf::compressVq(makeBtf(2, 2, btf::BtfViewSet({0}), "pole"), options).write(scratch);
  const Bytes pole = bytesOf(scratch);
  put(out / "pole-2x2.btfz", pole);
  put(out / "truncated.btfz", prefix(pole, pole.size() / 2));
  put(out / "magic-only.btfz", prefix(pole, 8));
  options.epsilon = 0.2f;
  btf::compressVq(makeBtf(2, 1, btf::BtfViewSet::upToTheta(30.0f), "rings"), options).write(scratch);
  put(out / "rings-2x1.btfz", bytesOf(scratch));
  options.levels = 2;
  btf::compressVq(makeBtf(1, 2, btf::BtfViewSet({0}), "two-levels"), options).write(scratch);
  put(out / "two-levels.btfz", bytesOf(scratch));
  options.levels = 3;
  const btf::BtfData a = makeBtf(1, 1, btf::BtfViewSet({0}), "a"), b = makeBtf(2, 1, btf::BtfViewSet({0}), "b");
  const btf::BtfSource* sources[] = {&a, &b};
  btf::compressVqDatabase(sources, {"a", "b"}, options).write(scratch);
  put(out / "database.btfz", bytesOf(scratch));
  // A BTF on its own direction set (format version 4: the header's "directions" and "rings"),
  // with view-dependent lights: 2 views of 5 lights, one moved aside in view 1.
  {
    const std::vector<btf::BtfAngles> views = {{0, 0}, {40, 90}};
    std::vector<std::vector<btf::BtfAngles>> lights(2, {{0, 0}, {20, 0}, {20, 120}, {20, 240}, {60, 30}});
    lights[1][1] = {24, 10};
    const auto set = std::make_shared<const btf::BtfDirectionSet>("seed set", views, lights);
    btf::BtfData own(2, 1, "own-set", btf::BtfViewSet::all(set));
    for (int v = 0; v < 2; ++v)
      for (int l = 0; l < 5; ++l)
        for (int x = 0; x < 2; ++x) own.at(x, 0, v, l) = btf::Rgb(0.1f + 0.1f * float(l), 0.2f + 0.05f * float(x), 0.3f);
    btf::compressVq(own, options).write(scratch);
    put(out / "own-set-2x1.btfz", bytesOf(scratch));
  }
  // A texel that repeats the other but in one view (1.3 times as bright there): level 3 stores
  // it as a derived entry (compress/vq_impl.h), so the reader's exception sections are reached.
  btf::BtfData twins = makeBtf(2, 1, btf::BtfViewSet::upToTheta(30.0f), "twins");
  const int odd_view = twins.views().view(3);
  for (int view : twins.views().views())
    for (int light = 0; light < btf::kBtfDirectionCount; ++light) {
      btf::Rgb c = twins.at(0, 0, view, light);
      if (view == odd_view) c *= 1.3f;
      twins.at(1, 0, view, light) = c;
    }
  options.epsilon = 0.05f;
  btf::compressVq(twins, options).write(scratch);
  put(out / "derived-2x1.btfz", bytesOf(scratch));
  // 12 x 12 texels: enough lit vectors for ring 1's level-1 basis (vq_basis.h), so the reader's
  // basis and coefficient sections are reached.
  options.levels = 1;
  btf::compressVq(makeBtf(12, 12, btf::BtfViewSet({0}), "basis"), options).write(scratch);
  put(out / "basis-12x12.btfz", bytesOf(scratch));
  // The factor form in both colour models (compress/factor_btf.h).
  for (const btf::FactorColorModel model : {btf::FactorColorModel::Linear, btf::FactorColorModel::LogLuminance}) {
    btf::FactorOptions factor;
    factor.epsilon = 0.05f;
    factor.color_model = model;
    btf::compressFactor(makeBtf(3, 2, btf::BtfViewSet::upToTheta(30.0f), "factor"), factor).write(scratch);
    put(out / ("factor-" + btf::factorColorModelName(model) + "-3x2.btfz"), bytesOf(scratch));
  }
  fs::remove(scratch);
}

void btfJson(const fs::path& out) {
  put(out / "written.json", std::string(R"({"format": "png8", "width": 2, "height": 2, "value_scale": 1.5, "transfer": "srgb", "views": 1, "source": "fuzz"})"));
  put(out / "linear.json", std::string(R"({"value_scale": 2, "transfer": "linear"})"));
  put(out / "empty-object.json", std::string("{}"));
  put(out / "bad-transfer.json", std::string(R"({"transfer": "gamma"})"));
  put(out / "zero-scale.json", std::string(R"({"value_scale": 0})"));
  put(out / "not-json.json", std::string("value_scale = 1"));
  put(out / "image-name.json", std::string("tv030_pv060_tl045_pl120.png"));
  put(out / "image-name-frame.json", std::string("00012 TL015-pl060.tv000_pv000.exr"));
}

void btfImage(const fs::path& out) {
  const fs::path scratch = out / "scratch";
  btf::BtfData data = makeBtf(2, 2, btf::BtfViewSet({0}), "image");
  for (auto format : {btf::BtfImageFormat::Exr, btf::BtfImageFormat::Png8}) {
    btf::BtfImageWriteOptions options;
    options.format = format;
    btf::writeBtfImageFolder(data, scratch, options);
    const std::string name = btf::btfImageName(0, 0, format);
    const Bytes image = bytesOf(scratch / name);
    put(out / ("valid" + btf::btfImageExtension(format)), image);
    put(out / ("truncated" + btf::btfImageExtension(format)), prefix(image, image.size() * 2 / 3));
    fs::remove_all(scratch);
  }
  btf::Image wrong(3, 2, 3);  // another size than the folder's 2 x 2
  for (float& p : wrong.pixels) p = 0.25f;
  btf::writeImage(out / "scratch.exr", wrong);
  put(out / "other-size.exr", bytesOf(out / "scratch.exr"));
  btf::Image grey(2, 2, 1);
  btf::writeImage(out / "scratch.exr", grey);
  put(out / "one-channel.exr", bytesOf(out / "scratch.exr"));
  fs::remove(out / "scratch.exr");
}

void exrStack(const fs::path& out) {
  btf::Image image(3, 2, 3);
  for (std::size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = 0.1f * float(i % 5);
  std::vector<btf::StackLayer> layers = {{"red", {{"channel", 0}, {"scale", 1.5f}, {"note", std::string("seed")}}, image},
                                         {"green", {{"channel", 1}}, image}};
  btf::writeImageStack(out / "stack.exr", layers);
  btf::writeImage(out / "single.exr", image);
  const Bytes stack = bytesOf(out / "stack.exr");
  put(out / "stack-truncated.exr", prefix(stack, stack.size() - 20));
}

void scene(const fs::path& out) {
  put(out / "lambert-quad.json", std::string(R"({
  "camera": {"position": [0.5, 0.5, 2], "look_at": [0.5, 0.5, 0], "up": [0, 1, 0], "fov_deg": 40, "resolution": [16, 16]},
  "render": {"spp": 1, "max_depth": 3, "rr_min_depth": 2},
  "materials": {"white": {"type": "lambert", "albedo": [0.8, 0.8, 0.8], "sampler": "cosine"}},
  "shapes": [{"file": "quad.obj", "material": "white", "shading": "flat",
              "transform": {"scale": 2, "rotate": {"axis": [0, 1, 0], "deg": 30}, "translate": [0, -0.1, 0]}},
             {"type": "sphere", "center": [0.5, 0.5, 0.3], "radius": 0.2, "material": "white", "emission": [2, 2, 2]}],
  "lights": [{"type": "point", "position": [0, 0, 1], "intensity": [1, 1, 1]}]
})"));
  put(out / "analytic.json", std::string(R"({
  "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0]},
  "materials": {"g": {"type": "ggx", "alpha": [0.2, 0.1], "f0": [0.9, 0.9, 0.9], "diffuse": [0.1, 0.1, 0.1]},
                "w": {"type": "ward", "diffuse": [0.1, 0.1, 0.1], "alpha": 0.1, "specular": [0.2, 0.2, 0.2]}, "p": {"type": "phong", "diffuse": [0.3, 0.3, 0.3], "specular": [0.2, 0.2, 0.2], "exponent": 20},
                "l": {"type": "lafortune", "diffuse": [0.1, 0.1, 0.1], "lobes": [{"c": [-1, -1, 1], "exponent": 10, "rho": [0.5, 0.5, 0.5]}]}},
  "shapes": [{"type": "quad", "corner": [-1, -1, 0], "edge_u": [2, 0, 0], "edge_v": [0, 2, 0], "material": "g", "two_sided": true,
              "emission": [1, 1, 1]},
             {"type": "sphere", "center": [0, 0, 1], "radius": 0.3, "material": "l"}],
  "lights": [{"type": "environment", "radiance": [1, 1, 1]}]
})"));
  put(out / "empty.json", std::string("{}"));
  put(out / "missing-file.json", std::string(R"({"camera": {}, "materials": {"m": {"type": "merl", "file": "none.binary"}}, "shapes": []})"));
}

void mesh(const fs::path& out) {
  // First byte: even for .obj, odd for .ply (fuzz_mesh.cpp).
  const std::string obj(1, '\0'), ply(1, '\1');
  put(out / "quad.obj", obj + "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
                              "f 1/1/1 2/2/1 3/3/1 4/4/1\n");
  put(out / "degenerate.obj", obj + "v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1 2 3\nf 1 2 9\n");
  // Its own material library (fuzz_mesh writes the input as input.obj), so that mutations reach the
  // .mtl reader too; a pentagon for the triangulation, groups and a change of material.
  put(out / "materials.obj", obj + "mtllib input.obj\nnewmtl red\nKd 0.8 0.1 0.1\nnewmtl lamp\nKe 4 4 4\n"
                                   "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0.5 1.5 0\nv 0 1 0\no box\ng side\nusemtl red\n"
                                   "f 1 2 3 4 5\nusemtl lamp\nf -1 -2 -3\ng top\nf 1 3 5\n");
  put(out / "ascii.ply", ply + std::string("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                     "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                                     "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"));
  Bytes binary(1, 1);
  const std::string head = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                           "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  binary.insert(binary.end(), head.begin(), head.end());
  for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) append(binary, v);
  binary.push_back(3);
  for (std::int32_t i : {0, 1, 2}) append(binary, i);
  put(out / "binary.ply", binary);
}

// Octree tables of a few KB: a constant table (the root alone), one with a block of holes and a
// step (a small tree), and damaged copies.
void octree(const fs::path& out) {
  btf::MerlTable table;
  for (std::size_t c = 0; c < btf::MerlTable::kEntriesPerChannel; ++c)
    for (int ch = 0; ch < 3; ++ch) table.raw(ch, c) = 30.0 + ch;
  const fs::path scratch = out / "scratch.octree";
  btf::writeOctreeFile(scratch, btf::OctreeTable::build(table, 0.0));
  put(out / "constant.octree", bytesOf(scratch));
  for (int i = 0; i < btf::MerlTable::kThetaHalfRes; ++i)
    for (int j = 0; j < btf::MerlTable::kThetaDiffRes; ++j)
      for (int k = 0; k < btf::MerlTable::kPhiDiffRes; ++k) {
        const std::size_t c = btf::MerlTable::index(i, j, k);
        if (i >= 45 && j >= 45) table.setUnmeasured(c);  // boundaries at midpoints: a tree of a few nodes
        else if (i < 11) table.raw(1, c) = 900.0 + (k >= 90 ? 100 : 0) + (j == 7 ? 50 : 0);
      }
  btf::writeOctreeFile(scratch, btf::OctreeTable::build(table, 0.0));
  const Bytes step = bytesOf(scratch);
  put(out / "step-and-holes.octree", step);
  put(out / "truncated.octree", prefix(step, step.size() / 2));
  fs::remove(scratch);
}

// Fit files of each model, as `btf fit` writes them, and a damaged one.
void fit(const fs::path& out) {
  const std::string info = R"("fit": {"source": "plastic.binary", "rel_rmse": 0.1, "converged": true}})";
  put(out / "ggx.json", std::string(R"({"format": "libbtf-fit", "version": 1, "model": "ggx", "parameters": )"
                                    R"({"diffuse": [0.2, 0.1, 0.1], "f0": [0.04, 0.04, 0.04], "alpha": 0.1}, )") + info);
  put(out / "ward.json", std::string(R"({"format": "libbtf-fit", "version": 1, "model": "ward", "parameters": )"
                                     R"({"diffuse": [0.3, 0.3, 0.3], "specular": [0.1, 0.1, 0.1], "alpha": 0.2}, )") + info);
  const std::string lafortune = std::string(R"({"format": "libbtf-fit", "version": 1, "model": "lafortune", "parameters": )"
                                            R"({"diffuse": [0.3, 0.2, 0.1], "lobes": [{"rho": [0.5, 0.5, 0.5], )"
                                            R"("c": [-1, -1, 1], "exponent": 20}]}, )") + info;
  put(out / "ggx2.json", std::string(R"({"format": "libbtf-fit", "version": 1, "model": "ggx2", "parameters": )"
                                     R"({"diffuse": [0.2, 0.1, 0.1], "f0": [0.04, 0.04, 0.04], "alpha": 0.3, )"
                                     R"("f0_2": [0.9, 0.6, 0.5], "alpha_2": 0.02}, )") + info);
  put(out / "abc.json", std::string(R"({"format": "libbtf-fit", "version": 1, "model": "abc", "parameters": )"
                                    R"({"diffuse": [0.02, 0.02, 0.01], "a": [51.7, 37.9, 27.4], "b": 10482.1, "c": 0.8167, )"
                                    R"("ior": 2.2365}, )") + info);
  put(out / "sgd.json", std::string(R"({"format": "libbtf-fit", "version": 1, "model": "sgd", "parameters": )"
                                    R"({"diffuse": [0.05, 0.03, 0.02], "rho_s": [12.5, 7.25, 3.5], "alpha": 0.0123, "p": 0.459, )"
                                    R"("f0": 0.0605, "f1": -0.0155, "kap": 1, "lambda": 3.12, "c": 1.71e-05, "k": 25, "theta0": 0}, )") +
                            info);
  put(out / "lafortune.json", lafortune);
  put(out / "truncated.json", lafortune.substr(0, lafortune.size() / 2));
}

// Bonn .btf files of a tiny BTF on a scattered set of directions (one view with its own lights),
// one per layout as our writers make them, and a damaged copy.
void bonn(const fs::path& out) {
  const std::vector<btf::BtfAngles> views = {{0, 0}, {30, 90}};
  const std::vector<std::vector<btf::BtfAngles>> lights = {{{0, 0}, {45, 0}, {60, -90}}, {{0, 0}, {40, 10}, {60, -90}}};
  const auto set = std::make_shared<const btf::BtfDirectionSet>("fuzz", views, lights);
  btf::BtfData data(2, 2, "tiny", btf::BtfViewSet::all(set));
  for (int v = 0; v < 2; ++v)
    for (int l = 0; l < 3; ++l)
      for (int t = 0; t < 4; ++t) data.at(t % 2, t / 2, v, l) = btf::Rgb(0.1f + 0.1f * float(l), 0.2f * float(v + 1), 0.05f * float(t + 1));
  const fs::path scratch = out / "scratch.btf";
  btf::BonnBtfWriteOptions options;
  options.max_components = 2;
  btf::writeBonnBtf(data, scratch, options);
  const Bytes dfmf = bytesOf(scratch);
  put(out / "dfmf-log-yuv-half.btf", dfmf);
  put(out / "truncated.btf", prefix(dfmf, dfmf.size() / 2));
  options.layout = btf::BonnBtfLayout::Fmf;
  options.dynamic_range_reduction = 1;
  options.scalar_bytes = 4;
  btf::writeBonnBtf(data, scratch, options);
  put(out / "fmf-log-float.btf", bytesOf(scratch));
  btf::writeBonnBtfPvf(data, scratch, 2, 8);
  put(out / "pvf-double.btf", bytesOf(scratch));
  fs::remove(scratch);
}

// UTIA's list of shifted lights: the full list (each light moved 4 degrees up where it meets the
// camera), one with a row off the set, and a truncated one.
void utiaList(const fs::path& out) {
  std::string list = "# number theta phi theta_lS phi_lS\n";
  for (int k = 0; k < btf::kBtfDirectionCount; ++k) {
    const btf::BtfDirection& d = btf::btfDirections()[std::size_t(k)];
    char line[96];
    std::snprintf(line, sizeof line, "%d %g %g %g %g\n", k + 1, double(d.theta_deg), double(d.phi_deg),
                  double(d.theta_deg + 4.0f), double(d.phi_deg));
    list += line;
  }
  put(out / "shifted.txt", list);
  std::string off = list;
  off.replace(off.find("\n2 15 0"), 7, "\n2 16 0");
  put(out / "off-the-set.txt", off);
  put(out / "truncated.txt", list.substr(0, list.size() / 2));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_corpus OUT_FOLDER (writes OUT_FOLDER/<target>/...)\n");
    return 2;
  }
  const fs::path out = argv[1];
  for (const char* target : {"fuzz_merl", "fuzz_rgl", "fuzz_btfz", "fuzz_btf_json", "fuzz_btf_image", "fuzz_exr_stack",
                             "fuzz_scene", "fuzz_mesh", "fuzz_octree", "fuzz_fit", "fuzz_bonn_btf", "fuzz_utia_folder"})
    fs::create_directories(out / target);
  merl(out / "fuzz_merl");
  rgl(out / "fuzz_rgl");
  btfz(out / "fuzz_btfz");
  btfJson(out / "fuzz_btf_json");
  btfImage(out / "fuzz_btf_image");
  exrStack(out / "fuzz_exr_stack");
  scene(out / "fuzz_scene");
  mesh(out / "fuzz_mesh");
  octree(out / "fuzz_octree");
  fit(out / "fuzz_fit");
  bonn(out / "fuzz_bonn_btf");
  utiaList(out / "fuzz_utia_folder");
  return 0;
}
