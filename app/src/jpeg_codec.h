#pragma once
/// JPEG → RGBA8 through libjpeg directly, strictly: where OpenCV's decoder prints libjpeg's
/// warnings ("Premature end of JPEG file", "Corrupt JPEG data: ...") and returns a picture whose
/// missing rows repeat the last one decoded, this refuses the file with libjpeg's message.

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

}  // namespace kc::app::detail
