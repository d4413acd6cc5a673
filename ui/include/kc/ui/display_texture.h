#pragma once
/// The picture as the window draws it: a copy sized for the screen (the display texture), made
/// once per picture by area averaging, and a full-resolution crop of the part on screen when the
/// view zooms in past the display texture's resolution (the detail texture). The export never
/// uses either: it renders the full-resolution picture (app::warpSessionImage).
/// Plain CPU functions: the renderer uploads what they return.

#include <utility>
#include <vector>

#include "kc/core/rasterize.h"

namespace kc::ui {

/// The display texture's longest side is at least this many texels (unless the picture is smaller).
inline constexpr int kMinDisplaySide = 4096;

/// Longest side (texels) of the display texture for a framebuffer of fbWidth×fbHeight pixels:
///   min(max(2·max(fbWidth, fbHeight), kMinDisplaySide), maxTextureSize).
/// Twice the framebuffer: the fitted picture (at most the framebuffer's size) keeps a texel per
/// pixel while zooming in twice; beyond that the detail texture takes over.
int displayTextureLimit(int fbWidth, int fbHeight, int maxTextureSize);

/// Size of the display texture of a width×height picture whose longest side may have `limit`
/// texels: the picture's own size when it fits, else scaled by limit / max(width, height)
/// (each side rounded, at least 1).
std::pair<int, int> displayTextureSize(int width, int height, int limit);

/// A rectangle of image pixels: columns x0..x0+width−1, rows y0..y0+height−1.
struct PixelRect {
  int x0 = 0, y0 = 0, width = 0, height = 0;
  bool empty() const { return width <= 0 || height <= 0; }
};

/// Area-averaged resampling of the rectangle `crop` of `source` to outWidth×outHeight (each no
/// larger than the crop's side): output pixel (i, j) is the mean of the source area
/// [x0 + i·fx, x0 + (i+1)·fx) × [y0 + j·fy, y0 + (j+1)·fy), fx = crop.width / outWidth, pixels cut
/// by the area's edge weighted by the part inside. Colours are averaged premultiplied by alpha
/// (no dark fringes at transparent edges). Parallel over output rows. Throws
/// std::invalid_argument for a crop outside the picture or a bad output size.
Image resampleArea(const Image& source, const PixelRect& crop, int outWidth, int outHeight);

/// The mipmap levels 1, 2, … of a texture whose level 0 is `base`: each half the previous one
/// (⌊w/2⌋×⌊h/2⌋, at least 1×1, as OpenGL expects) by resampleArea, down to 1×1. Made on the CPU
/// (parallel) because a software OpenGL builds them slowly (glGenerateMipmap: 0.7 s for 12 MP
/// under Mesa llvmpipe, against tens of milliseconds here).
std::vector<Image> mipmapLevels(const Image& base);

/// The whole picture at the display texture's size for `limit` (displayTextureSize): the picture
/// itself (a copy) when it fits.
Image displayImage(const Image& source, int limit);

}  // namespace kc::ui
