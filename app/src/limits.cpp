#include "kc/app/limits.h"

#include <cstdio>

#include "kc/app/errors.h"

namespace kc::app {

void checkImageSize(std::int64_t width, std::int64_t height, const std::string& where, const std::string& what) {
  const std::string size = std::to_string(width) + "x" + std::to_string(height);
  if (width <= 0 || height <= 0) throw InputError(where, what + " size " + size + " is empty");
  if (width > kMaxImageSide || height > kMaxImageSide)
    throw InputError(where, what + " size " + size + " has a side above kcwarp's limit of " + std::to_string(kMaxImageSide) +
                                " pixels; scale it down first");
  if (width * height > kMaxImagePixels)
    throw InputError(where, what + " size " + size + " is " + std::to_string((width * height + 500000) / 1000000) +
                                " megapixels, above kcwarp's limit of " + std::to_string(kMaxImagePixels) +
                                " pixels (8192 x 8192); scale it down first");
}

std::string byteText(double bytes) {
  char buf[32];
  const double k = 1024.0;
  if (bytes >= k * k * k) std::snprintf(buf, sizeof buf, "%.1f GiB", bytes / (k * k * k));
  else if (bytes >= k * k) std::snprintf(buf, sizeof buf, "%.0f MiB", bytes / (k * k));
  else if (bytes >= k) std::snprintf(buf, sizeof buf, "%.0f KiB", bytes / k);
  else std::snprintf(buf, sizeof buf, "%.0f bytes", bytes);
  return buf;
}

}  // namespace kc::app
