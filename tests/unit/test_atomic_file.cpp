// Atomic writes: a failure never leaves a half-written output or a stray temporary file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "btf/core/error.h"
#include "btf/io/atomic_file.h"
#include "support/test_support.h"

namespace btf {
namespace {
namespace fs = std::filesystem;

std::vector<std::string> filesIn(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename().string());
  return names;
}

std::string contents(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeText(const fs::path& path, const std::string& text) {
  writeFileAtomically(path, [&](std::ofstream& out) { out << text; });
}

// Expects `call` to throw FileError whose message names `path`; returns the message.
template <typename Call>
std::string expectFileErrorNaming(const fs::path& path, Call call) {
  try {
    call();
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no FileError for " << path;
  return {};
}

TEST(AtomicFile, SuccessfulWriteLeavesOnlyTheFile) {
  test::TempDir dir;
  writeText(dir / "out.txt", "complete");
  EXPECT_EQ(contents(dir / "out.txt"), "complete");
  EXPECT_EQ(filesIn(dir.path()), std::vector<std::string>{"out.txt"});
}

TEST(AtomicFile, FailingWriterLeavesNoFileAndNoTemporary) {
  test::TempDir dir;
  EXPECT_THROW(writeFileAtomically(dir / "out.bin",
                                   [](std::ofstream& out) {
                                     out << "half of the data";
                                     throw std::runtime_error("writer failed midway");
                                   }),
               std::runtime_error);
  EXPECT_TRUE(filesIn(dir.path()).empty());
}

TEST(AtomicFile, PreviousFileSurvivesAFailedOverwrite) {
  test::TempDir dir;
  writeText(dir / "out.txt", "previous version");
  EXPECT_THROW(writeFileAtomically(dir / "out.txt",
                                   [](std::ofstream& out) {
                                     out << "new but incomplete";
                                     throw std::runtime_error("writer failed midway");
                                   }),
               std::runtime_error);
  EXPECT_EQ(contents(dir / "out.txt"), "previous version");
  EXPECT_EQ(filesIn(dir.path()), std::vector<std::string>{"out.txt"});
}

TEST(AtomicFile, FailingPathWriterLeavesNoTemporary) {
  test::TempDir dir;
  EXPECT_THROW(writeViaTemporaryPath(dir / "image.exr",
                                     [](const fs::path& temporary) {
                                       std::ofstream(temporary) << "partial";
                                       throw std::runtime_error("encoder failed");
                                     }),
               std::runtime_error);
  EXPECT_TRUE(filesIn(dir.path()).empty());
}

TEST(AtomicFile, MissingFolderGivesFileErrorNamingThePath) {
  test::TempDir dir;
  const fs::path target = dir / "no-such-folder" / "out.txt";
  const std::string message = expectFileErrorNaming(target, [&] { writeText(target, "x"); });
  EXPECT_NE(message.find("does not exist"), std::string::npos) << message;
  EXPECT_TRUE(filesIn(dir.path()).empty());
}

TEST(AtomicFile, DirectoryAsDestinationGivesFileErrorNamingThePath) {
  test::TempDir dir;
  fs::create_directory(dir / "a-folder");
  const std::string message = expectFileErrorNaming(dir / "a-folder", [&] { writeText(dir / "a-folder", "x"); });
  EXPECT_NE(message.find("directory"), std::string::npos) << message;
  EXPECT_TRUE(fs::is_directory(dir / "a-folder"));
  EXPECT_TRUE(filesIn(dir / "a-folder").empty());
}

TEST(AtomicFile, RequireReadableFileRejectsMissingFilesAndDirectories) {
  test::TempDir dir;
  EXPECT_NE(expectFileErrorNaming(dir / "missing", [&] { requireReadableFile(dir / "missing"); }).find("no such file"),
            std::string::npos);
  EXPECT_NE(expectFileErrorNaming(dir.path(), [&] { requireReadableFile(dir.path()); }).find("directory"),
            std::string::npos);
  writeText(dir / "present.txt", "x");
  EXPECT_NO_THROW(requireReadableFile(dir / "present.txt"));
}

}  // namespace
}  // namespace btf
