// kcwarp's PNG reader (libpng, app/src/png_codec.cpp) against OpenCV's decoder, which kcwarp used
// before, on every PNG kind: the same RGBA8 pixels. Palette, tRNS, low-bit grey and interlaced
// files are written here with libpng itself (OpenCV cannot write them).
#include <gtest/gtest.h>
#include <png.h>

#include <csetjmp>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <stdexcept>

#include "cli_run.h"
#include "kc/app/image_io.h"

namespace kc::app {
namespace {

namespace fs = std::filesystem;

fs::path freshDir(const std::string& name) { return test::scratchDir("png_codec_" + name); }

/// What kcwarp produced before it read PNG itself: OpenCV's IMREAD_UNCHANGED, 16 bit scaled by
/// 1/257, then grey/BGR/BGRA to RGBA.
Image viaOpenCv(const fs::path& file) {
  cv::Mat m = cv::imread(file.string(), cv::IMREAD_UNCHANGED);
  if (m.empty()) throw std::runtime_error("OpenCV cannot read " + file.string());
  if (m.depth() == CV_16U) m.convertTo(m, CV_8U, 1.0 / 257.0);
  cv::Mat rgba;
  const int code = m.channels() == 1 ? cv::COLOR_GRAY2RGBA : m.channels() == 3 ? cv::COLOR_BGR2RGBA : cv::COLOR_BGRA2RGBA;
  cv::cvtColor(m, rgba, code);
  Image img(rgba.cols, rgba.rows);
  for (int y = 0; y < rgba.rows; ++y) std::copy_n(rgba.ptr<std::uint8_t>(y), std::size_t(rgba.cols) * 4, img.pixel(0, y));
  return img;
}

/// The largest per-channel difference; -1 when the sizes differ.
int maxDifference(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height) return -1;
  int worst = 0;
  for (std::size_t k = 0; k < a.rgba.size(); ++k) worst = std::max(worst, std::abs(int(a.rgba[k]) - int(b.rgba[k])));
  return worst;
}

cv::Mat randomMat(int rows, int cols, int type, unsigned seed) {
  cv::Mat m(rows, cols, type);
  cv::theRNG().state = seed;
  cv::randu(m, cv::Scalar::all(0), cv::Scalar::all(CV_MAT_DEPTH(type) == CV_16U ? 65536 : 256));
  return m;
}

TEST(PngCodec, EveryOpenCvWrittenKindDecodesAsOpenCvDecodesIt) {
  const fs::path dir = freshDir("kinds");
  struct Kind {
    const char* name;
    int type;
  };
  for (const Kind& kind : {Kind{"grey8", CV_8UC1}, Kind{"grey16", CV_16UC1}, Kind{"bgr8", CV_8UC3}, Kind{"bgr16", CV_16UC3},
                           Kind{"bgra8", CV_8UC4}, Kind{"bgra16", CV_16UC4}}) {
    const fs::path file = dir / (std::string(kind.name) + ".png");
    ASSERT_TRUE(cv::imwrite(file.string(), randomMat(37, 53, kind.type, 7)));
    const Image mine = loadImage(file.string());
    EXPECT_EQ(maxDifference(mine, viaOpenCv(file)), 0) << kind.name;
  }
  // Every 16-bit value scales exactly as OpenCV's convertTo(1/257) rounds it.
  cv::Mat ramp(256, 256, CV_16UC1);
  for (int k = 0; k < 65536; ++k) ramp.at<std::uint16_t>(k / 256, k % 256) = std::uint16_t(k);
  ASSERT_TRUE(cv::imwrite((dir / "ramp16.png").string(), ramp));
  EXPECT_EQ(maxDifference(loadImage((dir / "ramp16.png").string()), viaOpenCv(dir / "ramp16.png")), 0);
}

/// Writes a PNG with libpng: `rows` are packed rows in the given colour type and bit depth.
void writeWithLibpng(const fs::path& file, int w, int h, int colour, int depth, bool interlaced,
                     std::vector<std::vector<png_byte>>& rows, const std::vector<png_color>& palette = {},
                     const std::vector<png_byte>& alphas = {}, const png_color_16* greyKey = nullptr) {
  FILE* f = std::fopen(file.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  std::vector<png_bytep> pointers;
  for (auto& r : rows) pointers.push_back(r.data());
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    std::fclose(f);
    FAIL() << "libpng could not write the test file";
    return;
  }
  png_init_io(png, f);
  png_set_IHDR(png, info, png_uint_32(w), png_uint_32(h), depth, colour,
               interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  if (!palette.empty()) png_set_PLTE(png, info, palette.data(), int(palette.size()));
  if (!alphas.empty()) png_set_tRNS(png, info, alphas.data(), int(alphas.size()), nullptr);
  if (greyKey) png_set_tRNS(png, info, nullptr, 0, greyKey);
  png_write_info(png, info);
  png_write_image(png, pointers.data());
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(f);
}

TEST(PngCodec, PaletteTransparencyLowBitGreyAndInterlacedFilesGiveTheirPixels) {
  const fs::path dir = freshDir("libpng");
  const int w = 19, h = 11;
  // Palette of 4 colours, the second half-transparent: 2 bits per pixel.
  const std::vector<png_color> palette = {{10, 20, 30}, {200, 100, 50}, {0, 255, 0}, {255, 255, 255}};
  const std::vector<png_byte> alphas = {255, 128};  // entries past the list are opaque
  std::vector<std::vector<png_byte>> rows(h, std::vector<png_byte>((w * 2 + 7) / 8, 0));
  auto index = [](int x, int y) { return (x + 2 * y) % 4; };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) rows[y][x / 4] |= png_byte(index(x, y) << (6 - 2 * (x % 4)));
  writeWithLibpng(dir / "palette.png", w, h, PNG_COLOR_TYPE_PALETTE, 2, /*interlaced=*/true, rows, palette, alphas);
  const Image p = loadImage((dir / "palette.png").string());
  ASSERT_EQ(p.width, w);
  ASSERT_EQ(p.height, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int i = index(x, y);
      const Rgba expected{palette[i].red, palette[i].green, palette[i].blue, std::uint8_t(i < 2 ? alphas[i] : 255)};
      ASSERT_EQ(p.at(x, y), expected) << x << "," << y;
    }

  // 1-bit grey with a transparent colour key (black).
  std::vector<std::vector<png_byte>> bits(h, std::vector<png_byte>((w + 7) / 8, 0));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if ((x * y) % 3 == 0) bits[y][x / 8] |= png_byte(0x80 >> (x % 8));
  png_color_16 key{};
  key.gray = 0;
  writeWithLibpng(dir / "bits.png", w, h, PNG_COLOR_TYPE_GRAY, 1, false, bits, {}, {}, &key);
  const Image b = loadImage((dir / "bits.png").string());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool white = (x * y) % 3 == 0;
      ASSERT_EQ(b.at(x, y), white ? (Rgba{255, 255, 255, 255}) : (Rgba{0, 0, 0, 0})) << x << "," << y;
    }

  // Interlaced grey + alpha, 8 bit.
  std::vector<std::vector<png_byte>> ga(h, std::vector<png_byte>(w * 2));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) ga[y][2 * x] = png_byte(x * 13), ga[y][2 * x + 1] = png_byte(y * 23);
  writeWithLibpng(dir / "ga.png", w, h, PNG_COLOR_TYPE_GRAY_ALPHA, 8, true, ga);
  const Image g = loadImage((dir / "ga.png").string());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const auto v = std::uint8_t(x * 13);
      ASSERT_EQ(g.at(x, y), (Rgba{v, v, v, std::uint8_t(y * 23)})) << x << "," << y;
    }
  EXPECT_EQ(maxDifference(g, viaOpenCv(dir / "ga.png")), 0);
}

TEST(PngCodec, WrittenFilesDecodeInOpenCvToTheSamePixels) {
  Image img(61, 29);
  std::mt19937 rng(3);
  for (auto& v : img.rgba) v = std::uint8_t(rng());
  const fs::path dir = freshDir("write");
  for (int level : {0, 1, 6, 9}) {
    const fs::path file = dir / ("l" + std::to_string(level) + ".png");
    saveImage(file.string(), img, level);
    EXPECT_EQ(maxDifference(viaOpenCv(file), img), 0) << "level " << level;
  }
}

TEST(PngCodec, DamagedFilesAreRefusedWithTheFileAndTheReason) {
  const fs::path dir = freshDir("damaged");
  Image img(40, 30);
  for (std::size_t k = 0; k < img.rgba.size(); ++k) img.rgba[k] = std::uint8_t(k * 31);
  const std::string good = encodeImage(img, ".png", 6);
  auto expectRefused = [&](const std::string& name, const std::string& bytes, const std::string& reason) {
    const fs::path file = dir / name;
    std::ofstream(file, std::ios::binary) << bytes;
    try {
      loadImage(file.string());
      ADD_FAILURE() << name << ": no exception";
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(file.string()), std::string::npos) << what;
      EXPECT_NE(what.find(reason), std::string::npos) << what;
    }
  };
  expectRefused("truncated.png", good.substr(0, good.size() / 2), "truncated");
  std::string flipped = good;
  flipped[good.size() / 2] = char(flipped[good.size() / 2] ^ 0x55);  // inside the IDAT stream
  expectRefused("flipped.png", flipped, "cannot decode the PNG image");
}

}  // namespace
}  // namespace kc::app
