// Compress a BTF: fill a small in-memory BTF (8 x 8 texels, 81 views x 81 lights) from two
// analytic materials in a checkerboard, compress it by multi-level vector quantization into a
// .btfz file, read the file back, measure its error, and evaluate it as a Material.
// Runs on data it makes itself; exit code 0 on success.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <vector>

#include <btf/compress/vq_btf.h>
#include <btf/core/btf_directions.h>
#include <btf/core/error.h>
#include <btf/io/btf_data.h>
#include <btf/material/btf_material.h>
#include <btf/material/ggx.h>

int main() try {
  const btf::Ggx red(btf::Rgb(0.6f, 0.1f, 0.1f), btf::Rgb(0.04f), 0.25f, 0.25f);
  const btf::Ggx gold(btf::Rgb(0.0f), btf::Rgb(0.9f, 0.6f, 0.2f), 0.35f, 0.35f);

  // A BTF is RGB apparent BRDF over texels x 81 views x 81 lights (the Bonn direction set).
  btf::BtfData data(8, 8, "checker");
  const auto& dirs = btf::btfDirections();
  for (int view = 0; view < btf::kBtfDirectionCount; ++view)
    for (int light = 0; light < btf::kBtfDirectionCount; ++light)
      for (int y = 0; y < data.height(); ++y)
        for (int x = 0; x < data.width(); ++x) {
          const btf::Ggx& m = ((x / 2 + y / 2) % 2 == 0) ? red : gold;
          data.at(x, y, view, light) = m.eval(dirs[light].w, dirs[view].w);
        }

  // Multi-level VQ: each level reuses a codebook entry when it fits within epsilon.
  btf::VqOptions options;
  options.epsilon = 0.02f;
  const btf::VqBtf compressed = btf::compressVq(data, options);
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "libbtf_example_checker.btfz";
  compressed.write(file);  // checksummed sections, written atomically

  const auto decoded = std::make_shared<const btf::VqBtf>(btf::VqBtf::read(file));
  std::printf("%s: %lld bytes on disk, ratio_u8 %.1f\n", file.filename().c_str(),
              static_cast<long long>(std::filesystem::file_size(file)), decoded->stats().ratio_u8);
  std::filesystem::remove(file);

  // How far the decoded BTF is from the data (BtfSource streams one view at a time).
  const btf::BtfErrorStats error = btf::compareBtf(data, *decoded);
  std::printf("rel_rmse %.4f, psnr_db %.1f over %zu entries\n", error.rel_rmse, error.psnr_db, error.entries);

  // Random access to one (texel, view, light) and the BTF as a Material for a renderer.
  const btf::Rgb v = decoded->value(3, 4, 10, 20);
  const btf::BtfMaterial material(decoded);
  const glm::vec3 wi = dirs[20].w, wo = dirs[10].w;
  const btf::Rgb f = material.eval(wi, wo, {0.5f, 0.5f});
  std::printf("value(3, 4, view 10, light 20) = %.4f %.4f %.4f; eval at uv (0.5, 0.5) = %.4f %.4f %.4f\n", v.r, v.g,
              v.b, f.r, f.g, f.b);
  return error.rel_rmse < 0.05 ? 0 : 1;
} catch (const btf::Error& e) {
  std::fprintf(stderr, "compress_btf: %s\n", e.what());
  return 1;
}
