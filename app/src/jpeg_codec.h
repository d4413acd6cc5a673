#pragma once
/// JPEG ↔ RGBA8 through libjpeg directly. Decoding is strict: where OpenCV's decoder prints
/// libjpeg's warnings ("Premature end of JPEG file", "Corrupt JPEG data: ...") and returns a
/// picture whose missing rows repeat the last one decoded, this refuses the file with libjpeg's
/// message. Encoding needs no OpenCV (whose codecs library takes ~0.1 s to load).

#include <string>

#include "kc/core/rasterize.h"

namespace kc::app::detail {

/// Decodes JPEG file content `bytes` to RGBA8 (alpha 255): grey and colour (YCbCr, RGB) as libjpeg
/// converts them, CMYK and YCCK (Adobe's inverted CMYK) to RGB the way OpenCV's decoder does
/// (channel·K/255). Any libjpeg warning is an error. Returns false with `problem` set (libjpeg's
/// message, one line, nothing printed) when the content cannot be decoded without one, or when
/// its size is not expectWidth × expectHeight (the header the caller checked against the limits);
/// `out` is then unspecified.
bool decodeJpeg(const std::string& bytes, int expectWidth, int expectHeight, Image& out, std::string& problem);

/// `image` (RGBA8, alpha dropped) as a baseline JPEG of `quality` (1–100; libjpeg's standard
/// tables scaled, 4:2:0 chroma), in memory. Throws std::runtime_error with libjpeg's message on a
/// failure (an empty image, out of memory).
std::string encodeJpeg(const Image& image, int quality);

}  // namespace kc::app::detail
