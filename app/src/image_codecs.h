#pragma once
/// OpenCV's image decoders (libopencv_imgcodecs: BMP, TIFF, WebP, PNM), loaded on the first decode
/// instead of at program start. Debian's build of that library pulls in GDAL and about 140 further
/// shared libraries, which cost every kcwarp process ~0.15–0.2 s of start-up CPU whether it touches
/// pixels or not (`kcwarp-cli eval`, `stats`, `--help`, most tests). kc_app therefore links
/// opencv_core and opencv_imgproc only; this call opens the codecs library with dlopen. PNG and
/// JPEG never need it (libpng and libjpeg directly).

#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace kc::app::detail {

/// cv::imdecode(buf, flags) of the loaded codecs library. Throws std::runtime_error naming the
/// library when it cannot be loaded.
cv::Mat imdecode(cv::InputArray buf, int flags);

}  // namespace kc::app::detail
