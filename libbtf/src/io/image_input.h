// Opening images through the image backend (image_backend.h) with libbtf's size limits
// (io/image.h), shared by readImage, readImageStack and the image-folder BTF reader.
#pragma once

#include <filesystem>
#include <memory>

#include "image_backend.h"

namespace btf {

// Opens the image for reading: FileError for a missing, empty or unreadable file, or one whose
// header claims a size beyond imageSizeLimits() (checked before any pixel is allocated; OpenEXR
// checks its own headers against the same limit before it allocates its chunk tables).
std::unique_ptr<image_backend::Reader> openImageInput(const std::filesystem::path& path);

// The size check of openImageInput, for the subimage now current (multi-part files).
void requireImageSizeWithinLimits(const std::filesystem::path& path, const image_backend::ImageHeader& header);

}  // namespace btf
