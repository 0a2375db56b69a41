// The image backend: the one part of libbtf that decodes and encodes image files (EXR, PNG, JPEG,
// TIFF, HDR) and renders text for chart labels, through OpenImageIO. It is a module of its own
// (libbtf_image_oiio.so, backend/oiio_image_backend.cpp) that libbtf loads the first time an image
// is read or written: Debian's OpenImageIO links a large stack of libraries (GDAL, OpenCV,
// FFmpeg, OpenVDB, ...), whose loading would otherwise be paid by every program and every `btf`
// call, most of which touch no image. What stays in libbtf is everything that is not decoding: the
// size limits, the checks of EXR headers before OpenEXR reads them, the choice of reader by the
// file's first bytes, the conversions and the error messages.
//
// The interface is plain C++ between two builds of the same source tree: kAbiVersion changes when
// it does, and the module refuses a libbtf of another version. Nothing here throws across it;
// failures come back as false (or nullptr) and a message.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace btf::image_backend {

inline constexpr int kAbiVersion = 1;

// The per-channel type of pixels in a file, or of the buffer they are read into or written from.
enum class PixelType { UInt8, UInt16, Half, Float, Other };

using Attribute = std::variant<int, float, std::string>;

// What a file's header says of its current subimage.
struct ImageHeader {
  int width = 0, height = 0, depth = 1, channels = 0;
  PixelType stored = PixelType::Other;
  bool floating_point = false;  // the stored type is a floating-point one (also when Other)
  int subimages = 1;
  std::string name;  // the subimage's (EXR part's) name, if it has one
  // Every int, float and string attribute of the header, with the backend's own bookkeeping.
  std::vector<std::pair<std::string, Attribute>> attributes;
};

class Reader {
 public:
  virtual ~Reader() = default;
  virtual const ImageHeader& header() const = 0;  // of the current subimage
  virtual bool seekSubimage(int subimage) = 0;
  // Channels [0, channels) of the current subimage (x fastest) as `as` into the buffer
  // `destination()` returns, which must hold width * height * channels values. destination() is
  // called only once the first row (or tile) has been decoded: a tiny file whose header claims a
  // huge size then fails before the memory for it is allocated and filled. Scanline images are
  // read a row at a time: OpenImageIO 2.4's read_image converts through a large buffer per call
  // whatever the image's size (a cost of every small image).
  virtual bool readPixels(int subimage, int channels, PixelType as, const std::function<void*()>& destination) = 0;
  virtual std::string error() = 0;
};

// One subimage to write: its size, the type stored in the file, and header attributes.
struct WriteSpec {
  int width = 0, height = 0, channels = 0;
  PixelType stored = PixelType::Float;
  std::vector<std::pair<std::string, Attribute>> attributes;
};

class Writer {
 public:
  virtual ~Writer() = default;
  virtual bool supportsMultiImage() = 0;
  // Opens the file for one image.
  virtual bool open(const std::string& path, const WriteSpec& spec) = 0;
  // Opens the file for the first of `subimages`, all of them declared up front (as multi-part EXR
  // needs); appendSubimage moves to the next one.
  virtual bool openSubimages(const std::string& path, const std::vector<WriteSpec>& subimages) = 0;
  virtual bool appendSubimage(const std::string& path, const WriteSpec& spec) = 0;
  virtual bool write(PixelType as, const void* pixels) = 0;
  virtual bool close() = 0;
  virtual std::string error() = 0;
};

// A text's coverage (0..1, antialiased), one float per pixel, in a box just large enough for it.
struct TextMask {
  int width = 0, height = 0;
  std::vector<float> coverage;
};

class Backend {
 public:
  virtual ~Backend() = default;
  // A reader of the named format ("openexr", "png", "jpeg", "tiff", "hdr") for the file, or
  // nullptr with the reason in `error`.
  virtual std::unique_ptr<Reader> openReader(const std::string& format, const std::string& path,
                                             std::string& error) = 0;
  // A writer chosen by the path's extension, or nullptr with the reason in `error`.
  virtual std::unique_ptr<Writer> createWriter(const std::string& path, std::string& error) = 0;
  // OpenEXR decodes in the calling thread instead of its own pool (btf/io/image.h).
  virtual void decodeExrInCallingThreads() = 0;
  // Renders text with the named font; false with `font_missing` set when the font cannot be
  // loaded, else with the reason in `error`.
  virtual bool renderText(const std::string& text, int font_size, const std::string& font, TextMask& mask,
                          bool& font_missing, std::string& error) = 0;
};

// The module's entry point, by this name (extern "C"): the backend for a libbtf of interface
// version `abi_version`, or nullptr when the module was built for another.
using EntryPoint = Backend* (*)(int abi_version);
inline constexpr const char* kEntryPointName = "btf_image_backend";
inline constexpr const char* kModuleFileName = "libbtf_image_oiio.so";

}  // namespace btf::image_backend

namespace btf {

// The loaded backend; loads it on first use (thread-safe). Throws btf::Error naming the module's
// path when it cannot be loaded.
image_backend::Backend& imageBackend();

}  // namespace btf
