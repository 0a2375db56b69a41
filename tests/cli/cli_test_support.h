// Helpers of the command-line tests: run the real `btf` and `btf-datagen`, parse their JSON.
#pragma once

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "support/test_support.h"

namespace btf::test {

inline CommandResult runBtf(const std::vector<std::string>& args) { return runCommand(BTF_CLI_PATH, args); }
inline CommandResult runDatagen(const std::vector<std::string>& args) { return runCommand(BTF_DATAGEN_PATH, args); }

// The JSON document in a command's output (stdout and stderr are merged; warnings may precede it).
// A clean failure: a non-zero exit that is no crash, with a message holding each of `parts` (the
// input's name, the problem).
inline void expectFailure(const CommandResult& r, const std::vector<std::string>& parts) {
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_LT(r.exit_code, 128) << "crashed: " << r.output;
  for (const std::string& part : parts) EXPECT_THAT(r.output, testing::HasSubstr(part));
}

inline nlohmann::json parseJsonOutput(const CommandResult& result) {
  const std::size_t start = result.output.find_first_of("{[");
  if (start == std::string::npos) throw std::runtime_error("no JSON in output: " + result.output);
  return nlohmann::json::parse(result.output.substr(start));
}

inline std::string readBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A small scene for `btf render`: a floor quad of `material` under a square light, 16 x 16 pixels.
inline nlohmann::json floorScene(const nlohmann::json& material) {
  nlohmann::json scene = nlohmann::json::parse(R"({
    "camera": {"position": [0, 1.2, 2.5], "look_at": [0, 0, 0], "fov_deg": 50, "resolution": [16, 16]},
    "render": {"spp": 4, "max_depth": 4},
    "shapes": [
      {"type": "quad", "corner": [-1, 0, -1], "edge_u": [0, 0, 2], "edge_v": [2, 0, 0], "material": "floor"},
      {"type": "quad", "corner": [-0.3, 1, -0.3], "edge_u": [0.6, 0, 0], "edge_v": [0, 0, 0.6], "emission": [4, 4, 4]}
    ]
  })");
  scene["materials"]["floor"] = material;
  return scene;
}

inline std::vector<std::filesystem::path> filesIn(const std::filesystem::path& folder) {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) files.push_back(entry.path());
  return files;
}

}  // namespace btf::test
