#pragma once
// Test support: a generated picture with a background, as a person's own drawing would have one:
// a sky gradient, a horizon, grass, a sun and a simple character (body, head, arms) in the middle.
// Independent of the bundled examples in images/.

#include <algorithm>
#include <cmath>

#include "kc/core/rasterize.h"

namespace kc::test {

/// width×height RGBA8, opaque. The character's body spans x ∈ [0.42, 0.58]·width,
/// y ∈ [0.35, 0.75]·height; the horizon is at y = 0.62·height; the sun is centred at
/// (0.82·width, 0.18·height) with radius 0.07·height.
inline Image sceneImage(int width, int height) {
  Image img(width, height, Rgba{0, 0, 0, 255});
  const double horizon = 0.62 * height;
  const double sunX = 0.82 * width, sunY = 0.18 * height, sunR = 0.07 * height;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      Rgba c;
      if (y < horizon) {  // sky: light blue at the horizon, deeper above
        const double t = y / horizon;
        c = Rgba{static_cast<std::uint8_t>(70 + 110 * t), static_cast<std::uint8_t>(130 + 90 * t), 235, 255};
      } else {  // grass with horizontal stripes (not a checkerboard: that means "transparent")
        const bool stripe = (y / 9) % 2 == 0;
        c = Rgba{static_cast<std::uint8_t>(stripe ? 60 : 75), static_cast<std::uint8_t>(stripe ? 150 : 170), 55, 255};
      }
      if (std::hypot(x - sunX, y - sunY) < sunR) c = Rgba{255, 215, 60, 255};
      const double u = double(x) / width, v = double(y) / height;
      const bool body = u > 0.42 && u < 0.58 && v > 0.35 && v < 0.75;
      const bool head = std::hypot(u - 0.5, (v - 0.27) * height / width) < 0.06;
      const bool arms = v > 0.38 && v < 0.44 && u > 0.30 && u < 0.70;
      if (body || arms) c = Rgba{200, 40, 60, 255};
      if (head) c = Rgba{240, 200, 160, 255};
      img.pixel(x, y)[0] = c.r;
      img.pixel(x, y)[1] = c.g;
      img.pixel(x, y)[2] = c.b;
      img.pixel(x, y)[3] = 255;
    }
  return img;
}

}  // namespace kc::test
