#include "kc/core/rasterize.h"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <random>
#include <stdexcept>

#include "kc/core/parallel.h"

namespace kc {
namespace {

/// A smooth-ish colourful test image (checker + gradients), alpha `a`.
Image testImage(int w, int h, std::uint8_t a = 255) {
  Image img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = img.pixel(x, y);
      const bool check = ((x / 8) + (y / 8)) % 2 == 0;
      p[0] = static_cast<std::uint8_t>(check ? 220 : 30);
      p[1] = static_cast<std::uint8_t>(255 * x / std::max(1, w - 1));
      p[2] = static_cast<std::uint8_t>(255 * y / std::max(1, h - 1));
      p[3] = a;
    }
  return img;
}

/// A regular grid mesh over [−0.5, w−0.5]×[−0.5, h−0.5] with `cells` cells per side.
void gridMesh(int w, int h, int cells, Points& V, Triangles& T) {
  V.resize((cells + 1) * (cells + 1), 2);
  for (int j = 0; j <= cells; ++j)
    for (int i = 0; i <= cells; ++i) V.row(j * (cells + 1) + i) << -0.5 + double(w) * i / cells, -0.5 + double(h) * j / cells;
  T.clear();
  for (int j = 0; j < cells; ++j)
    for (int i = 0; i < cells; ++i) {
      const int a = j * (cells + 1) + i, b = a + 1, c = a + cells + 1, d = c + 1;
      T.push_back({a, b, d});
      T.push_back({a, d, c});
    }
}

TEST(Rasterize, IdentityMeshCoversEveryPixelExactlyOnce) {
  // Semi-transparent source: a pixel drawn twice would be blended twice and change its alpha.
  const Image src = testImage(67, 45, 128);
  Points V;
  Triangles T;
  gridMesh(67, 45, 16, V, T);
  RasterReport rep;
  const Image out = rasterizeMesh(src, V, V, T, 67, 45, {}, &rep);
  EXPECT_EQ(out.rgba, src.rgba);
  EXPECT_EQ(rep.trianglesDrawn, Index(T.size()));
}

TEST(Rasterize, JitteredMeshCoversEveryPixelExactlyOnce) {
  // Interior vertices moved by up to a quarter cell, every third one then snapped onto a pixel
  // centre and every third onto a half-pixel (where the tie rule decides); edges of every slope.
  const int w = 83, h = 61, cells = 9;
  const Image src = testImage(w, h, 128);
  Points V;
  Triangles T;
  gridMesh(w, h, cells, V, T);
  Points F = V;
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> jitter(-0.25, 0.25);
  for (int j = 1; j < cells; ++j)
    for (int i = 1; i < cells; ++i) {
      const Index v = j * (cells + 1) + i;
      F(v, 0) += jitter(rng) * w / cells;
      F(v, 1) += jitter(rng) * h / cells;
      if (v % 3 == 0) F.row(v) = F.row(v).array().round();
      if (v % 3 == 1) F.row(v) = (F.row(v).array() + 0.5).round() - 0.5;
    }
  for (const auto& t : T) {  // no fold-overs: the premise of "exactly once"
    const Vec2 a = F.row(t[0]), b = F.row(t[1]), c = F.row(t[2]);
    ASSERT_GT((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x(), 0.0);
  }
  const Image out = rasterizeMesh(src, V, F, T, w, h);
  int wrong = 0;  // drawn twice: alpha 192; never: 0
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) wrong += out.at(x, y).a != 128;
  EXPECT_EQ(wrong, 0);
}

TEST(Rasterize, IntegerTranslationShiftsPixels) {
  const Image src = testImage(40, 30);
  Points V;
  Triangles T;
  gridMesh(40, 30, 5, V, T);
  Points F = V;
  F.col(0).array() += 3;
  F.col(1).array() += 2;
  const Image out = rasterizeMesh(src, V, F, T, 40, 30);
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) {
      if (x >= 3 && y >= 2) {
        EXPECT_EQ(out.at(x, y), src.at(x - 3, y - 2)) << x << "," << y;
      } else {
        EXPECT_EQ(out.at(x, y).a, 0) << x << "," << y;  // uncovered: transparent background
      }
    }
}

TEST(Rasterize, AffineWarpMatchesAnalyticInverseSampling) {
  const int w = 96, h = 80;
  const Image src = testImage(w, h);
  Points V;
  Triangles T;
  gridMesh(w, h, 12, V, T);
  Eigen::Matrix2d A;
  A << 0.9, 0.25, -0.15, 1.05;
  const Vec2 b(4, -3);
  Points F(V.rows(), 2);
  for (Index v = 0; v < V.rows(); ++v) F.row(v) = (A * V.row(v).transpose() + b).transpose();
  const Image out = rasterizeMesh(src, V, F, T, w, h);
  // Reference: output pixel x shows the source at A⁻¹(x − b); compare where that lies inside.
  Image ref(w, h);
  std::vector<std::uint8_t> mask(ref.pixelCount(), 0);
  const Eigen::Matrix2d Ai = A.inverse();
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Vec2 s = Ai * (Vec2(x, y) - b);
      const Rgba c = sampleBilinear(src, s.x(), s.y());
      std::copy_n(&c.r, 4, ref.pixel(x, y));
      if (s.x() > 0.5 && s.y() > 0.5 && s.x() < w - 1.5 && s.y() < h - 1.5) mask[std::size_t(y) * w + x] = 1;
    }
  EXPECT_GT(psnr(out, ref, mask), 45.0);
}

TEST(Rasterize, LaterTriangleWinsOverlaps) {
  Image src(2, 1);
  std::uint8_t* p0 = src.pixel(0, 0);
  std::uint8_t* p1 = src.pixel(1, 0);
  p0[0] = 255, p0[3] = 255;  // red at x = 0
  p1[2] = 255, p1[3] = 255;  // blue at x = 1
  // Two big triangles covering the whole 10×10 output: the first samples red, the second blue.
  Points V(6, 2), F(6, 2);
  V << 0, 0, 0, 0, 0, 0, 1, 0, 1, 0, 1, 0;
  F << -1, -1, 30, -1, -1, 30, -1, -1, 30, -1, -1, 30;
  const Triangles T{{0, 1, 2}, {3, 4, 5}};
  const Image out = rasterizeMesh(src, V, F, T, 10, 10);
  EXPECT_EQ(out.at(5, 5), (Rgba{0, 0, 255, 255}));
  const Triangles Trev{{3, 4, 5}, {0, 1, 2}};
  EXPECT_EQ(rasterizeMesh(src, V, F, Trev, 10, 10).at(5, 5), (Rgba{255, 0, 0, 255}));
}

TEST(Rasterize, SupersamplingKeepsTheRestImage) {
  const Image src = testImage(64, 64);
  Points V;
  Triangles T;
  gridMesh(64, 64, 8, V, T);
  RasterOptions opt;
  opt.supersample = 2;
  const Image out = rasterizeMesh(src, V, V, T, 64, 64, opt);
  // Interior pixels: the 2×2 box over the bilinear reconstruction is a mild blur.
  std::vector<std::uint8_t> mask(out.pixelCount(), 0);
  for (int y = 1; y < 63; ++y)
    for (int x = 1; x < 63; ++x) mask[std::size_t(y) * 64 + x] = 1;
  EXPECT_GT(psnr(out, src, mask), 25.0);
  for (std::size_t i = 0; i < out.pixelCount(); ++i) ASSERT_EQ(out.rgba[4 * i + 3], 255);
}

TEST(Rasterize, BackgroundFillsUncoveredPixels) {
  const Image src = testImage(20, 20);
  Points V(3, 2);
  V << 0, 0, 5, 0, 0, 5;
  RasterOptions opt;
  opt.background = {10, 20, 30, 255};
  const Image out = rasterizeMesh(src, V, V, {{0, 1, 2}}, 20, 20, opt);
  EXPECT_EQ(out.at(19, 19), opt.background);
  EXPECT_EQ(out.at(1, 1), src.at(1, 1));
}

TEST(Rasterize, ResultIsIdenticalForOneAndTwoThreads) {
  const Image src = testImage(120, 100);
  Points V;
  Triangles T;
  gridMesh(120, 100, 20, V, T);
  Points F = V;
  for (Index v = 0; v < V.rows(); ++v) F.row(v) += Eigen::RowVector2d(8 * std::sin(V(v, 1) / 9), 30 * std::cos(V(v, 0) / 23));
  Image one, two;
  {
    ScopedThreadCount t(1);
    one = rasterizeMesh(src, V, F, T, 120, 100);
  }
  {
    ScopedThreadCount t(2);
    two = rasterizeMesh(src, V, F, T, 120, 100);
  }
  EXPECT_EQ(one.rgba, two.rgba);
}

TEST(Rasterize, PolygonMaskAndPsnr) {
  Points C(4, 2);
  C << 1.5, 1.5, 5.5, 1.5, 5.5, 4.5, 1.5, 4.5;
  const auto mask = polygonMask(C, 8, 8);
  int inside = 0;
  for (auto v : mask) inside += v ? 1 : 0;
  EXPECT_EQ(inside, 4 * 3);  // x 2..5, y 2..4
  EXPECT_EQ(mask[2 * 8 + 2], 255);
  EXPECT_EQ(mask[1 * 8 + 1], 0);
  const Image a = testImage(8, 8);
  EXPECT_TRUE(std::isinf(psnr(a, a)));
  EXPECT_THROW(psnr(a, testImage(9, 8)), std::invalid_argument);
}

TEST(Rasterize, RejectsBadInput) {
  const Image src = testImage(8, 8);
  Points V(3, 2);
  V << 0, 0, 5, 0, 0, 5;
  EXPECT_THROW(rasterizeMesh(src, V, Points(2, 2), {{0, 1, 2}}, 8, 8), std::invalid_argument);
  EXPECT_THROW(rasterizeMesh(src, V, V, {{0, 1, 3}}, 8, 8), std::invalid_argument);
  RasterOptions opt;
  opt.supersample = 3;
  EXPECT_THROW(rasterizeMesh(src, V, V, {{0, 1, 2}}, 8, 8, opt), std::invalid_argument);
  Image broken = src;
  broken.rgba.pop_back();
  EXPECT_THROW(rasterizeMesh(broken, V, V, {{0, 1, 2}}, 8, 8), std::invalid_argument);
}

}  // namespace
}  // namespace kc
