// The picture the window draws from (display_texture.h): its size for a screen, and area
// averaging of a picture or a crop of it.
#include <gtest/gtest.h>

#include <random>

#include "kc/core/parallel.h"
#include "kc/ui/display_texture.h"

namespace kc::ui {
namespace {

Image randomImage(int w, int h, unsigned seed, bool opaque = true) {
  Image img(w, h);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> byte(0, 255);
  for (std::size_t k = 0; k < img.rgba.size(); ++k) img.rgba[k] = static_cast<std::uint8_t>(k % 4 == 3 && opaque ? 255 : byte(rng));
  return img;
}

TEST(DisplayTexture, LimitIsTwiceTheFramebufferAtLeast4096AndAtMostTheGpuMaximum) {
  EXPECT_EQ(displayTextureLimit(1400, 900, 16384), 4096);   // a laptop window: the floor
  EXPECT_EQ(displayTextureLimit(3840, 2160, 16384), 7680);  // a 4K window: twice its longest side
  EXPECT_EQ(displayTextureLimit(3840, 2160, 4096), 4096);   // never past GL_MAX_TEXTURE_SIZE
}

TEST(DisplayTexture, SmallPicturesKeepTheirSizeBigOnesScaleTheirLongestSideToTheLimit) {
  EXPECT_EQ(displayTextureSize(4000, 3000, 4096), std::make_pair(4000, 3000));
  EXPECT_EQ(displayTextureSize(20000, 15000, 4096), std::make_pair(4096, 3072));
  EXPECT_EQ(displayTextureSize(3000, 20000, 4096), std::make_pair(614, 4096));
  EXPECT_EQ(displayTextureSize(100000, 10, 4096), std::make_pair(4096, 1));  // at least one texel
}

TEST(ResampleArea, HalvingAveragesEachTwoByTwoBlock) {
  const Image src = randomImage(8, 6, 1);
  const Image out = resampleArea(src, {0, 0, 8, 6}, 4, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x)
      for (int c = 0; c < 4; ++c) {
        const int sum = src.pixel(2 * x, 2 * y)[c] + src.pixel(2 * x + 1, 2 * y)[c] + src.pixel(2 * x, 2 * y + 1)[c] +
                        src.pixel(2 * x + 1, 2 * y + 1)[c];
        EXPECT_NEAR(out.pixel(x, y)[c], sum / 4.0, 0.51) << x << "," << y << " channel " << c;
      }
}

TEST(ResampleArea, FractionalFootprintsKeepThePictureMean) {
  // 7×5 → 3×2: output pixels cut source pixels; each source pixel's area is shared, none lost.
  const Image src = randomImage(7, 5, 2);
  const Image out = resampleArea(src, {0, 0, 7, 5}, 3, 2);
  for (int c = 0; c < 3; ++c) {
    double in = 0.0, got = 0.0;
    for (std::size_t p = 0; p < src.pixelCount(); ++p) in += src.rgba[4 * p + c];
    for (std::size_t p = 0; p < out.pixelCount(); ++p) got += out.rgba[4 * p + c];
    EXPECT_NEAR(got / 6.0, in / 35.0, 0.5) << "channel " << c;
  }
  const Image flat = resampleArea(Image(7, 5, Rgba{10, 200, 30, 255}), {0, 0, 7, 5}, 3, 2);
  for (std::size_t p = 0; p < flat.pixelCount(); ++p) EXPECT_EQ(flat.at(int(p % 3), int(p / 3)), (Rgba{10, 200, 30, 255}));
}

TEST(ResampleArea, TransparentPixelsDoNotDarkenTheirNeighbours) {
  Image src(2, 1, Rgba{0, 0, 0, 0});  // transparent black beside opaque red
  src.pixel(0, 0)[0] = 255;
  src.pixel(0, 0)[3] = 255;
  const Image out = resampleArea(src, {0, 0, 2, 1}, 1, 1);
  EXPECT_EQ(out.at(0, 0), (Rgba{255, 0, 0, 128}));  // half covered, still red (not 128, 0, 0)
}

TEST(ResampleArea, ACropIsTheSameAsResamplingTheCutOutPicture) {
  const Image src = randomImage(40, 30, 3, false);
  const PixelRect crop{7, 5, 21, 17};
  Image cut(crop.width, crop.height);
  for (int y = 0; y < crop.height; ++y)
    for (int x = 0; x < crop.width; ++x) std::copy_n(src.pixel(crop.x0 + x, crop.y0 + y), 4, cut.pixel(x, y));
  EXPECT_EQ(resampleArea(src, crop, 9, 7).rgba, resampleArea(cut, {0, 0, crop.width, crop.height}, 9, 7).rgba);
  const Image opaque = randomImage(40, 30, 3);
  const Image same = resampleArea(opaque, crop, crop.width, crop.height);  // scale 1: the crop itself
  for (int y = 0; y < crop.height; ++y)
    for (int x = 0; x < crop.width; ++x) ASSERT_EQ(same.at(x, y), opaque.at(crop.x0 + x, crop.y0 + y));
}

TEST(ResampleArea, SameResultForOneAndTwoThreads) {
  const Image src = randomImage(301, 203, 4, false);
  Image one, two;
  {
    ScopedThreadCount t(1);
    one = resampleArea(src, {0, 0, 301, 203}, 97, 64);
  }
  {
    ScopedThreadCount t(2);
    two = resampleArea(src, {0, 0, 301, 203}, 97, 64);
  }
  EXPECT_EQ(one.rgba, two.rgba);
}

TEST(ResampleArea, RejectsACropOutsideThePictureAndAnOutputLargerThanTheCrop) {
  const Image src(10, 10);
  EXPECT_THROW(resampleArea(src, {5, 5, 6, 2}, 3, 1), std::invalid_argument);
  EXPECT_THROW(resampleArea(src, {-1, 0, 4, 4}, 2, 2), std::invalid_argument);
  EXPECT_THROW(resampleArea(src, {0, 0, 4, 4}, 5, 2), std::invalid_argument);
  EXPECT_THROW(resampleArea(src, {0, 0, 4, 4}, 0, 2), std::invalid_argument);
}

TEST(DisplayImage, APictureThatFitsIsCopiedABigOneAveraged) {
  const Image small = randomImage(30, 20, 5);
  EXPECT_EQ(displayImage(small, 64).rgba, small.rgba);
  const Image big = randomImage(128, 64, 6);
  const Image shown = displayImage(big, 64);
  EXPECT_EQ(shown.width, 64);
  EXPECT_EQ(shown.height, 32);
  EXPECT_EQ(shown.rgba, resampleArea(big, {0, 0, 128, 64}, 64, 32).rgba);
}

TEST(MipmapLevels, HalveDownToOnePixelAsOpenGLExpects) {
  const Image base = randomImage(37, 10, 7);
  const std::vector<Image> levels = mipmapLevels(base);
  const std::vector<std::pair<int, int>> sizes = {{18, 5}, {9, 2}, {4, 1}, {2, 1}, {1, 1}};
  ASSERT_EQ(levels.size(), sizes.size());
  for (std::size_t k = 0; k < sizes.size(); ++k) EXPECT_EQ(std::make_pair(levels[k].width, levels[k].height), sizes[k]) << k;
  EXPECT_EQ(levels[0].rgba, resampleArea(base, {0, 0, 37, 10}, 18, 5).rgba);
  EXPECT_EQ(levels[2].rgba, resampleArea(levels[1], {0, 0, 9, 2}, 4, 1).rgba);
  EXPECT_TRUE(mipmapLevels(Image(1, 1)).empty());
}

TEST(MipmapLevels, EvenSizesGiveWhatAreaAveragingGives) {
  // Even sides take a faster integer path: the same bytes as resampleArea, transparency included.
  const Image base = randomImage(64, 48, 8, /*opaque=*/false);
  const std::vector<Image> levels = mipmapLevels(base);
  ASSERT_GE(levels.size(), 2u);
  EXPECT_EQ(levels[0].rgba, resampleArea(base, {0, 0, 64, 48}, 32, 24).rgba);
  EXPECT_EQ(levels[1].rgba, resampleArea(levels[0], {0, 0, 32, 24}, 16, 12).rgba);
}

}  // namespace
}  // namespace kc::ui
