// A program outside the project that uses the installed libbtf through find_package.
#include <btf/core/half_diff.h>
#include <btf/core/math.h>

#include <cmath>
#include <cstdio>

int main() {
  const glm::vec3 wi = btf::sphericalDirection(0.4f, 1.0f);
  const glm::vec3 wo = btf::sphericalDirection(0.9f, 3.0f);
  const btf::DirectionPair back = btf::fromHalfDiff(btf::toHalfDiff(wi, wo));
  const float error = glm::length(back.wi - wi) + glm::length(back.wo - wo);
  std::printf("downstream half/diff round trip error %g\n", error);
  return error < 1e-4f ? 0 : 1;
}
