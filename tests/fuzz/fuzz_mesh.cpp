// Meshes of scenes: loadTriangleMeshes (OBJ through tinyobjloader, PLY by libbtf). The first
// byte picks the format by the file's extension (even: .obj, odd: .ply); the rest is the file.
#include "btf/render/triangle_mesh.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const auto path = btf::fuzz::writeInput({data + 1, size - 1}, data[0] % 2 == 0 ? "input.obj" : "input.ply");
  btf::fuzz::acceptingFileErrors([&] { (void)btf::render::loadTriangleMeshes(path); });
  return 0;
}
