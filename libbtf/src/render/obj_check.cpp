#include "obj_check.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <string>
#include <vector>

#include "btf/core/error.h"

namespace btf::render {
namespace {

// The whitespace-separated words of one line (tinyobjloader splits on spaces and tabs).
std::vector<std::string_view> wordsOf(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
  return words;
}

// The file's lines, ended by "\n", "\r\n" or a lone "\r" (tinyobjloader's safeGetline).
std::vector<std::string_view> linesOf(std::string_view text) {
  std::vector<std::string_view> lines;
  std::size_t pos = 0;
  while (pos < text.size()) {
    const std::size_t eol = std::min(text.find_first_of("\r\n", pos), text.size());
    lines.push_back(text.substr(pos, eol - pos));
    pos = eol + 1;
    if (eol < text.size() && text[eol] == '\r' && pos < text.size() && text[pos] == '\n') ++pos;
  }
  return lines;
}

// 'text', quoted for a message (appended, not prepended: GCC 12 warns falsely on "'" + string).
std::string quoted(std::string_view text) {
  std::string q(1, '\'');
  q.append(text);
  q += '\'';
  return q;
}

// A finite decimal number, whole (tinyobjloader reads what it cannot parse as 0, silently).
bool isFiniteNumber(std::string_view word) {
  const std::string_view digits = !word.empty() && word[0] == '+' ? word.substr(1) : word;  // from_chars takes no '+'
  double value = 0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  return !digits.empty() && ec == std::errc() && end == digits.data() + digits.size() && std::isfinite(value);
}

constexpr std::array<std::string_view, 3> kLists = {"v", "vt", "vn"};
// The numbers an entry of each list takes: v x y z [w] or x y z r g b; vt u v [w]; vn x y z.
constexpr std::array<std::array<std::size_t, 3>, 3> kComponents = {{{3, 4, 6}, {2, 3, 3}, {3, 3, 3}}};
constexpr std::array<std::string_view, 5> kOtherStatementsRead = {"f", "g", "o", "usemtl", "mtllib"};

}  // namespace

std::string checkedObjStatements(const std::filesystem::path& path, std::string_view text) {
  const std::vector<std::string_view> lines = linesOf(text);
  // First pass: control characters, the entries of each list and their count over the whole file
  // (a positive index may point forward); the statements kept.
  std::array<long long, 3> total{};
  std::string kept;
  kept.reserve(text.size() + 1);
  for (std::size_t number = 1; number <= lines.size(); ++number) {
    const std::string_view line = lines[number - 1];
    auto fail = [&](const std::string& problem) {
      throw FileError(path, "line " + std::to_string(number) + ": " + problem);
    };
    for (const char c : line)
      if (static_cast<unsigned char>(c) < 0x20 && c != '\t')
        fail("a control character (code " + std::to_string(int(static_cast<unsigned char>(c))) + ") in an OBJ file");
    const std::vector<std::string_view> w = wordsOf(line);
    const bool read = !w.empty() && (std::find(kLists.begin(), kLists.end(), w[0]) != kLists.end() ||
                                     std::find(kOtherStatementsRead.begin(), kOtherStatementsRead.end(), w[0]) !=
                                         kOtherStatementsRead.end());
    // A comment ends the statement (tinyobjloader would read a '#' in a face as an index).
    if (read) kept.append(line.substr(0, line.find('#')));
    kept += '\n';
    for (std::size_t l = 0; read && l < kLists.size(); ++l) {
      if (w[0] != kLists[l]) continue;
      ++total[l];
      std::size_t components = 0;
      for (std::size_t k = 1; k < w.size() && w[k][0] != '#'; ++k, ++components)
        if (!isFiniteNumber(w[k])) fail(quoted(w[k]) + " is not a finite number");
      const auto& allowed = kComponents[l];
      if (std::find(allowed.begin(), allowed.end(), components) == allowed.end())
        fail(quoted(w[0]) + " with " + std::to_string(components) + " numbers (it needs " +
             (l == 0 ? "3, 4, or 6 with a colour" : l == 1 ? "2 or 3" : "3") + ")");
    }
  }

  // Second pass: the faces' indices, a negative one relative to the entries defined before it.
  std::array<long long, 3> defined{};
  for (std::size_t number = 1; number <= lines.size(); ++number) {
    const std::vector<std::string_view> w = wordsOf(lines[number - 1]);
    if (w.empty()) continue;
    for (std::size_t l = 0; l < kLists.size(); ++l)
      if (w[0] == kLists[l]) ++defined[l];
    if (w[0] != "f") continue;
    auto fail = [&](const std::string& problem) {
      throw FileError(path, "line " + std::to_string(number) + ": " + problem);
    };
    std::size_t corners = 0;
    for (std::size_t k = 1; k < w.size() && w[k][0] != '#'; ++k, ++corners) {
      // "v", "v/vt", "v//vn" or "v/vt/vn".
      std::string_view rest = w[k];
      for (std::size_t l = 0; l < kLists.size(); ++l) {
        const std::size_t slash = rest.find('/');
        const std::string_view part = rest.substr(0, slash);
        // Only the texture coordinate may be left out, between two slashes ("v//vn").
        if (!(l == 1 && part.empty() && slash != std::string_view::npos)) {
          long long index = 0;
          const auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), index);
          if (ec != std::errc() || end != part.data() + part.size() || index == 0)
            fail(quoted(w[k]) + " is not a valid " + std::string(kLists[l]) + " index");
          const bool within = index > 0 ? index <= total[l] : -index <= defined[l];
          if (!within)
            fail(quoted(w[k]) + " indexes past the " + std::to_string(index > 0 ? total[l] : defined[l]) + " " +
                 quoted(kLists[l]) + " entries" + (index > 0 ? " of the file" : " defined before it"));
        }
        if (slash == std::string_view::npos) break;
        rest = rest.substr(slash + 1);
        if (l == kLists.size() - 1) fail(quoted(w[k]) + " has more than three indices");
      }
    }
    if (corners < 3) fail("'f' with " + std::to_string(corners) + " vertices (it needs 3 or more)");
  }
  return kept;
}

}  // namespace btf::render
