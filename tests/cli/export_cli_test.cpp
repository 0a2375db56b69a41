// `btf export --runtime`: the runtime file of a .btfz (compress/vq_runtime_export.h; the runtime's
// agreement with the library is tests/unit/test_runtime.cpp), and bad inputs failing clearly
// without leaving an output behind.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "cli_test_support.h"

namespace btf::test {
namespace {
using testing::HasSubstr;
namespace fs = std::filesystem;

TEST(ExportCli, WritesTheRuntimeFileOfABtfz) {
  TempDir dir;
  const fs::path folder = dir / "stones", packed = dir / "stones.btfz", out = dir / "stones.btfrt";
  ASSERT_EQ(runDatagen({"btf", "--pattern", "stones", "--size", "4", "--format", "exr", "-o", folder.string()}).exit_code, 0);
  ASSERT_EQ(runBtf({"compress", folder.string(), packed.string()}).exit_code, 0);
  const CommandResult e = runBtf({"export", "--runtime", packed.string(), out.string()});
  ASSERT_EQ(e.exit_code, 0) << e.output;
  std::ifstream in(out, std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  EXPECT_EQ(std::memcmp(magic, "BTFRT\0\r\n", 8), 0);
}

TEST(ExportCli, BadInputsFailNamingTheFileAndWriteNothing) {
  TempDir dir;
  const fs::path out = dir / "out.btfrt";
  const CommandResult missing = runBtf({"export", "--runtime", (dir / "missing.btfz").string(), out.string()});
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_THAT(missing.output, HasSubstr("missing.btfz"));
  std::ofstream(dir / "junk.btfz") << "not a container";
  const CommandResult junk = runBtf({"export", "--runtime", (dir / "junk.btfz").string(), out.string()});
  EXPECT_NE(junk.exit_code, 0);
  EXPECT_THAT(junk.output, HasSubstr("junk.btfz"));
  // A dome BTF: the runtime evaluates the 81-direction set only.
  const fs::path dome = dir / "dome.btf", dome_packed = dir / "dome.btfz";
  ASSERT_EQ(runDatagen({"btf", "--pattern", "stones", "--size", "4", "--directions", "dome", "--layout", "dfmf", "-o",
                        dome.string()}).exit_code, 0);
  ASSERT_EQ(runBtf({"compress", dome.string(), dome_packed.string()}).exit_code, 0);
  const CommandResult d = runBtf({"export", "--runtime", dome_packed.string(), out.string()});
  EXPECT_NE(d.exit_code, 0);
  EXPECT_THAT(d.output, HasSubstr("81-direction set only"));
  const CommandResult no_flag = runBtf({"export", dome_packed.string(), out.string()});
  EXPECT_NE(no_flag.exit_code, 0);
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace btf::test
