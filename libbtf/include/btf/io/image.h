// Float images and their files (OpenImageIO behind the scenes, loaded on first use; it stays out of
// this header).
//
// - EXR holds linear float data exactly (32-bit float channels).
// - PNG holds 8-bit data: values are clamped to [0, 1] and quantized as they are, so the caller
//   tone-maps and encodes first (toneMapToSrgb).
// - A "stack" is a multi-part EXR: several images of any size in one file, each with a name and
//   header attributes (used by `btf convert` for MERL half/diff slices).
// Every write is atomic (temporary file beside the destination, then rename). Every error is a
// FileError naming the file and the problem.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace btf {

// Interleaved channels, rows top to bottom, pixels left to right.
struct Image {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<float> pixels;

  Image() = default;
  Image(int width_, int height_, int channels_, float fill = 0.0f)
      : width(width_), height(height_), channels(channels_),
        pixels(std::size_t(width_) * std::size_t(height_) * std::size_t(channels_), fill) {}

  std::size_t offset(int x, int y, int c = 0) const {
    return (std::size_t(y) * std::size_t(width) + std::size_t(x)) * std::size_t(channels) + std::size_t(c);
  }
  float& at(int x, int y, int c) { return pixels[offset(x, y, c)]; }
  float at(int x, int y, int c) const { return pixels[offset(x, y, c)]; }
};

// The first pixel with a value that is NaN or infinite, described ("pixel (x, y) channel c is
// inf"), or nothing when every value is finite.
std::optional<std::string> nonFinitePixel(const Image& image);

// Writes by extension: .exr (float), .png (8-bit), .tif/.tiff (float), .hdr (RGBE).
// Throws FileError for unknown extensions, unwritable destinations and encoder failures.
void writeImage(const std::filesystem::path& path, const Image& image);

// Reads any format OpenImageIO knows, converted to float (8-bit data maps to [0, 1]).
Image readImage(const std::filesystem::path& path);

// The format of an image file by its first bytes, whatever its name: "openexr", "png", "jpeg",
// "tiff", "hdr", or empty for none of these (or an unreadable file).
std::string imageFileFormat(const std::filesystem::path& path);

// What every image reader of libbtf (readImage, readImageStack, image-folder BTFs) accepts: a
// header claiming more is refused with a FileError before any pixel is allocated, so that a corrupt
// file cannot exhaust memory. The defaults bound one RGB float image at 0.8 GB; raise them
// (process-wide; `btf --max-image-pixels`) for larger real images.
struct ImageSizeLimits {
  int max_side = 65536;                               // pixels per side
  std::uint64_t max_pixels = std::uint64_t(1) << 26;  // width x height (8192 x 8192)
};
void setImageSizeLimits(const ImageSizeLimits& limits);
ImageSizeLimits imageSizeLimits();

// Lets OpenEXR decode in the calling thread instead of its own thread pool (OpenImageIO's
// process-wide "exr_threads" attribute set to -1), unless the environment's OPENIMAGEIO_OPTIONS
// already sets exr_threads. libbtf reads the images of a BTF folder many at a time on its own
// threads (81 per view); OpenEXR's pool then adds nothing but hand-offs of every image's scanline
// blocks to another thread and back, which on small images cost more than the decoding. (Writing
// is bound by creating the files, and gains nothing either way.) Process-wide, so libbtf does not
// do this on its own: a program that mostly reads BTF folders calls it once at start, as `btf`
// does; one that reads large single EXRs keeps OpenEXR's pool.
void decodeExrInCallingThreads();

// A text's coverage (0..1, antialiased) as a one-channel image just large enough for it, rendered
// with FreeType (through the same backend as the image files) in the named font at font_size
// pixels; for the labels of charts. Nothing when the font cannot be loaded; Error when the text
// cannot be rendered.
std::optional<Image> renderTextMask(std::string_view text, int font_size, const std::string& font);

// The sRGB transfer curves (IEC 61966-2-1): encoding a linear value in [0, 1] (clamped; 12.92 x
// below 0.0031308, 1.055 x^(1/2.4) - 0.055 above) and decoding an encoded one in [0, 1] (clamped).
float srgbEncode(float linear);
float srgbDecode(float encoded);

// 8-bit sRGB codes without a pow per value: encode() searches the 255 thresholds between codes,
// decode() reads a table of the 256 codes' values. Exactly lround(srgbEncode(x) * 255) and
// srgbDecode(code / 255.0f) for every float x (the thresholds are found by bisection over the
// floats with that very expression), so a writer, reader or camera model that switches to it
// changes no output. A NaN encodes to 0.
class Srgb8 {
 public:
  static const Srgb8& instance();  // built on first use, shared
  std::uint8_t encode(float linear) const;
  float decode(std::uint8_t code) const { return decoded_[code]; }

 private:
  Srgb8();
  std::array<float, 256> threshold_;  // threshold_[k]: the least x whose code is k (threshold_[0] = -inf)
  std::array<float, 256> decoded_;
};
// Linear radiance -> displayable [0, 1] sRGB values: multiply by 2^exposure_stops, clamp, encode.
// Alpha (a fourth channel) is copied unchanged.
Image toneMapToSrgb(const Image& linear, float exposure_stops = 0.0f);

using ImageAttribute = std::variant<int, float, std::string>;

struct StackLayer {
  std::string name;                                    // the EXR part name
  std::map<std::string, ImageAttribute> attributes;    // extra header attributes of the part
  Image image;
};

// Writes a multi-part EXR, one part per layer (the path must end in .exr).
void writeImageStack(const std::filesystem::path& path, const std::vector<StackLayer>& layers);
// Reads every part of a (multi-part) EXR with its name and its int, float and string attributes.
std::vector<StackLayer> readImageStack(const std::filesystem::path& path);

}  // namespace btf
