// Comma-separated option values ("fabric,stones"), as several `btf bench` options take them.
#pragma once

#include <sstream>
#include <string>
#include <vector>

namespace btf::cli {

// The non-empty items of a comma-separated list, in order.
inline std::vector<std::string> splitCommaList(const std::string& list) {
  std::vector<std::string> items;
  std::stringstream in(list);
  std::string item;
  while (std::getline(in, item, ','))
    if (!item.empty()) items.push_back(item);
  return items;
}

}  // namespace btf::cli
