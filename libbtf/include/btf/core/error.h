// Errors raised by libbtf. Messages are complete sentences for the user: `<file>: <problem>`.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

namespace btf {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A problem with a file's existence or contents; what() reads "<path>: <problem>".
class FileError : public Error {
 public:
  FileError(const std::filesystem::path& path, const std::string& problem)
      : Error(path.string() + ": " + problem), path_(path), problem_(problem) {}
  const std::filesystem::path& path() const { return path_; }
  const std::string& problem() const { return problem_; }

 private:
  std::filesystem::path path_;
  std::string problem_;
};

}  // namespace btf
