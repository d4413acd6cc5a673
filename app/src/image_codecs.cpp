#include "image_codecs.h"

#include <dlfcn.h>

#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>
#include <type_traits>

namespace kc::app::detail {
namespace {

// The function's type, taken from OpenCV's declarations without referencing the functions
// (decltype is unevaluated): a change of signature fails to compile instead of crashing.
using DecodeFn = decltype(static_cast<cv::Mat (*)(cv::InputArray, int)>(&cv::imdecode));
static_assert(std::is_same_v<cv::String, std::string>, "the symbol names below assume cv::String is std::string");

// Its exported (Itanium-mangled) name in libopencv_imgcodecs, as `nm -D` lists them.
constexpr const char* kDecodeSymbol = "_ZN2cv8imdecodeERKNS_11_InputArrayEi";

struct Codecs {
  DecodeFn decode = nullptr;
  std::string problem;  // why loading failed, or ""

  Codecs() {
    // The library this build found (its SONAME, then its full path as a fallback).
    void* handle = nullptr;
    for (const char* name : {KC_IMGCODECS_SONAME, KC_IMGCODECS_PATH})
      if ((handle = dlopen(name, RTLD_NOW | RTLD_LOCAL)) != nullptr) break;
    if (!handle) {
      const char* why = dlerror();
      problem = std::string("cannot load OpenCV's image codecs (") + KC_IMGCODECS_SONAME + "): " + (why ? why : "unknown error");
      return;
    }
    // OpenCV's decoders report through its log (and libtiff's handlers, which it routes there):
    // silenced, so a file they refuse gives kcwarp's one line only.
    cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
    decode = reinterpret_cast<DecodeFn>(dlsym(handle, kDecodeSymbol));
    if (!decode) problem = std::string("OpenCV's image codecs (") + KC_IMGCODECS_SONAME + ") lack imdecode";
  }
};

const Codecs& codecs() {
  static const Codecs loaded;  // thread-safe one-time initialization
  if (!loaded.problem.empty()) throw std::runtime_error(loaded.problem);
  return loaded;
}

}  // namespace

cv::Mat imdecode(cv::InputArray buf, int flags) { return codecs().decode(buf, flags); }

}  // namespace kc::app::detail
