#include "kc/core/rasterize.h"

#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

#include "kc/core/parallel.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace kc {
namespace {

using Clock = std::chrono::steady_clock;

constexpr int kSubBits = 8;                        // fixed point: 1/256 pixel
constexpr double kSubScale = 1 << kSubBits;
constexpr double kMaxCoordinate = double(1 << 20);  // |x| beyond this (pixels): triangle skipped

/// Round to the fixed-point grid (inlined; the same rule everywhere, so shared edges agree).
inline std::int64_t toFixed(double v) {
  const double f = v * kSubScale;
  return static_cast<std::int64_t>(f + (f >= 0 ? 0.5 : -0.5));
}

/// Straight-alpha "over": s over the 4 bytes at d.
inline void blendOver(std::uint8_t* d, const float s[4]) {
  const float sa = s[3] * (1.0f / 255.0f);
  if (sa >= 1.0f) {
    for (int c = 0; c < 4; ++c) d[c] = static_cast<std::uint8_t>(s[c] + 0.5f);
    return;
  }
  if (sa <= 0.0f) return;
  const float da = d[3] * (1.0f / 255.0f) * (1.0f - sa);
  const float oa = sa + da;
  for (int c = 0; c < 3; ++c) d[c] = static_cast<std::uint8_t>((s[c] * sa + d[c] * da) / oa + 0.5f);
  d[3] = static_cast<std::uint8_t>(oa * 255.0f + 0.5f);
}

/// Bilinear sample into s[4] (floats 0..255); (x, y) clamped to the image.
inline void sampleInto(const Image& img, double x, double y, float s[4]) {
  x = std::clamp(x, 0.0, double(img.width - 1));
  y = std::clamp(y, 0.0, double(img.height - 1));
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const int x1 = std::min(x0 + 1, img.width - 1), y1 = std::min(y0 + 1, img.height - 1);
  const float fx = static_cast<float>(x - x0), fy = static_cast<float>(y - y0);
  const std::uint8_t* p00 = img.pixel(x0, y0);
  const std::uint8_t* p10 = img.pixel(x1, y0);
  const std::uint8_t* p01 = img.pixel(x0, y1);
  const std::uint8_t* p11 = img.pixel(x1, y1);
  for (int c = 0; c < 4; ++c) {
    const float top = p00[c] + fx * (p10[c] - p00[c]);
    const float bottom = p01[c] + fx * (p11[c] - p01[c]);
    s[c] = top + fy * (bottom - top);
  }
}

#if defined(__SSE2__)
/// The four bytes at p as four floats.
inline __m128 loadRgba(const std::uint8_t* p) {
  std::int32_t v;
  std::memcpy(&v, p, 4);
  const __m128i zero = _mm_setzero_si128();
  return _mm_cvtepi32_ps(_mm_unpacklo_epi16(_mm_unpacklo_epi8(_mm_cvtsi32_si128(v), zero), zero));
}
#endif

/// sampleInto(img, x, y) blended over the 4 bytes at d: with SSE2 the four channels at once, the
/// same float operations in the same order (so the same bytes), and an opaque sample stored
/// directly.
inline void drawSample(const Image& img, double x, double y, std::uint8_t* d) {
#if defined(__SSE2__)
  x = std::clamp(x, 0.0, double(img.width - 1));
  y = std::clamp(y, 0.0, double(img.height - 1));
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const int x1 = std::min(x0 + 1, img.width - 1), y1 = std::min(y0 + 1, img.height - 1);
  const __m128 fx = _mm_set1_ps(static_cast<float>(x - x0)), fy = _mm_set1_ps(static_cast<float>(y - y0));
  const __m128 p00 = loadRgba(img.pixel(x0, y0)), p10 = loadRgba(img.pixel(x1, y0));
  const __m128 p01 = loadRgba(img.pixel(x0, y1)), p11 = loadRgba(img.pixel(x1, y1));
  const __m128 top = _mm_add_ps(p00, _mm_mul_ps(fx, _mm_sub_ps(p10, p00)));
  const __m128 bottom = _mm_add_ps(p01, _mm_mul_ps(fx, _mm_sub_ps(p11, p01)));
  const __m128 s = _mm_add_ps(top, _mm_mul_ps(fy, _mm_sub_ps(bottom, top)));
  if (_mm_cvtss_f32(_mm_shuffle_ps(s, s, 0xFF)) * (1.0f / 255.0f) >= 1.0f) {  // blendOver's opaque case
    const __m128i q = _mm_cvttps_epi32(_mm_add_ps(s, _mm_set1_ps(0.5f)));
    const std::int32_t bytes = _mm_cvtsi128_si32(_mm_packus_epi16(_mm_packs_epi32(q, q), q));
    std::memcpy(d, &bytes, 4);
    return;
  }
  alignas(16) float sample[4];
  _mm_store_ps(sample, s);
#else
  float sample[4];
  sampleInto(img, x, y, sample);
#endif
  blendOver(d, sample);
}

/// One triangle, set up for scan conversion: fixed-point vertices (counter-clockwise in the
/// sense that the edge functions are positive inside), tie biases, bbox and the affine map
/// output pixel → source pixel.
struct TriangleSetup {
  std::int64_t X[3], Y[3];
  std::int64_t bias[3];
  int x0, x1, y0, y1;       // pixel bbox, clipped
  double A[2][3];           // source = A · (x, y, 1)
};

bool setupTriangle(const Points& V, const Points& F, const std::array<int, 3>& t, int width, int height,
                   TriangleSetup& s, bool& degenerate) {
  degenerate = false;
  int idx[3] = {t[0], t[1], t[2]};
  double fx[3], fy[3];
  for (int k = 0; k < 3; ++k) {
    fx[k] = F(idx[k], 0);
    fy[k] = F(idx[k], 1);
    if (!(std::abs(fx[k]) < kMaxCoordinate && std::abs(fy[k]) < kMaxCoordinate)) return false;
  }
  const double bx0 = std::min({fx[0], fx[1], fx[2]}), bx1 = std::max({fx[0], fx[1], fx[2]});
  const double by0 = std::min({fy[0], fy[1], fy[2]}), by1 = std::max({fy[0], fy[1], fy[2]});
  s.x0 = std::max(0, static_cast<int>(std::ceil(bx0 - 1.0 / kSubScale)));
  s.x1 = std::min(width - 1, static_cast<int>(std::floor(bx1 + 1.0 / kSubScale)));
  s.y0 = std::max(0, static_cast<int>(std::ceil(by0 - 1.0 / kSubScale)));
  s.y1 = std::min(height - 1, static_cast<int>(std::floor(by1 + 1.0 / kSubScale)));
  if (s.x0 > s.x1 || s.y0 > s.y1) return false;
  for (int k = 0; k < 3; ++k) {
    s.X[k] = toFixed(fx[k]);
    s.Y[k] = toFixed(fy[k]);
  }
  const std::int64_t area = (s.X[1] - s.X[0]) * (s.Y[2] - s.Y[0]) - (s.Y[1] - s.Y[0]) * (s.X[2] - s.X[0]);
  if (area == 0) {
    degenerate = true;
    return false;
  }
  if (area < 0) {  // orient so that the edge functions are positive inside
    std::swap(s.X[1], s.X[2]);
    std::swap(s.Y[1], s.Y[2]);
  }
  for (int k = 0; k < 3; ++k) {
    const int b = (k + 1) % 3;
    const std::int64_t dx = s.X[b] - s.X[k], dy = s.Y[b] - s.Y[k];
    // Antisymmetric under edge reversal, so a shared edge includes its ties exactly once.
    s.bias[k] = (dy < 0 || (dy == 0 && dx > 0)) ? 1 : 0;
  }
  // Affine map output → source from the three correspondences (unsnapped coordinates).
  Eigen::Matrix2d D, S;
  D << fx[1] - fx[0], fx[2] - fx[0], fy[1] - fy[0], fy[2] - fy[0];
  S << V(idx[1], 0) - V(idx[0], 0), V(idx[2], 0) - V(idx[0], 0), V(idx[1], 1) - V(idx[0], 1),
      V(idx[2], 1) - V(idx[0], 1);
  const double det = D.determinant();
  if (std::abs(det) < 1e-300) {
    degenerate = true;
    return false;
  }
  const Eigen::Matrix2d M = S * D.inverse();
  const Eigen::Vector2d c = V.row(idx[0]).transpose() - M * Eigen::Vector2d(fx[0], fy[0]);
  for (int r = 0; r < 2; ++r) {
    s.A[r][0] = M(r, 0);
    s.A[r][1] = M(r, 1);
    s.A[r][2] = c(r);
  }
  return true;
}

/// Scan-converts rows [rowBegin, rowEnd] of one triangle into target. A pixel is drawn when all
/// three edge functions (with tie bias) are non-negative at its centre; along a row each is linear
/// in x with an integer step, so the drawn pixels are one span, found exactly in integers.
void drawRows(Image& target, const Image& source, const TriangleSetup& s, int rowBegin, int rowEnd) {
  const std::int64_t unit = std::int64_t(1) << kSubBits;
  std::int64_t stepX[3];
  for (int k = 0; k < 3; ++k) stepX[k] = -(s.Y[(k + 1) % 3] - s.Y[k]) * unit;
  for (int y = std::max(rowBegin, s.y0); y <= std::min(rowEnd, s.y1); ++y) {
    const std::int64_t py = std::int64_t(y) * unit, px = std::int64_t(s.x0) * unit;
    // The span [s.x0 + first, s.x0 + last]: e_k(x0 + i) = e_k + i·step_k ≥ 0 for every k.
    std::int64_t first = 0, last = s.x1 - s.x0;
    for (int k = 0; k < 3; ++k) {
      const int b = (k + 1) % 3;
      const std::int64_t e = (s.X[b] - s.X[k]) * (py - s.Y[k]) - (s.Y[b] - s.Y[k]) * (px - s.X[k]) + s.bias[k] - 1;
      if (stepX[k] > 0) {
        if (e < 0) first = std::max(first, (-e + stepX[k] - 1) / stepX[k]);  // i ≥ ⌈−e/step⌉
      } else if (e < 0) {
        last = -1;  // negative and not growing along the row
      } else if (stepX[k] < 0) {
        last = std::min(last, e / -stepX[k]);  // i ≤ ⌊e/(−step)⌋
      }
    }
    if (first > last) continue;
    std::uint8_t* row = target.pixel(0, y);
    for (int x = s.x0 + int(first); x <= s.x0 + int(last); ++x) {
      const double u = s.A[0][0] * x + s.A[0][1] * y + s.A[0][2];
      const double v = s.A[1][0] * x + s.A[1][1] * y + s.A[1][2];
      drawSample(source, u, v, row + std::size_t(x) * 4);
    }
  }
}

void checkInputs(const Image& source, const Points& V, const Points& F, const Triangles& T) {
  source.validate();
  if (source.empty()) throw std::invalid_argument("rasterize: the source image is empty");
  if (V.rows() != F.rows())
    throw std::invalid_argument("rasterize: " + std::to_string(V.rows()) + " rest vertices but " +
                                std::to_string(F.rows()) + " deformed vertices");
  const Index n = V.rows();
  for (const auto& t : T)
    for (int k : t)
      if (k < 0 || k >= n) throw std::invalid_argument("rasterize: triangle vertex index out of range");
}

/// The core: draws all triangles over target (same sample grid as F), in index order per band.
void drawMesh(Image& target, const Image& source, const Points& V, const Points& F, const Triangles& T,
              int bandRows, RasterReport& rep) {
  const int W = target.width, H = target.height;
  bandRows = std::max(1, bandRows);
  const int bands = (H + bandRows - 1) / bandRows;
  // Bin triangles by bands (counting sort, keeps increasing index order within each band).
  const Index nt = static_cast<Index>(T.size());
  std::vector<int> lo(static_cast<std::size_t>(nt), -1), hi(static_cast<std::size_t>(nt), -1);
  std::vector<std::uint8_t> degenerate(static_cast<std::size_t>(nt), 0);
  parallelFor(nt, [&](Index i) {  // light pass: rows touched, zero-area triangles
    const auto& t = T[std::size_t(i)];
    double y0 = std::numeric_limits<double>::infinity(), y1 = -y0, x0 = y0, x1 = -y0;
    std::int64_t X[3], Y[3];
    for (int k = 0; k < 3; ++k) {
      const double x = F(t[std::size_t(k)], 0), y = F(t[std::size_t(k)], 1);
      if (!(std::abs(x) < kMaxCoordinate && std::abs(y) < kMaxCoordinate)) return;
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
      X[k] = toFixed(x), Y[k] = toFixed(y);
    }
    if ((X[1] - X[0]) * (Y[2] - Y[0]) - (Y[1] - Y[0]) * (X[2] - X[0]) == 0) {
      degenerate[std::size_t(i)] = 1;
      return;
    }
    const int r0 = std::max(0, static_cast<int>(std::ceil(y0 - 1.0 / kSubScale)));
    const int r1 = std::min(H - 1, static_cast<int>(std::floor(y1 + 1.0 / kSubScale)));
    if (r0 > r1 || x1 + 1.0 < 0.0 || x0 - 1.0 > W - 1) return;
    lo[std::size_t(i)] = r0 / bandRows;
    hi[std::size_t(i)] = r1 / bandRows;
  }, 4096);
  std::vector<Index> start(static_cast<std::size_t>(bands) + 1, 0);
  for (Index i = 0; i < nt; ++i) {
    if (degenerate[std::size_t(i)]) ++rep.degenerateTriangles;
    if (lo[std::size_t(i)] < 0) continue;
    ++rep.trianglesDrawn;
    for (int b = lo[std::size_t(i)]; b <= hi[std::size_t(i)]; ++b) ++start[std::size_t(b) + 1];
  }
  for (int b = 0; b < bands; ++b) start[std::size_t(b) + 1] += start[std::size_t(b)];
  std::vector<int> list(static_cast<std::size_t>(start.back()));
  std::vector<Index> fill(start.begin(), start.end() - 1);
  for (Index i = 0; i < nt; ++i)
    for (int b = lo[std::size_t(i)]; b >= 0 && b <= hi[std::size_t(i)]; ++b)
      list[std::size_t(fill[std::size_t(b)]++)] = static_cast<int>(i);

  parallelFor(bands, [&](Index b) {
    const int r0 = static_cast<int>(b) * bandRows, r1 = std::min(H, r0 + bandRows) - 1;
    TriangleSetup s;
    bool deg = false;
    for (Index k = start[std::size_t(b)]; k < start[std::size_t(b) + 1]; ++k)
      if (setupTriangle(V, F, T[std::size_t(list[std::size_t(k)])], W, H, s, deg)) drawRows(target, source, s, r0, r1);
  }, 1);
}

/// Averages 2×2 blocks of `fine` (2w×2h) into `coarse` (w×h), weighting colour by alpha.
void downsample2x2(const Image& fine, Image& coarse) {
  parallelFor(coarse.height, [&](Index yy) {
    const int y = static_cast<int>(yy);
    for (int x = 0; x < coarse.width; ++x) {
      float sum[3] = {0, 0, 0}, alpha = 0;
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
          const std::uint8_t* p = fine.pixel(2 * x + dx, 2 * y + dy);
          for (int c = 0; c < 3; ++c) sum[c] += p[c] * float(p[3]);
          alpha += p[3];
        }
      std::uint8_t* q = coarse.pixel(x, y);
      if (alpha <= 0.0f) {
        q[0] = q[1] = q[2] = q[3] = 0;
        continue;
      }
      for (int c = 0; c < 3; ++c) q[c] = static_cast<std::uint8_t>(std::min(255.0f, sum[c] / alpha + 0.5f));
      q[3] = static_cast<std::uint8_t>(alpha / 4.0f + 0.5f);
    }
  }, 8);
}

}  // namespace

Image::Image(int w, int h, Rgba fill) : width(w), height(h) {
  if (w < 0 || h < 0) throw std::invalid_argument("image size must not be negative");
  rgba.resize(pixelCount() * 4);  // zeros: transparent black
  if (fill == Rgba{}) return;
  for (std::size_t i = 0; i < pixelCount(); ++i) {
    rgba[4 * i] = fill.r;
    rgba[4 * i + 1] = fill.g;
    rgba[4 * i + 2] = fill.b;
    rgba[4 * i + 3] = fill.a;
  }
}

Rgba Image::at(int x, int y) const {
  const std::uint8_t* p = pixel(x, y);
  return {p[0], p[1], p[2], p[3]};
}

void Image::validate() const {
  if (width < 0 || height < 0 || rgba.size() != pixelCount() * 4)
    throw std::invalid_argument("image buffer holds " + std::to_string(rgba.size()) + " bytes but " +
                                std::to_string(width) + "x" + std::to_string(height) + " RGBA needs " +
                                std::to_string(pixelCount() * 4));
}

void rasterizeMeshInto(Image& target, const Image& source, const Points& V, const Points& F, const Triangles& T,
                       const RasterOptions& options, RasterReport* report) {
  const auto t0 = Clock::now();
  checkInputs(source, V, F, T);
  target.validate();
  if (options.supersample != 1 && options.supersample != 2)
    throw std::invalid_argument("supersample must be 1 or 2, got " + std::to_string(options.supersample));
  RasterReport rep;
  if (options.supersample == 1) {
    drawMesh(target, source, V, F, T, options.bandRows, rep);
  } else {
    // Samples at (i ± 1/4, j ± 1/4) = centres of a 2× grid: x' = 2x + 1/2.
    Image fine(2 * target.width, 2 * target.height);
    parallelFor(fine.height, [&](Index y) {
      for (int x = 0; x < fine.width; ++x)
        std::copy_n(target.pixel(x / 2, static_cast<int>(y) / 2), 4, fine.pixel(x, static_cast<int>(y)));
    }, 16);
    Points F2 = (2.0 * F).array() + 0.5;
    drawMesh(fine, source, V, F2, T, 2 * options.bandRows, rep);
    downsample2x2(fine, target);
  }
  rep.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  if (report) *report = rep;
}

Image rasterizeMesh(const Image& source, const Points& V, const Points& F, const Triangles& T, int width,
                    int height, const RasterOptions& options, RasterReport* report) {
  Image target(width, height, options.background);
  rasterizeMeshInto(target, source, V, F, T, options, report);
  return target;
}

Rgba sampleBilinear(const Image& image, double x, double y) {
  float s[4];
  sampleInto(image, x, y, s);
  auto q = [](float v) { return static_cast<std::uint8_t>(std::clamp(v + 0.5f, 0.0f, 255.0f)); };
  return {q(s[0]), q(s[1]), q(s[2]), q(s[3])};
}

std::vector<std::uint8_t> cageMask(const Cage& cage, int width, int height) {
  std::vector<std::uint8_t> mask(static_cast<std::size_t>(std::max(0, width)) * std::max(0, height), 0);
  if (!hasInterior(cage)) return mask;
  const Points& C = cage.C;
  const auto edges = loopEdges(cage);  // even-odd over the loops; sticks have no inside
  parallelFor(height, [&](Index yy) {
    const double y = static_cast<double>(yy);
    std::vector<double> xs;
    for (const auto& [i, j] : edges) {
      const double ya = C(i, 1), yb = C(j, 1);
      if ((ya > y) != (yb > y)) xs.push_back(C(i, 0) + (y - ya) / (yb - ya) * (C(j, 0) - C(i, 0)));
    }
    std::sort(xs.begin(), xs.end());
    std::uint8_t* row = mask.data() + static_cast<std::size_t>(yy) * width;
    for (std::size_t k = 0; k + 1 < xs.size(); k += 2) {
      const int a = std::max(0, static_cast<int>(std::ceil(xs[k])));
      const int b = std::min(width - 1, static_cast<int>(std::ceil(xs[k + 1])) - 1);
      for (int x = a; x <= b; ++x) row[x] = 255;
    }
  }, 16);
  return mask;
}

std::vector<std::uint8_t> polygonMask(const Points& C, int width, int height) { return cageMask(Cage::polygon(C), width, height); }

Image applyMask(const Image& image, const std::vector<std::uint8_t>& mask) {
  image.validate();
  if (mask.size() != image.pixelCount()) throw std::invalid_argument("applyMask: mask size differs from the image");
  Image out = image;
  for (std::size_t i = 0; i < mask.size(); ++i)
    out.rgba[4 * i + 3] = static_cast<std::uint8_t>((out.rgba[4 * i + 3] * unsigned(mask[i]) + 127) / 255);
  return out;
}

Image compositeOver(const Image& top, const Image& bottom) {
  top.validate();
  bottom.validate();
  if (top.width != bottom.width || top.height != bottom.height)
    throw std::invalid_argument("compositeOver: images differ in size");
  Image out = bottom;
  parallelFor(static_cast<Index>(top.pixelCount()), [&](Index i) {
    const std::uint8_t* s = top.rgba.data() + 4 * i;
    const float sf[4] = {float(s[0]), float(s[1]), float(s[2]), float(s[3])};
    blendOver(out.rgba.data() + 4 * i, sf);
  }, 1 << 14);
  return out;
}

double psnr(const Image& a, const Image& b, const std::vector<std::uint8_t>& mask) {
  a.validate();
  b.validate();
  if (a.width != b.width || a.height != b.height) throw std::invalid_argument("psnr: images differ in size");
  if (!mask.empty() && mask.size() != a.pixelCount()) throw std::invalid_argument("psnr: mask size differs");
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < a.pixelCount(); ++i) {
    if (!mask.empty() && mask[i] == 0) continue;
    for (int c = 0; c < 3; ++c) {
      const double d = double(a.rgba[4 * i + c]) - double(b.rgba[4 * i + c]);
      sum += d * d;
    }
    count += 3;
  }
  if (count == 0) throw std::invalid_argument("psnr: the mask selects no pixels");
  const double mse = sum / double(count);
  if (mse == 0.0) return std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(255.0 * 255.0 / mse);
}

}  // namespace kc
