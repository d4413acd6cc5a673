#pragma once
/// OpenCV's image codecs (libopencv_imgcodecs), loaded on the first decode or encode instead of at
/// program start. Debian's build of that library pulls in GDAL and about 140 further shared
/// libraries, which cost every kcwarp process ~0.15–0.2 s of start-up CPU whether it touches
/// pixels or not (`kcwarp-cli eval`, `stats`, `--help`, most tests). kc_app therefore links
/// opencv_core and opencv_imgproc only; these two calls open the codecs library with dlopen.

#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace kc::app::detail {

/// cv::imdecode(buf, flags) of the loaded codecs library. Throws std::runtime_error naming the
/// library when it cannot be loaded.
cv::Mat imdecode(cv::InputArray buf, int flags);
/// cv::imencode(ext, image, out, params) of the loaded codecs library (same failure as above).
bool imencode(const std::string& ext, cv::InputArray image, std::vector<uchar>& out, const std::vector<int>& params);

}  // namespace kc::app::detail
