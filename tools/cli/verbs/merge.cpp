// `btf merge A.btfz B.btfz ... -o DB.btfz`: files compressed apart joined into one database.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "btf/compress/vq_database.h"
#include "btf/core/error.h"
#include "commands.h"

namespace btf::cli {
namespace {

void runMerge(const std::vector<std::string>& in, const std::string& out) {
  if (std::filesystem::path(out).extension() != ".btfz") throw FileError(out, "the output must end in .btfz");
  std::vector<VqDatabase> parts;
  std::uint64_t in_bytes = 0;
  for (const std::string& path : in) {
    if (std::filesystem::path(path).extension() != ".btfz") throw FileError(path, "is not a .btfz file");
    parts.push_back(VqDatabase::read(path));
    in_bytes += std::filesystem::file_size(path);
  }
  VqDatabase merged = mergeVqDatabases(parts, in);
  merged.write(out);
  const std::uint64_t bytes = std::filesystem::file_size(out);
  std::printf("wrote %s: %zu materials from %zu files, %llu bytes (the inputs: %llu, factor %.2f)\n", out.c_str(),
              merged.size(), in.size(), static_cast<unsigned long long>(bytes), static_cast<unsigned long long>(in_bytes),
              double(in_bytes) / double(bytes));
  std::printf("shared codebook entries (level 1, level 2):");
  for (std::size_t n : merged.sharedEntries()) std::printf(" %zu", n);
  std::printf("\n");
}

}  // namespace

void registerMergeCommand(CLI::App& app) {
  auto parts = std::make_shared<std::vector<std::string>>();
  auto merged = std::make_shared<std::string>();
  auto* merge = app.add_subcommand(
      "merge", "Join .btfz files (single materials or databases, compressed with the same options, e.g. on different "
               "machines) into one database; lossless: each distinct codebook entry is stored once");
  merge->add_option("IN", *parts, "Input .btfz files")->required()->expected(1, -1)->check(CLI::ExistingFile);
  merge->add_option("-o,--output", *merged, "Output .btfz database, written atomically")->required();
  merge->callback([parts, merged] { runMerge(*parts, *merged); });
}

}  // namespace btf::cli
