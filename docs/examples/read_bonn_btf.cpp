// Read a Bonn .btf file (UBO2014 layout): here one written first from a small in-memory BTF on the
// Bonn dome's 151 x 151 directions, factorised as the database ships its files (DFMF, log-Y U/Y
// V/Y, half factors); then its header without decoding, and one view as linear RGB through the
// registry, which finds the format by the file's signature. Exit code 0 on success.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <vector>

#include <btf/core/btf_direction_set.h>
#include <btf/core/error.h>
#include <btf/io/bonn_btf.h>
#include <btf/io/btf_data.h>
#include <btf/material/ggx.h>
#include <btf/material/registry.h>

int main() try {
  // 4 x 4 texels of a GGX, measured on the dome's directions.
  const auto dome = btf::BtfDirectionSet::uboDome1();
  const btf::Ggx ggx(btf::Rgb(0.5f, 0.3f, 0.1f), btf::Rgb(0.04f), 0.3f, 0.3f);
  btf::BtfData data(4, 4, "ggx", btf::BtfViewSet::all(dome));
  for (int v = 0; v < dome->viewCount(); ++v)
    for (int l = 0; l < dome->lightCount(v); ++l)
      for (int t = 0; t < 16; ++t) data.at(t % 4, t / 4, v, l) = ggx.eval(dome->lightDirections(v)[l], dome->view(v));
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "libbtf-example.btf";
  const btf::BonnBtfWriteReport written = btf::writeBonnBtf(data, file);  // DFMF, 64 components at most

  // What `btf info` shows: headers and factor sizes, nothing decoded.
  const btf::BonnBtfHeader header = btf::readBonnBtfHeader(file);
  std::printf("%s: %s, %s, %d x %d texels, colour model %d (%s), %llu bytes\n", file.filename().c_str(),
              header.signature.c_str(), header.directions->describe().c_str(), header.width, header.height,
              header.color_model, btf::bonnColorModelName(header.color_model).c_str(),
              static_cast<unsigned long long>(header.file_bytes));

  // One view, every light and texel, as linear RGB: out[(light * height + y) * width + x].
  const std::shared_ptr<const btf::BtfSource> btf = btf::openBtf(file.string());
  std::vector<btf::Rgb> view;
  const int v = 40;
  btf->loadView(v, view);
  const btf::Rgb measured = view[std::size_t(7) * 16];  // light 7, texel (0, 0)
  const btf::Rgb truth = ggx.eval(dome->lightDirections(v)[7], dome->view(v));
  std::printf("view %d (%s), light 7: %.4f %.4f %.4f (the GGX: %.4f %.4f %.4f; %u components kept)\n", v,
              dome->describeView(v).c_str(), measured.r, measured.g, measured.b, truth.r, truth.g, truth.b,
              written.components[0]);
  std::printf("whole file against the data: rel_rmse %.2g\n", btf::compareBtf(data, *btf).rel_rmse);
  std::filesystem::remove(file);
  return std::abs(measured.r - truth.r) < 0.02f * truth.r + 1e-3f ? 0 : 1;
} catch (const btf::Error& e) {
  std::fprintf(stderr, "error: %s\n", e.what());
  return 1;
}
