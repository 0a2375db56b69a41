#include "obj_indices.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <string>
#include <type_traits>
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

// Calls visit(number, words) or visit(number, words, line) for every line.
template <class Visit>
void forEachLine(std::string_view text, const Visit& visit) {
  std::size_t pos = 0, number = 0;
  while (pos < text.size()) {
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string_view::npos) eol = text.size();
    const std::string_view line = text.substr(pos, eol - pos);
    if constexpr (std::is_invocable_v<Visit, std::size_t, const std::vector<std::string_view>&, std::string_view>)
      visit(++number, wordsOf(line), line);
    else
      visit(++number, wordsOf(line));
    pos = eol + 1;
  }
}

// Whether Assimp's OBJ reader takes `word` as a number: it counts the components of a v, vt or vn
// line by their first characters (a digit, a sign, "nan" or "inf"), so ".5" is no component.
// Such a word must also parse whole here.
bool isAssimpNumber(std::string_view word) {
  if (word.empty()) return false;
  auto startsWith = [&](std::string_view prefix) {
    if (word.size() < prefix.size()) return false;
    for (std::size_t i = 0; i < prefix.size(); ++i)
      if ((word[i] | 0x20) != prefix[i]) return false;
    return true;
  };
  const char c = word[0];
  if (!((c >= '0' && c <= '9') || c == '+' || c == '-' || startsWith("nan") || startsWith("inf"))) return false;
  const std::string_view digits = c == '+' ? word.substr(1) : word;  // from_chars takes no plus sign
  double value = 0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  return ec == std::errc() && end == digits.data() + digits.size();
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
  // The entries must be the entries Assimp counts, or an index checked here could lie past
  // Assimp's list, and Assimp throws on it after building its meshes, which it then leaks. Assimp
  // skips an indented line, joins a line ending in a backslash to the next, and skips a vertex of
  // other than 3, 4 or 6 components (vt: 2 or 3; vn: 3) counted its own way (isAssimpNumber). So
  // such lines are refused, not read differently from Assimp.
  constexpr std::array<std::array<std::size_t, 3>, 3> kComponents = {{{3, 4, 6}, {2, 3, 3}, {3, 3, 3}}};
  forEachLine(text, [&](std::size_t number, const std::vector<std::string_view>& w, std::string_view raw) {
    auto fail = [&](const std::string& problem) {
      throw FileError(path, "line " + std::to_string(number) + ": " + problem);
    };
    const std::size_t last = raw.find_last_not_of(" \t\r");
    if (last != std::string_view::npos && raw[last] == '\\')
      fail("a line continuation (a backslash at the end of the line), which is not read");
    if (w.empty()) return;
    const bool statement = w[0] == "f" || w[0] == "l" || w[0] == "p" || w[0] == "v" || w[0] == "vt" || w[0] == "vn";
    if (statement && raw.substr(0, w[0].size()) != w[0]) fail("an indented " + quoted(w[0]) + " line (a statement begins its line)");
    for (std::size_t l = 0; l < kLists.size(); ++l) {
      if (w[0] != kLists[l]) continue;
      std::size_t components = 0;
      for (std::size_t k = 1; k < w.size() && w[k][0] != '#'; ++k, ++components)
        if (!isAssimpNumber(w[k])) fail(quoted(w[k]) + " is not a number (write numbers with a digit or a sign first)");
      const auto& allowed = kComponents[l];
      if (std::find(allowed.begin(), allowed.end(), components) == allowed.end())
        fail(quoted(w[0]) + " with " + std::to_string(components) + " numbers (it needs " +
             (l == 0 ? "3, 4, or 6 with a colour" : l == 1 ? "2 or 3" : "3") + ")");
    }
  });
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
