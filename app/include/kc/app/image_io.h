#pragma once
/// Image files ↔ the core's plain RGBA image (OpenCV lives only in app/src).

#include <string>

#include "kc/core/rasterize.h"

namespace kc::app {

/// Loads a PNG/JPEG/… (anything OpenCV reads) as RGBA8: grey, BGR and BGRA, 8 or 16 bit, are
/// converted; images without alpha get alpha 255. Throws InputError (a std::runtime_error)
/// naming the file when it is missing or cannot be decoded.
Image loadImage(const std::string& path);

/// Saves an RGBA8 image; the format follows the extension (.png keeps alpha, .jpg/.jpeg drop it).
/// Atomic: encoded in memory, written to a temporary file in the same folder, then renamed.
/// Throws InputError naming the file on an unknown extension or a failed write.
void saveImage(const std::string& path, const Image& image);

/// The image encoded as `ext` (".png", ".jpg") in memory.
std::string encodeImage(const Image& image, const std::string& ext);

}  // namespace kc::app
