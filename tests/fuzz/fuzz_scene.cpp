// Scene files: loadSceneDescription (`btf render`), in a folder that also holds a small OBJ quad
// for the scene to name, then the Embree scene built from what loaded and rendered tiny: every
// material value, light and pixel of what loads is finite (exerciseScene).
#include "btf/render/scene.h"
#include "btf/render/scene_loader.h"
#include "fuzz_support.h"

namespace {

std::filesystem::path makeFolder() {
  const auto folder = btf::fuzz::emptyFolder("scene");
  const char quad[] = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n";
  btf::fuzz::writeFile(folder / "quad.obj", {reinterpret_cast<const std::uint8_t*>(quad), sizeof quad - 1});
  return folder;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path folder = makeFolder();
  const auto file = folder / "scene.json";
  btf::fuzz::writeFile(file, {data, size});
  btf::fuzz::acceptingFileErrors([&] { btf::fuzz::exerciseScene(btf::render::loadSceneDescription(file)); });
  return 0;
}
