// Running the toolkit's own programs from a benchmark, and the memory a process has used: what a
// bench needs to measure a verb as a user runs it (its own process, its own peak memory).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace btf::tools {

// A string single-quoted for the shell.
std::string shellQuote(const std::string& text);

// The program `name` in the folder of the running executable (btf and btf-datagen are built and
// installed side by side). Throws btf::Error when it is not there.
std::filesystem::path programBeside(const std::string& name);

// The peak resident memory of this process so far, in bytes (getrusage's ru_maxrss).
std::uint64_t peakMemoryBytes();

// Runs `argv` (argv[0] a path), its stdout discarded and stderr passed through. Throws btf::Error
// naming the command when it exits non-zero.
void runCommand(const std::vector<std::string>& argv);

// Runs `argv` (argv[0] a path) with stdout captured and stderr passed through (its progress bars and
// error messages stay on the terminal), and parses stdout as JSON. Throws btf::Error naming the
// command when it exits non-zero or prints no JSON.
nlohmann::json runJsonCommand(const std::vector<std::string>& argv);

}  // namespace btf::tools
