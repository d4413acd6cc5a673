#include "kc/ui/display_texture.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "kc/core/parallel.h"

namespace kc::ui {
namespace {

/// The source pixels under each of `out` output pixels along one axis of `n` source pixels
/// starting at `offset`: output i covers [i·f, (i+1)·f), f = n / out; pixel k weighs its overlap / f.
struct Footprints {
  std::vector<int> first;     ///< #out+1: output i uses taps first[i]..first[i+1]−1
  std::vector<int> pixel;     ///< source index per tap
  std::vector<float> weight;  ///< weight per tap (each output's weights sum to 1)
};

Footprints footprints(int offset, int n, int out) {
  Footprints fp;
  const double f = double(n) / out;
  fp.first.reserve(static_cast<std::size_t>(out) + 1);
  for (int i = 0; i < out; ++i) {
    fp.first.push_back(static_cast<int>(fp.pixel.size()));
    const double a = i * f, b = (i + 1) * f;
    const int lo = static_cast<int>(std::floor(a)), hi = std::min(n - 1, static_cast<int>(std::ceil(b)) - 1);
    for (int k = lo; k <= hi; ++k) {
      const double overlap = std::min(b, k + 1.0) - std::max(a, double(k));
      if (overlap <= 0.0) continue;
      fp.pixel.push_back(offset + k);
      fp.weight.push_back(static_cast<float>(overlap / f));
    }
  }
  fp.first.push_back(static_cast<int>(fp.pixel.size()));
  return fp;
}

/// resampleArea(image, whole, w/2, h/2) for even w and h, in integers: each output pixel the
/// alpha-weighted mean of a 2×2 block, rounded half up (as resampleArea rounds), about four
/// times faster.
Image halveEven(const Image& image) {
  Image out(image.width / 2, image.height / 2);
  parallelForRange(out.height, 16, [&](Index begin, Index end) {
    for (Index j = begin; j < end; ++j) {
      const std::uint8_t* r0 = image.pixel(0, static_cast<int>(2 * j));
      const std::uint8_t* r1 = image.pixel(0, static_cast<int>(2 * j + 1));
      std::uint8_t* dst = out.pixel(0, static_cast<int>(j));
      for (int i = 0; i < out.width; ++i, r0 += 8, r1 += 8, dst += 4) {
        const unsigned a = unsigned(r0[3]) + r0[7] + r1[3] + r1[7];
        for (int c = 0; c < 3; ++c) {
          const unsigned sum = unsigned(r0[c]) * r0[3] + unsigned(r0[4 + c]) * r0[7] + unsigned(r1[c]) * r1[3] + unsigned(r1[4 + c]) * r1[7];
          dst[c] = a ? static_cast<std::uint8_t>((2 * sum + a) / (2 * a)) : 0;
        }
        dst[3] = static_cast<std::uint8_t>((a + 2) / 4);
      }
    }
  });
  return out;
}

}  // namespace

int displayTextureLimit(int fbWidth, int fbHeight, int maxTextureSize) {
  return std::max(1, std::min(std::max(2 * std::max(fbWidth, fbHeight), kMinDisplaySide), maxTextureSize));
}

std::pair<int, int> displayTextureSize(int width, int height, int limit) {
  const int longest = std::max(width, height);
  if (longest <= limit) return {width, height};
  const double s = double(limit) / longest;
  return {std::clamp(static_cast<int>(std::lround(width * s)), 1, limit),
          std::clamp(static_cast<int>(std::lround(height * s)), 1, limit)};
}

Image resampleArea(const Image& source, const PixelRect& crop, int outWidth, int outHeight) {
  if (crop.empty() || crop.x0 < 0 || crop.y0 < 0 || crop.x0 + crop.width > source.width || crop.y0 + crop.height > source.height)
    throw std::invalid_argument("resampleArea: the crop lies outside the " + std::to_string(source.width) + "x" +
                                std::to_string(source.height) + " picture");
  if (outWidth < 1 || outHeight < 1 || outWidth > crop.width || outHeight > crop.height)
    throw std::invalid_argument("resampleArea: output size " + std::to_string(outWidth) + "x" + std::to_string(outHeight) +
                                " must be between 1x1 and the crop's size");
  const Footprints fx = footprints(crop.x0, crop.width, outWidth);
  const Footprints fy = footprints(crop.y0, crop.height, outHeight);
  Image out(outWidth, outHeight);
  const std::size_t rowFloats = static_cast<std::size_t>(outWidth) * 4;
  parallelForRange(outHeight, 8, [&](Index begin, Index end) {
    std::vector<float> row(rowFloats), acc(rowFloats);
    for (Index j = begin; j < end; ++j) {
      std::fill(acc.begin(), acc.end(), 0.0f);
      for (int ty = fy.first[j]; ty < fy.first[j + 1]; ++ty) {
        const std::uint8_t* src = source.pixel(0, fy.pixel[ty]);
        const float wy = fy.weight[ty];
        for (int i = 0; i < outWidth; ++i) {  // this source row across output pixel i, premultiplied
          float r = 0, g = 0, b = 0, a = 0;
          for (int tx = fx.first[i]; tx < fx.first[i + 1]; ++tx) {
            const std::uint8_t* p = src + static_cast<std::size_t>(fx.pixel[tx]) * 4;
            const float wa = fx.weight[tx] * p[3];
            r += wa * p[0];
            g += wa * p[1];
            b += wa * p[2];
            a += wa;
          }
          float* q = acc.data() + static_cast<std::size_t>(i) * 4;
          q[0] += wy * r;
          q[1] += wy * g;
          q[2] += wy * b;
          q[3] += wy * a;
        }
      }
      std::uint8_t* dst = out.pixel(0, static_cast<int>(j));
      for (int i = 0; i < outWidth; ++i) {
        const float* q = acc.data() + static_cast<std::size_t>(i) * 4;
        const float a = q[3];
        for (int c = 0; c < 3; ++c)
          dst[4 * i + c] = a > 0.0f ? static_cast<std::uint8_t>(std::clamp(std::lround(q[c] / a), 0L, 255L)) : 0;
        dst[4 * i + 3] = static_cast<std::uint8_t>(std::clamp(std::lround(a), 0L, 255L));
      }
    }
  });
  return out;
}

std::vector<Image> mipmapLevels(const Image& base) {
  std::vector<Image> levels;
  for (;;) {
    const Image& previous = levels.empty() ? base : levels.back();
    if (previous.width <= 1 && previous.height <= 1) return levels;
    Image next = previous.width % 2 == 0 && previous.height % 2 == 0
                     ? halveEven(previous)
                     : resampleArea(previous, {0, 0, previous.width, previous.height}, std::max(1, previous.width / 2),
                                    std::max(1, previous.height / 2));
    levels.push_back(std::move(next));  // (after the read: push_back may move `previous`)
  }
}

Image displayImage(const Image& source, int limit) {
  const auto [w, h] = displayTextureSize(source.width, source.height, limit);
  if (w == source.width && h == source.height) return source;
  return resampleArea(source, {0, 0, source.width, source.height}, w, h);
}

}  // namespace kc::ui
