// Evaluate a MERL-layout table: tabulate an analytic GGX into the MERL layout, write it as a
// `.binary`, read it back and look it up through TabulatedBrdf, beside the model it came from.
// Runs on data it makes itself; exit code 0 on success.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include <btf/core/error.h>
#include <btf/core/math.h>
#include <btf/io/merl.h>
#include <btf/material/ggx.h>
#include <btf/material/tabulated_brdf.h>

int main() try {
  // A red plastic: diffuse albedo, Schlick F0 and GGX roughness (isotropic: alpha_x == alpha_y).
  const btf::Ggx ggx(btf::Rgb(0.5f, 0.05f, 0.05f), btf::Rgb(0.04f), 0.3f, 0.3f);

  // Any isotropic Material into the MERL layout (90 x 90 x 180 cells), then to disk and back.
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "libbtf_example_ggx.binary";
  btf::writeMerl(file, btf::tabulate(ggx));
  auto table = std::make_shared<const btf::MerlTable>(btf::readMerl(file));
  std::filesystem::remove(file);

  const btf::TabulatedBrdf interpolated(table);  // trilinear lookup (the default)
  const btf::TabulatedBrdf nearest(table, btf::TableLookup::Nearest);

  // Directions live in the local shading frame: +z is the normal, theta from +z, phi from +x.
  const float deg = btf::kPi / 180.0f;
  const glm::vec3 wo = btf::sphericalDirection(30 * deg, 0);
  std::printf("theta_i  model.r   interpolated.r  nearest.r   (phi_i = 180 deg, theta_o = 30 deg)\n");
  float worst = 0;
  for (int theta_i = 0; theta_i <= 60; theta_i += 15) {
    const glm::vec3 wi = btf::sphericalDirection(float(theta_i) * deg, btf::kPi);
    const btf::Rgb f = ggx.eval(wi, wo), fi = interpolated.eval(wi, wo), fn = nearest.eval(wi, wo);
    std::printf("%7d  %7.4f   %14.4f  %9.4f\n", theta_i, f.r, fi.r, fn.r);
    worst = std::max(worst, std::abs(fi.r - f.r) / f.r);
  }
  std::printf("largest relative difference of the interpolated lookup: %.3f\n", worst);
  return worst < 0.1f ? 0 : 1;
} catch (const btf::Error& e) {  // every libbtf failure names the file and the problem
  std::fprintf(stderr, "eval_merl: %s\n", e.what());
  return 1;
}
