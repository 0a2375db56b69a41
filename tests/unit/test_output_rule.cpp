// Nothing non-finite or partial leaves libbtf: the writers refuse non-finite values, an interrupted
// write removes its temporary, and the temporaries of an interrupted run are cleaned up by the next.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <OpenImageIO/imageio.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <vector>

#include "btf/core/error.h"
#include "btf/io/atomic_file.h"
#include "btf/io/image.h"
#include "btf/io/merl.h"
#include "support/test_support.h"

namespace btf {
namespace {
namespace fs = std::filesystem;
using testing::HasSubstr;

TEST(OutputRule, ImageWritersRefuseNonFiniteValues) {
  test::TempDir dir;
  Image image(4, 3, 3, 0.5f);
  image.at(2, 1, 1) = std::numeric_limits<float>::infinity();
  for (const char* name : {"a.exr", "a.png"}) {
    try {
      writeImage(dir / name, image);
      FAIL() << name << " was written";
    } catch (const FileError& e) {
      EXPECT_THAT(e.what(), HasSubstr("pixel (2, 1) channel 1 is inf"));
    }
    EXPECT_TRUE(fs::is_empty(dir.path())) << "a partial file was left";
  }
  std::vector<StackLayer> layers(1);
  layers[0].name = "part";
  layers[0].image = image;
  EXPECT_THROW(writeImageStack(dir / "s.exr", layers), FileError);
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(OutputRule, ExrHeadersCarryNoCaptureTime) {
  test::TempDir dir;
  writeImage(dir / "a.exr", Image(2, 2, 3, 0.25f));
  auto in = OIIO::ImageInput::open((dir / "a.exr").string());
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().get_string_attribute("DateTime"), "");
}

TEST(OutputRule, ImageFormatIsReadFromTheContent) {
  test::TempDir dir;
  writeImage(dir / "a.png", Image(2, 2, 3, 0.25f));
  fs::rename(dir / "a.png", dir / "a.exr");
  EXPECT_EQ(imageFileFormat(dir / "a.exr"), "png");
  writeImage(dir / "b.exr", Image(2, 2, 3, 0.25f));
  EXPECT_EQ(imageFileFormat(dir / "b.exr"), "openexr");
  std::ofstream(dir / "c.exr") << "text";
  EXPECT_EQ(imageFileFormat(dir / "c.exr"), "");
}

// The MERL range error prints the value itself, not a rounding of it to the limit.
TEST(OutputRule, MerlRangeErrorPrintsTheValueInFull) {
  test::TempDir dir;
  const fs::path file = dir / "t.binary";
  {
    std::ofstream out(file, std::ios::binary);
    const std::int32_t dims[3] = {90, 90, 180};
    out.write(reinterpret_cast<const char*>(dims), sizeof dims);
    std::vector<double> values(3 * MerlTable::kEntriesPerChannel, 0.1);
    values[7] = 1.0000001e20;
    out.write(reinterpret_cast<const char*>(values.data()), std::streamsize(values.size() * sizeof(double)));
  }
  const std::string message = test::errorOf([&] { readMerl(file); });
  EXPECT_THAT(message, HasSubstr("value 1.0000001"));
  EXPECT_THAT(message, HasSubstr("<= 1e+20"));
}

// SIGINT while a temporary is registered removes it, and the process ends as SIGINT ends it.
TEST(OutputRule, AnInterruptedWriteLeavesNoTemporary) {
  test::TempDir dir;
  const fs::path file = dir / ".o.tmp1-0.btfz", folder = dir / ".f.tmp1-0";
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    removeTemporariesOnSignals();
    std::ofstream(file) << "partial";
    fs::create_directory(folder);
    std::ofstream(folder / "image.exr") << "partial";
    const TemporaryGuard file_guard(file, false), folder_guard(folder, true);
    ::raise(SIGINT);
    ::_exit(0);  // not reached
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGINT);
  EXPECT_FALSE(fs::exists(file));
  EXPECT_FALSE(fs::exists(folder));
}

// A temporary of a process that is gone is removed by the next write of the same output; one of a
// living process (here, this one's parent) is left alone.
TEST(OutputRule, StaleTemporariesAreRemovedByTheNextWrite) {
  test::TempDir dir;
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) ::_exit(0);
  ASSERT_EQ(::waitpid(child, nullptr, 0), child);  // a pid that no longer runs
  const fs::path stale = dir / (".o.tmp" + std::to_string(child) + "-0.btfz");
  const fs::path living = dir / (".o.tmp" + std::to_string(::getppid()) + "-0.btfz");
  const fs::path other = dir / ".other.tmp1-0.btfz";
  for (const fs::path& p : {stale, living, other}) std::ofstream(p) << "partial";
  writeFileAtomically(dir / "o.btfz", [](std::ofstream& out) { out << "whole"; });
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(living));
  EXPECT_TRUE(fs::exists(other));
  EXPECT_TRUE(fs::exists(dir / "o.btfz"));
}

}  // namespace
}  // namespace btf
