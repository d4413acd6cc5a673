#include "kc/app/image_io.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

namespace kc::app {
namespace {

namespace fs = std::filesystem;

fs::path freshDir(const std::string& name) {
  const fs::path dir = fs::path(testing::TempDir()) / ("kc_image_io_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

Image pattern(int w, int h) {
  Image img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = img.pixel(x, y);
      p[0] = std::uint8_t(x * 7), p[1] = std::uint8_t(y * 5), p[2] = std::uint8_t((x ^ y) * 3), p[3] = std::uint8_t(x + y);
    }
  return img;
}

TEST(ImageIo, PngRoundTripKeepsRgba) {
  const fs::path dir = freshDir("png");
  const Image img = pattern(37, 23);
  saveImage((dir / "a.png").string(), img);
  const Image back = loadImage((dir / "a.png").string());
  EXPECT_EQ(back.width, 37);
  EXPECT_EQ(back.height, 23);
  EXPECT_EQ(back.rgba, img.rgba);
  // Channel order on disk is what other programs expect: OpenCV reads red where we wrote red.
  const cv::Mat m = cv::imread((dir / "a.png").string(), cv::IMREAD_UNCHANGED);
  EXPECT_EQ(m.at<cv::Vec4b>(2, 5)[2], img.pixel(5, 2)[0]);
}

TEST(ImageIo, EveryPngCompressionLevelIsLosslessAndLevelsTradeSizeForTime) {
  // A smooth picture with flat regions: what compression should shrink.
  Image img(256, 192);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      std::uint8_t* p = img.pixel(x, y);
      p[0] = std::uint8_t(x), p[1] = std::uint8_t(y), p[2] = std::uint8_t(x < 128 ? 40 : 200), p[3] = 255;
    }
  std::vector<std::size_t> sizes;
  for (int level = 0; level <= 9; ++level) {
    const std::string bytes = encodeImage(img, ".png", level);
    sizes.push_back(bytes.size());
    const cv::Mat m = cv::imdecode(cv::Mat(1, int(bytes.size()), CV_8U, const_cast<char*>(bytes.data())), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(m.type(), CV_8UC4) << "level " << level;  // RGBA even when every alpha is 255
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x)
        for (int c = 0; c < 3; ++c)
          ASSERT_EQ(m.at<cv::Vec4b>(y, x)[2 - c], img.pixel(x, y)[c]) << "level " << level << " at " << x << "," << y;
  }
  EXPECT_GT(sizes[0], std::size_t(img.width) * img.height * 4);  // stored: at least the raw RGBA pixels
  EXPECT_LT(sizes[kDefaultPngCompression] * 4, sizes[0]);     // the fast default still compresses
  EXPECT_LE(sizes[9], sizes[kDefaultPngCompression]);
  EXPECT_THROW(encodeImage(img, ".png", -1), std::invalid_argument);
  EXPECT_THROW(encodeImage(img, ".png", 10), std::invalid_argument);
  const fs::path dir = freshDir("png_level");
  EXPECT_THROW(saveImage((dir / "a.png").string(), img, 10), std::runtime_error);
  EXPECT_FALSE(fs::exists(dir / "a.png"));
}

TEST(ImageIo, JpegDropsAlphaAndIsClose) {
  const fs::path dir = freshDir("jpg");
  Image img(64, 64, Rgba{200, 100, 50, 255});
  saveImage((dir / "a.jpg").string(), img);
  const Image back = loadImage((dir / "a.jpg").string());
  ASSERT_EQ(back.width, 64);
  EXPECT_GT(psnr(back, img), 35.0);
  EXPECT_EQ(back.at(10, 10).a, 255);
}

TEST(ImageIo, GreyAndSixteenBitImagesBecomeRgba) {
  const fs::path dir = freshDir("grey");
  cv::Mat grey(5, 4, CV_8U, cv::Scalar(77));
  cv::imwrite((dir / "g.png").string(), grey);
  const Image g = loadImage((dir / "g.png").string());
  EXPECT_EQ(g.at(3, 4), (Rgba{77, 77, 77, 255}));
  cv::Mat deep(3, 3, CV_16UC3, cv::Scalar(0, 0, 65535));  // BGR: pure red
  cv::imwrite((dir / "d.png").string(), deep);
  EXPECT_EQ(loadImage((dir / "d.png").string()).at(1, 1), (Rgba{255, 0, 0, 255}));
}

TEST(ImageIo, FailedLoadNamesTheFile) {
  const fs::path dir = freshDir("fail");
  const std::string missing = (dir / "missing.png").string();
  try {
    loadImage(missing);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
  const std::string junk = (dir / "junk.png").string();
  std::ofstream(junk) << "not a png";
  try {
    loadImage(junk);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(junk), std::string::npos) << e.what();
  }
}

TEST(ImageIo, SaveIsAtomicAndLeavesNoTemporaryFiles) {
  const fs::path dir = freshDir("atomic");
  const std::string path = (dir / "out.png").string();
  saveImage(path, pattern(8, 8));
  saveImage(path, pattern(9, 9));  // replaces
  EXPECT_EQ(loadImage(path).width, 9);
  int files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1);
  // Failures throw (naming the file) and leave the previous file alone.
  EXPECT_THROW(saveImage((dir / "out.bmpx").string(), pattern(8, 8)), std::runtime_error);
  EXPECT_THROW(saveImage((dir / "nope" / "out.png").string(), pattern(8, 8)), std::runtime_error);
  EXPECT_THROW(saveImage(path, Image()), std::exception);
  EXPECT_EQ(loadImage(path).width, 9);
}

}  // namespace
}  // namespace kc::app
