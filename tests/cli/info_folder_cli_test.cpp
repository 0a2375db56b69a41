// `btf info` on an image-folder BTF checks btf.json and every image's header: a mutation probe
// found it exiting 0 on an empty EXR, a 10-byte one, one replaced by "{}" and a
// btf.json whose width was 2^63, true or "nan".
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>

#include "btf/io/btf_images.h"
#include "cli_test_support.h"

namespace btf::test {
namespace {
namespace fs = std::filesystem;
using testing::HasSubstr;

TEST(InfoFolder, EveryImageHeaderAndTheSidecarAreChecked) {
  TempDir dir;
  const fs::path folder = dir.path() / "btf";
  ASSERT_EQ(runDatagen({"btf", "--pattern", "fabric", "--size", "2", "--format", "exr", "-o", folder.string()})
                .exit_code,
            0);
  const CommandResult good = runBtf({"info", folder.string()});
  ASSERT_EQ(good.exit_code, 0) << good.output;
  EXPECT_THAT(good.output, HasSubstr("every image's header"));
  // The size limit of every image reader, set on the command line (2 x 2 = 4 pixels > 3).
  const CommandResult limited = runBtf({"--max-image-pixels", "3", "info", folder.string()});
  EXPECT_EQ(limited.exit_code, 1) << limited.output;
  EXPECT_THAT(limited.output, HasSubstr("beyond the limit of 3 pixels"));

  const fs::path image = folder / btfImageName(0, 57, BtfImageFormat::Exr);
  const std::string bytes = readBytes(image);
  for (const std::string& bad : {std::string(), bytes.substr(0, 10), std::string("{}")}) {
    std::ofstream(image, std::ios::binary | std::ios::trunc) << bad;
    const CommandResult r = runBtf({"info", folder.string()});
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_THAT(r.output, HasSubstr(image.string())) << bad.size() << " bytes";
  }
  std::ofstream(image, std::ios::binary | std::ios::trunc) << bytes;

  const fs::path sidecar = folder / kBtfSidecarName;
  for (const char* width : {"9223372036854775808", "true", "\"nan\""}) {
    std::ofstream(sidecar, std::ios::trunc) << R"({"width": )" << width << "}";
    const CommandResult r = runBtf({"info", folder.string()});
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_THAT(r.output, HasSubstr(sidecar.string())) << width;
    EXPECT_THAT(r.output, HasSubstr("width must be a whole number")) << width;
  }
}

}  // namespace
}  // namespace btf::test
