// .btfz files: the container (section table, zstd payloads, CRCs) and the VQ and factor payloads,
// single materials and databases alike. readCompressedBtf decodes the file as `btf decompress` and
// scenes do; VqDatabase::read lists a database's materials; then every material is looked up one
// by one and as a stream, and evaluated and sampled as a BtfMaterial.
#include <memory>

#include "btf/compress/compressed_btf.h"
#include "btf/compress/vq_btf.h"
#include "btf/compress/vq_database.h"
#include "btf/material/btf_material.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = btf::fuzz::writeInput({data, size}, "input.btfz");
  btf::fuzz::acceptingFileErrors([&] {
    const auto source = btf::readCompressedBtf(path);
    const auto btf = std::dynamic_pointer_cast<const btf::BtfLookup>(source);
    if (!btf) return;
    btf::fuzz::exerciseLookup(*btf);
    btf::fuzz::exerciseDecode(*source);
    btf::fuzz::acceptingFileErrors([&] { btf::fuzz::exerciseMaterial(btf::BtfMaterial(btf)); });
  });
  btf::fuzz::acceptingFileErrors([&] {
    const btf::VqDatabase database = btf::VqDatabase::read(path);
    for (const std::string& name : database.names())
      btf::fuzz::exerciseLookup(btf::VqBtf::read(path, name));
  });
  return 0;
}
