// The .octree file (layout in octree_table.h): the container's checksums catch damage, and
// OctreeTable::fromParts checks that what decodes is one well-formed tree.
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <string>

#include "btf/compress/octree_table.h"
#include "btf/core/error.h"
#include "btf/io/container.h"

namespace btf {
namespace {

constexpr const char* kFormat = "libbtf-octree";
constexpr int kVersion = 1;

std::uint64_t headerCount(const nlohmann::json& header, const char* key, const std::filesystem::path& path) {
  const auto it = header.find(key);
  if (it == header.end() || !it->is_number_unsigned()) throw FileError(path, std::string("octree header has no count \"") + key + "\"");
  return it->get<std::uint64_t>();
}

}  // namespace

void writeOctreeFile(const std::filesystem::path& path, const OctreeTable& octree) {
  // What is written is finite: the reader refuses anything else.
  for (const OctreeTable::Node& n : octree.nodes())
    if (!std::isfinite(n.f_min) || !std::isfinite(n.f_max)) throw FileError(path, "not written: a node's range is not finite");
  for (const OctreeTable::Leaf& l : octree.leaves())
    if (!std::isfinite(l[0]) || !std::isfinite(l[1]) || !std::isfinite(l[2]))
      throw FileError(path, "not written: a leaf value is not finite");
  nlohmann::json header;
  header["format"] = kFormat;
  header["version"] = kVersion;
  header["tolerance"] = octree.tolerance();
  header["nodes"] = octree.nodes().size();
  header["leaves"] = octree.leaves().size();
  const std::string text = header.dump();

  std::vector<ContainerSection> sections(3);
  sections[0].type = SectionType::Header;
  sections[0].name = "header";
  sections[0].data.resize(text.size());
  std::memcpy(sections[0].data.data(), text.data(), text.size());

  ByteWriter nodes;
  for (const OctreeTable::Node& n : octree.nodes()) {
    nodes.put(n.ref);
    nodes.put(n.f_min);
    nodes.put(n.f_max);
  }
  sections[1] = {SectionType::Other, "nodes", std::move(nodes.bytes()), true, 0};
  ByteWriter leaves;
  for (const OctreeTable::Leaf& l : octree.leaves()) leaves.putAll(l);
  sections[2] = {SectionType::Other, "leaves", std::move(leaves.bytes()), true, 0};
  // zstd 19 costs tens of seconds on the tens of MB of a lossless tree, for a few per cent; as
  // the .btfz writers do, large files get level 9.
  const std::size_t raw = sections[1].data.size() + sections[2].data.size();
  writeContainer(path, sections, raw <= (std::size_t(4) << 20) ? 19 : 9);
}

OctreeTable readOctreeFile(const std::filesystem::path& path) {
  const std::vector<ContainerSection> sections = readContainer(path);
  const ContainerSection& h = requireSection(sections, "header", path);
  nlohmann::json header;
  try {
    header = nlohmann::json::parse(std::string(reinterpret_cast<const char*>(h.data.data()), h.data.size()));
  } catch (const nlohmann::json::exception& e) {
    throw FileError(path, std::string("octree header is not JSON: ") + e.what());
  }
  if (!header.is_object() || header.value("format", std::string()) != kFormat)
    throw FileError(path, std::string("is not an octree table (its header names no format \"") + kFormat + "\")");
  if (!header.contains("version") || !header["version"].is_number_integer() || header["version"].get<long long>() != kVersion)
    throw FileError(path, "octree version " + (header.contains("version") ? header["version"].dump() : std::string("missing")) +
                              " (this build reads version " + std::to_string(kVersion) + ")");
  if (!header.contains("tolerance") || !header["tolerance"].is_number()) throw FileError(path, "octree header has no tolerance");
  const double tolerance = header["tolerance"].get<double>();
  const std::uint64_t node_count = headerCount(header, "nodes", path), leaf_count = headerCount(header, "leaves", path);

  ByteReader nodes_in(requireSection(sections, "nodes", path), path);
  if (node_count > nodes_in.remaining() / 12) throw FileError(path, "section 'nodes' is shorter than its " + std::to_string(node_count) + " nodes");
  std::vector<OctreeTable::Node> nodes(node_count);
  for (OctreeTable::Node& n : nodes) {
    n.ref = nodes_in.get<std::uint32_t>();
    n.f_min = nodes_in.get<float>();
    n.f_max = nodes_in.get<float>();
  }
  nodes_in.requireEnd();
  ByteReader leaves_in(requireSection(sections, "leaves", path), path);
  std::vector<OctreeTable::Leaf> leaves = leaves_in.getVector<OctreeTable::Leaf>(leaf_count);
  leaves_in.requireEnd();
  try {
    return OctreeTable::fromParts(std::move(nodes), std::move(leaves), tolerance);
  } catch (const FileError&) {
    throw;
  } catch (const Error& e) {
    throw FileError(path, std::string("malformed octree: ") + e.what());
  }
}

}  // namespace btf
