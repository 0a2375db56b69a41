// .octree files: the container, the header, and the tree checks of OctreeTable::fromParts. A tree
// that loads is located at the table's corners, bounded over boxes and evaluated and sampled as an
// OctreeBrdf with each lookup (expand() is left out: 35 MB per input would stall the fuzzer).
#include <memory>

#include "btf/compress/octree_table.h"
#include "btf/material/octree_brdf.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = btf::fuzz::writeInput({data, size}, "input.octree");
  btf::fuzz::acceptingFileErrors([&] {
    auto octree = std::make_shared<const btf::OctreeTable>(btf::readOctreeFile(path));
    for (int i : {0, 45, 89})
      for (int j : {0, 44, 89})
        for (int k : {0, 90, 179}) (void)octree->raw(i, j, k);
    (void)octree->maxOver(btf::OctreeTable::Box{});
    (void)octree->maxOver(btf::OctreeTable::Box{{10, 20, 30}, {11, 60, 31}});
    for (btf::TableLookup lookup : {btf::TableLookup::Interpolated, btf::TableLookup::Nearest, btf::TableLookup::Truncated})
      btf::fuzz::exerciseMaterial(btf::OctreeBrdf(octree, lookup));
  });
  return 0;
}
