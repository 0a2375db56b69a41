// Image-folder BTFs (the layout of the Bonn UBO2003 data, docs/formats.md): one image per
// (view, light) pair over the 81-direction set (btf_directions.h), named by its four angles in
// whole degrees, e.g. `tv030_pv060_tl045_pl120.png`. Pixel (x, y) of every image is texel (x, y).
//
// Names: the tags tv, pv (view theta, phi) and tl, pl (light theta, phi), each followed by its angle
// in degrees, in any order, in any case, separated by `_`, `-`, `.`, spaces or nothing; a leading
// or trailing frame number is allowed (`00012 tl015 pl060 tv000 pv000.png`). Files without these
// tags (previews, notes) are ignored; a name with the tags but an angle outside the set is an error.
//
// Views: a folder may hold any subset of the 81 views (one view of a sample, or the views up to some
// elevation); each view it holds needs all 81 light images. views() says which it has.
//
// Values: float images (EXR) hold the apparent BRDF itself. Integer images (PNG 8/16-bit, also
// TIFF/JPEG through OpenImageIO) hold value = transfer(code / max_code) * value_scale, with
// value_scale and transfer from the optional sidecar `btf.json` in the folder
// (`{"value_scale": s, "transfer": "srgb" | "linear"}`). Without them: value_scale 1, and the
// transfer is sRGB for 8-bit images (what cameras and the Bonn database store: the IEC 61966-2-1
// decoding curve, linear below code 0.04045 * 255, a 2.4 power above) and linear for 16-bit ones.
// The sidecar's transfer applies to the folder's integer images of every depth; float images are
// always linear. Our writer writes both keys: 8-bit PNGs sRGB-encoded, 16-bit PNGs linear, with
// value_scale set so that they can hold apparent-BRDF values above 1.
#pragma once

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "btf/io/btf_data.h"

namespace btf {

enum class BtfImageFormat { Png8, Png16, Exr };
enum class BtfImageLayout { Ubo2003, Utia };
std::string btfImageLayoutName(BtfImageLayout layout);  // "UBO2003", "UTIA"
// The colour space of float images: linear Rec.709 primaries, or CIE XYZ (D65 white).
enum class BtfColorSpace { Rec709, Xyz };

// How integer codes map to linear values (see above).
enum class BtfTransfer { Srgb, Linear };
std::string btfTransferName(BtfTransfer transfer);                  // "srgb", "linear"
std::optional<BtfTransfer> parseBtfTransfer(std::string_view name);  // any case; nothing if unknown

// "png8", "png16", "exr" and the file extension (".png", ".exr") of a format.
std::string btfImageFormatName(BtfImageFormat format);
std::string btfImageExtension(BtfImageFormat format);

// The (view, light) pair a file name stands for (see above), or nothing when the name carries no
// angle tags. Throws btf::Error (naming the file name) for tags that are repeated, missing or not
// a direction of the 81-direction set.
struct BtfImagePair {
  int view;
  int light;
};
std::optional<BtfImagePair> parseBtfImageName(std::string_view file_name);
// The canonical name our writer uses, e.g. "tv030_pv060_tl045_pl120.png"; in the UTIA layout the
// path inside the folder, e.g. "tv030_pv060/tl045_pl120_tv030_pv060.png".
std::string btfImageName(int view, int light, BtfImageFormat format);
std::string btfImagePath(int view, int light, BtfImageFormat format, BtfImageLayout layout);

// The name of the sidecar with value_scale and transfer (and facts for people: size, format, source).
inline constexpr const char* kBtfSidecarName = "btf.json";

// A BTF read from an image folder, one view (81 images) at a time.
class BtfImageFolder final : public BtfSource {
 public:
  // Scans the folder and checks the names up front: every light of each view held present exactly
  // once (FileError naming the first missing (theta, phi) pair, or both files of a duplicate);
  // reads btf.json if present and the size of the first image. Pixel data is read by loadView.
  static BtfImageFolder open(const std::filesystem::path& folder);

  int width() const override { return width_; }
  int height() const override { return height_; }
  const BtfViewSet& views() const override { return views_; }
  // For integer images: value_scale (the value of the largest code). Nothing for float images.
  std::optional<float> white() const override;
  std::string name() const override;
  // Reads the view's 81 images (in parallel). FileError naming the file for an unreadable or
  // corrupt image, one of another size (both sizes named), fewer than 3 channels, or a float image
  // with NaN, infinite or negative values.
  void loadView(int view, std::vector<Rgb>& out) const override;

  // Opens every image's header, not its pixels: FileError naming the first image that is missing,
  // empty, unreadable, of another size than the first or with fewer than 3 channels. What `btf
  // info` checks; loadView checks the same, and the pixels.
  void checkImageHeaders() const;

  const std::filesystem::path& folder() const { return folder_; }
  const std::filesystem::path& imagePath(int view, int light) const;
  float valueScale() const { return value_scale_; }
  // The transfer of the folder's (first) images; nothing for float images.
  std::optional<BtfTransfer> transfer() const;
  BtfImageLayout layout() const { return layout_; }
  // The colour space of float images: XYZ in the UTIA layout, Rec.709 otherwise, unless btf.json's
  // "color_space" ("xyz" or "rec709") says.
  BtfColorSpace colorSpace() const { return color_space_; }
  // The direction list btf.json names (UTIA's shifted lights), if any.
  const std::optional<std::filesystem::path>& directionList() const { return direction_list_; }

 private:
  BtfImageFolder() = default;
  void readImageInto(int view, int light, std::vector<Rgb>& out) const;
  // How an image's values are stored, as far as their transfer depends on it.
  struct StoredType {
    bool floating_point = false;
    bool eight_bit = false;
  };
  BtfTransfer transferOf(StoredType stored) const;

  std::filesystem::path folder_;
  std::vector<std::filesystem::path> paths_;  // view * 81 + light
  BtfViewSet views_;
  BtfImageLayout layout_ = BtfImageLayout::Ubo2003;
  BtfColorSpace color_space_ = BtfColorSpace::Rec709;
  std::optional<std::filesystem::path> direction_list_;
  float value_scale_ = 1.0f;
  std::optional<BtfTransfer> transfer_override_;  // btf.json's, if it has one
  StoredType first_type_;
  int width_ = 0, height_ = 0;
};

struct BtfImageWriteOptions {
  BtfImageFormat format = BtfImageFormat::Exr;
  // UTIA: per-view subfolders, and EXR images in CIE XYZ (D65) as that database stores them.
  BtfImageLayout layout = BtfImageLayout::Ubo2003;
  // For PNG: the value of the largest code. Without it the writer first reads the whole source
  // once to find its largest value (a second pass over a generated source).
  std::optional<float> value_scale;
  // Replace an existing destination folder, but only one this writer made (it holds btf.json) or
  // an empty one: never a folder of other files.
  bool overwrite = true;
};

// Writes every (view, light) image of the views `source` holds into `folder` plus btf.json. The folder is built
// as a hidden temporary sibling and renamed into place when complete, so a failure or an
// interruption never leaves a half-written BTF under the destination name. Progress is reported
// per image. PNG values above value_scale are clamped (none are when the scale is found by the
// writer); negative and NaN values are rejected (btf::Error naming the entry).
void writeBtfImageFolder(const BtfSource& source, const std::filesystem::path& folder,
                         const BtfImageWriteOptions& options = {});
inline void writeBtfImageFolder(const BtfSource& source, const std::filesystem::path& folder, BtfImageFormat format) {
  BtfImageWriteOptions options;
  options.format = format;
  writeBtfImageFolder(source, folder, options);
}

}  // namespace btf
