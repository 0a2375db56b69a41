// A program outside the project that uses the installed libbtf through find_package: the public
// headers, and an image written and read back, which needs the image backend that libbtf loads
// from beside itself (libbtf/src/io/image_backend.h) to be installed there too.
#include <btf/core/half_diff.h>
#include <btf/core/math.h>
#include <btf/io/image.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

int main(int argc, char** argv) {
  const glm::vec3 wi = btf::sphericalDirection(0.4f, 1.0f);
  const glm::vec3 wo = btf::sphericalDirection(0.9f, 3.0f);
  const btf::DirectionPair back = btf::fromHalfDiff(btf::toHalfDiff(wi, wo));
  const float error = glm::length(back.wi - wi) + glm::length(back.wo - wo);
  std::printf("downstream half/diff round trip error %g\n", error);

  // The folder to write in: the first argument (the test's scratch folder).
  const std::filesystem::path file = std::filesystem::path(argc > 1 ? argv[1] : ".") / "downstream-image.exr";
  btf::writeImage(file, btf::Image(3, 2, 3, 0.25f));
  const btf::Image image = btf::readImage(file);
  const bool image_ok = image.width == 3 && image.height == 2 && image.channels == 3 && image.at(2, 1, 2) == 0.25f;
  std::printf("downstream EXR round trip %s\n", image_ok ? "exact" : "wrong");
  return error < 1e-4f && image_ok ? 0 : 1;
}
