// Write any isotropic material as an RGL measured material (`.bsdf`) that pbrt-v4's and Mitsuba 3's
// `measured` materials read, by virtual acquisition (the measurement pipeline of Dupuy & Jakob 2018
// run against the material), then read it back, through its RGB and its spectral channels, and
// measure what the conversion lost.
#include <cstdint>
#include <cstdio>
#include <filesystem>

#include <btf/core/error.h>
#include <btf/io/rgl_tensor.h>
#include <btf/material/ggx.h>
#include <btf/material/material_difference.h>
#include <btf/material/rgl_acquisition.h>
#include <btf/material/rgl_brdf.h>

int main() try {
  // A copper-coloured GGX conductor over a weak diffuse term; any btf::Material will do.
  const btf::Ggx copper(btf::Rgb(0.05f, 0.04f, 0.02f), btf::Rgb(0.95f, 0.64f, 0.54f), 0.2f, 0.2f);

  btf::RglAcquisitionOptions options;  // the RGL database's resolutions: 8 x 32 x 32, VNDF 128 x 128
  options.description = "GGX copper, alpha 0.2";
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "libbtf-example-copper.bsdf";
  btf::writeTensorFile(file, btf::acquireRglFields(copper, options));  // atomically

  const btf::RglBrdf written(file);
  const btf::MaterialDifference d = btf::compareMaterials(written, copper);
  std::printf("%s: %ju bytes, rel_rmse of f cos %.4f, largest albedo error %.2f%%\n", file.c_str(),
              static_cast<std::uintmax_t>(std::filesystem::file_size(file)), d.fcos_rel_rmse,
              100.0 * d.max_albedo_rel_error);
  // What a spectral renderer sees: the `spectra` field integrated against CIE 1931 under D65.
  const btf::RglBrdf spectral(file, btf::RglChannels::Spectra);
  const btf::MaterialDifference s = btf::compareMaterials(spectral, copper);
  std::printf("spectral channels: largest albedo error %.2f%%\n", 100.0 * s.max_albedo_rel_error);
  std::filesystem::remove(file);
  return d.fcos_rel_rmse < 0.05 && d.max_albedo_rel_error < 0.02 && s.max_albedo_rel_error < 0.02 ? 0 : 1;
} catch (const btf::Error& e) {
  std::fprintf(stderr, "write_rgl: %s\n", e.what());
  return 1;
}
