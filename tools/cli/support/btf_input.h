// Opening anything `btf compress`, `btf decompress` and `btf info` accept as a BTF:
//   a folder          an image-folder BTF (io/btf_images.h)
//   FILE.btfz         a VQ-compressed BTF (compress/vq_btf.h)
//   .binary/.bsdf/.exr a measured BRDF, as a one-texel BTF sampled at the 81 x 81 directions
//   merl-fit:MODEL:NAME a published fit of a MERL material (io/merl_fits.h), the same way
#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "btf/io/btf_data.h"
#include "btf/material/material.h"

namespace btf::cli {

enum class BtfInputKind { ImageFolder, Compressed, Brdf };

struct BtfInput {
  BtfInputKind kind;
  std::shared_ptr<const BtfSource> source;
  std::string description;  // e.g. "image-folder BTF (png8)"
};

inline constexpr const char* kMerlFitPrefix = "merl-fit:";

// Throws FileError for a missing path or an unknown kind of file. `material` names the material
// of a .btfz database to read (empty: the file must hold one); other inputs refuse a name.
BtfInput openBtfInput(const std::filesystem::path& path, const std::string& material = {});

// `btf info` for BTFs: true for a folder or a .btfz file, which runBtfInfo describes.
bool isBtfPath(const std::filesystem::path& path);
void runBtfInfo(const std::filesystem::path& path, bool json);

// A BRDF as a one-texel BTF: value(view, light) = f(light direction, view direction).
BtfData brdfAsBtf(const Material& material, const std::string& name);

}  // namespace btf::cli
