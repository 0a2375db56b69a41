// Opening and reading images through OpenImageIO with libbtf's size limits (io/image.h), shared by
// readImage, readImageStack and the image-folder BTF reader.
#pragma once

#include <OpenImageIO/imageio.h>

#include <filesystem>
#include <functional>
#include <memory>

namespace btf {

// Opens the image for reading: FileError for a missing, empty or unreadable file, or one whose
// header claims a size beyond imageSizeLimits() (checked before any pixel is allocated; OpenEXR
// checks its own headers against the same limit before it allocates its chunk tables).
std::unique_ptr<OIIO::ImageInput> openImageInput(const std::filesystem::path& path);

// The size check of openImageInput, for the subimage now current (multi-part files).
void requireImageSizeWithinLimits(const std::filesystem::path& path, const OIIO::ImageSpec& spec);

// Channels [0, channels) of the current subimage (its data window, x fastest) as `format` into
// the buffer `destination()` returns, which must hold width * height * channels values.
// destination() is called only once the first row (or tile) has been decoded: a 21-byte file
// whose header claims 12485 x 2053 pixels then fails before hundreds of megabytes are allocated
// and filled for it. Scanline images are read a row at a time: OpenImageIO 2.4's read_image
// converts through a buffer of 64 MB per call whatever the image's size (a cost of every small
// image, and of each under the sanitizers, which touch it all).
// False on a decoding error (in.geterror() says which); destination() may not have been called.
bool readPixels(OIIO::ImageInput& in, int subimage, int channels, OIIO::TypeDesc format,
                const std::function<void*()>& destination);

}  // namespace btf
