// Read a real measured material, an RGL database file (Dupuy & Jakob 2018, `.bsdf`), and use it
// as any Material: evaluate it, draw from its own warp, and estimate its albedo. The file comes
// from the shared data folder (BTF_SHARED_DATA_DIR, set by CMake, or the environment variable of
// the same name); when it is absent the example exits with code 77, which ctest counts as skipped.
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include <btf/core/error.h>
#include <btf/core/math.h>
#include <btf/material/albedo.h>
#include <btf/material/rgl_brdf.h>

#ifndef BTF_SHARED_DATA_DIR
#define BTF_SHARED_DATA_DIR "../shared/data/real"
#endif

int main() try {
  const char* env = std::getenv("BTF_SHARED_DATA_DIR");
  const std::filesystem::path file =
      std::filesystem::path(env ? env : BTF_SHARED_DATA_DIR) / "rgl_bsdf" / "paper_white_rgb.bsdf";
  if (!std::filesystem::is_regular_file(file)) {
    std::printf("skipped: %s not found\n", file.c_str());
    return 77;
  }
  const btf::RglBrdf paper(file);  // every field, dtype and bound checked
  std::printf("%s\n", paper.name().c_str());

  const glm::vec3 wo = btf::sphericalDirection(30 * btf::kPi / 180, 0);
  const glm::vec3 wi = btf::sphericalDirection(45 * btf::kPi / 180, 2.0f);
  const btf::Rgb f = paper.eval(wi, wo);
  std::printf("f(theta_i 45, theta_o 30) = %.4f %.4f %.4f 1/sr\n", f.r, f.g, f.b);

  // sample() draws wi from the file's own luminance and VNDF warps; its pdf equals pdf() exactly.
  if (auto s = paper.sample(wo, {}, {0.3f, 0.7f})) {
    std::printf("a draw: wi = (%.3f, %.3f, %.3f), pdf %.4f (pdf() says %.4f)\n", s->wi.x, s->wi.y, s->wi.z, s->pdf,
                paper.pdf(s->wi, wo));
    if (s->pdf != paper.pdf(s->wi, wo)) return 1;
  }
  const btf::AlbedoEstimate albedo = btf::estimateAlbedo(paper, wo, 20000, /*seed=*/1);
  std::printf("albedo at theta_o 30: %.3f %.3f %.3f (+- %.3f)\n", albedo.value.r, albedo.value.g, albedo.value.b,
              albedo.standard_error.g);
  return 0;
} catch (const btf::Error& e) {
  std::fprintf(stderr, "read_rgl: %s\n", e.what());
  return 1;
}
