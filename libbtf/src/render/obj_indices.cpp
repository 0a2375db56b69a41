#include "obj_indices.h"

#include <array>
#include <charconv>
#include <string>
#include <vector>

#include "btf/core/error.h"

namespace btf::render {
namespace {

// The whitespace-separated words of one line (Assimp's OBJ tokenizer splits on spaces and tabs).
std::vector<std::string_view> wordsOf(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
  return words;
}

// 'text', quoted for a message (appended, not prepended: GCC 12 warns falsely on "'" + string).
std::string quoted(std::string_view text) {
  std::string q(1, '\'');
  q.append(text);
  q += '\'';
  return q;
}

// Calls visit(words) for every line.
template <class Visit>
void forEachLine(std::string_view text, const Visit& visit) {
  std::size_t pos = 0, number = 0;
  while (pos < text.size()) {
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string_view::npos) eol = text.size();
    visit(++number, wordsOf(text.substr(pos, eol - pos)));
    pos = eol + 1;
  }
}

}  // namespace

void checkObjElements(const std::filesystem::path& path, std::string_view text) {
  // Assimp ends a line at NUL and form feed as well as at a newline, so a line read here would not
  // be the line Assimp reads: an OBJ is text, and other control characters are refused.
  std::size_t line = 1;
  for (const char c : text) {
    if (c == '\n') ++line;
    else if (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\r')
      throw FileError(path, "line " + std::to_string(line) + ": a control character (code " +
                                std::to_string(int(static_cast<unsigned char>(c))) + ") in an OBJ file");
  }
  // Lists: v, vt, vn. Their counts over the whole file (positive indices may point forward).
  constexpr std::array<std::string_view, 3> kLists = {"v", "vt", "vn"};
  std::array<long long, 3> total{};
  forEachLine(text, [&](std::size_t, const std::vector<std::string_view>& w) {
    for (std::size_t l = 0; l < kLists.size(); ++l)
      if (!w.empty() && w[0] == kLists[l]) ++total[l];
  });

  std::array<long long, 3> defined{};
  forEachLine(text, [&](std::size_t number, const std::vector<std::string_view>& w) {
    if (w.empty()) return;
    for (std::size_t l = 0; l < kLists.size(); ++l)
      if (w[0] == kLists[l]) ++defined[l];
    const std::size_t minimum = w[0] == "f" ? 3 : w[0] == "l" ? 2 : w[0] == "p" ? 1 : 0;
    if (minimum == 0) return;
    auto fail = [&](const std::string& problem) {
      throw FileError(path, "line " + std::to_string(number) + ": " + problem);
    };
    if (w.size() - 1 < minimum)
      fail(quoted(w[0]) + " with " + std::to_string(w.size() - 1) + " vertices (it needs " +
           std::to_string(minimum) + " or more)");
    for (std::size_t k = 1; k < w.size(); ++k) {
      // "v", "v/vt", "v//vn" or "v/vt/vn".
      std::string_view rest = w[k];
      for (std::size_t l = 0; l < kLists.size(); ++l) {
        const std::size_t slash = rest.find('/');
        const std::string_view part = rest.substr(0, slash);
        if (!(l > 0 && part.empty())) {
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
  });
}

}  // namespace btf::render
