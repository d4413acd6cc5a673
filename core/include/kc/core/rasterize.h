#pragma once
/// CPU rasterization of a deformed triangle mesh with bilinear source sampling (thesis 6.3.3:
/// rendering through a triangle mesh defined on the pixel grid of the undeformed image).
///
/// Pixel convention (OpenCV's): pixel (i, j) is the unit square centred at (x, y) = (i, j), so an
/// image of w×h pixels covers [−0.5, w−0.5]×[−0.5, h−0.5]. A pixel belongs to a triangle when its
/// centre does; centres exactly on an edge go to exactly one of the two triangles sharing it
/// (a top-left style tie rule on fixed-point coordinates with 1/256 pixel precision), so a mesh
/// without fold-overs covers every pixel once: no cracks, no double blending.
///
/// Overlaps (fold-overs) are resolved deterministically: triangles are composited "over" in
/// increasing triangle index, so the later triangle wins. For the warp mesh's row-major grid this
/// means the part whose rest position is lower in the image (then further right) is on top.
/// Results are bit-identical for any thread count: each parallel task owns a band of rows.

#include <array>
#include <cstdint>
#include <vector>

#include "kc/core/cage.h"
#include "kc/core/types.h"

namespace kc {

/// An 8-bit RGBA colour (straight, not premultiplied alpha).
struct Rgba {
  std::uint8_t r = 0, g = 0, b = 0, a = 0;
  friend bool operator==(const Rgba&, const Rgba&) = default;
};

/// A plain RGBA8 image: rows top to bottom, 4 bytes per pixel (r, g, b, a), no padding.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba;  ///< width·height·4 bytes.

  Image() = default;
  Image(int w, int h, Rgba fill = {});
  bool empty() const { return width <= 0 || height <= 0; }
  std::size_t pixelCount() const { return static_cast<std::size_t>(width) * static_cast<std::size_t>(height); }
  std::uint8_t* pixel(int x, int y) { return rgba.data() + (static_cast<std::size_t>(y) * width + x) * 4; }
  const std::uint8_t* pixel(int x, int y) const { return rgba.data() + (static_cast<std::size_t>(y) * width + x) * 4; }
  Rgba at(int x, int y) const;
  /// Throws std::invalid_argument when the buffer size does not match width·height·4.
  void validate() const;
};

struct RasterOptions {
  int supersample = 1;   ///< 1 = one sample per pixel; 2 = 2×2 samples per pixel, averaged.
  Rgba background{};     ///< Colour of uncovered pixels (default transparent black).
  int bandRows = 16;     ///< Rows per parallel task.
};

struct RasterReport {
  Index trianglesDrawn = 0;     ///< Non-degenerate triangles that touch the output.
  Index degenerateTriangles = 0;
  double seconds = 0.0;
};

/// Renders the mesh (rest vertices V #V×2 in source pixels, deformed vertices F #V×2 in output
/// pixels, triangles T) into a width×height image: every output pixel covered by a deformed
/// triangle gets the source colour bilinearly sampled at the corresponding rest position
/// (barycentric interpolation of V), composited over `background`/earlier triangles.
/// Source coordinates are clamped to the image. Throws std::invalid_argument on bad shapes.
Image rasterizeMesh(const Image& source, const Points& V, const Points& F, const Triangles& T, int width,
                    int height, const RasterOptions& options = {}, RasterReport* report = nullptr);

/// Same, drawing over an existing image `target` (its pixels are the background).
void rasterizeMeshInto(Image& target, const Image& source, const Points& V, const Points& F, const Triangles& T,
                       const RasterOptions& options = {}, RasterReport* report = nullptr);

/// Bilinear sample of `image` at (x, y) in pixel-centre coordinates, clamped to the border.
Rgba sampleBilinear(const Image& image, double x, double y);

/// Per-pixel inside test of the closed polygon C (m×2) by the even-odd rule at pixel centres:
/// width·height bytes, 255 inside, 0 outside.
std::vector<std::uint8_t> polygonMask(const Points& C, int width, int height);
/// The same for the region bounded by the cage's edges (kc::cageEdges: explicit edge graphs of
/// closed loops included); an open cage bounds nothing (all 0).
std::vector<std::uint8_t> cageMask(const Cage& cage, int width, int height);

/// Copy of `image` with alpha multiplied by mask/255 (mask: width·height bytes).
Image applyMask(const Image& image, const std::vector<std::uint8_t>& mask);

/// `top` composited over `bottom` (same size), straight alpha.
Image compositeOver(const Image& top, const Image& bottom);

/// Peak signal-to-noise ratio in dB over the RGB channels of pixels where mask ≠ 0 (all pixels
/// when mask is empty): 10 log10(255² / MSE). +∞ for identical images.
double psnr(const Image& a, const Image& b, const std::vector<std::uint8_t>& mask = {});

}  // namespace kc
