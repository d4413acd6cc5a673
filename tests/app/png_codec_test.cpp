// kcwarp's PNG reader (libpng, app/src/png_codec.cpp) against OpenCV's decoder, which kcwarp used
// before, on every PNG kind: the same RGBA8 pixels. Palette, tRNS, low-bit grey and interlaced
// files are written here with libpng itself (OpenCV cannot write them). kcwarp's writer (zlib, in
// parallel strips) against libpng's and OpenCV's decoders and against zlib itself.
#include <gtest/gtest.h>
#include <png.h>
#include <zlib.h>

#include <algorithm>
#include <csetjmp>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <stdexcept>

#include "cli_run.h"
#include "kc/app/image_io.h"
#include "kc/core/parallel.h"

namespace kc::app {
namespace {

namespace fs = std::filesystem;

fs::path freshDir(const std::string& name) { return test::scratchDir("png_codec_" + name); }

/// What kcwarp produced before it read PNG itself: OpenCV's IMREAD_UNCHANGED, 16 bit scaled by
/// 1/257, then grey/BGR/BGRA to RGBA.
Image viaOpenCv(cv::Mat m) {
  if (m.empty()) throw std::runtime_error("OpenCV cannot decode the PNG");
  if (m.depth() == CV_16U) m.convertTo(m, CV_8U, 1.0 / 257.0);
  cv::Mat rgba;
  const int code = m.channels() == 1 ? cv::COLOR_GRAY2RGBA : m.channels() == 3 ? cv::COLOR_BGR2RGBA : cv::COLOR_BGRA2RGBA;
  cv::cvtColor(m, rgba, code);
  Image img(rgba.cols, rgba.rows);
  for (int y = 0; y < rgba.rows; ++y) std::copy_n(rgba.ptr<std::uint8_t>(y), std::size_t(rgba.cols) * 4, img.pixel(0, y));
  return img;
}
Image viaOpenCv(const fs::path& file) { return viaOpenCv(cv::imread(file.string(), cv::IMREAD_UNCHANGED)); }

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

/// PNG content decoded by libpng's simplified API (not kcwarp's reader) to RGBA8.
Image viaLibpng(const std::string& bytes) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&image, bytes.data(), bytes.size()))
    throw std::runtime_error(std::string("libpng cannot read the PNG: ") + image.message);
  image.format = PNG_FORMAT_RGBA;
  Image out(int(image.width), int(image.height));
  const bool read = png_image_finish_read(&image, nullptr, out.rgba.data(), 0, nullptr) != 0;
  png_image_free(&image);
  if (!read) throw std::runtime_error(std::string("libpng cannot decode the PNG: ") + image.message);
  return out;
}

cv::Mat openCvDecode(const std::string& bytes) {
  return cv::imdecode(cv::Mat(1, int(bytes.size()), CV_8U, const_cast<char*>(bytes.data())), cv::IMREAD_UNCHANGED);
}

/// Colour ramps with noise. Opaque: every alpha 255; otherwise about one pixel in eleven gets an
/// alpha from 0 to 255 (pixel (0, 0) among them, with alpha 0).
Image testPicture(int w, int h, bool opaque, unsigned seed) {
  Image img(w, h);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> noise(-6, 6);
  const auto level = [&](int v) { return std::uint8_t(std::clamp(v + noise(rng), 0, 255)); };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = img.pixel(x, y);
      p[0] = level(255 * x / std::max(1, w - 1));
      p[1] = level(255 * y / std::max(1, h - 1));
      p[2] = level((x / 5 + y / 3) % 2 ? 200 : 40);
      p[3] = opaque || (7 * x + 3 * y) % 11 ? 255 : std::uint8_t((x * 13 + y * 7) % 256);
    }
  return img;
}

TEST(PngCodec, WrittenFilesDecodeInLibpngAndOpenCvToTheSamePixelsAtEverySizeAndLevel) {
  // 333×1000: 3 strips of about 512 KB, the last one shorter; 70001×3: 1 row per strip (the
  // window primed from inside the row above).
  struct Size {
    int w, h;
  };
  for (const Size size : {Size{1, 1}, Size{1, 9}, Size{9, 1}, Size{3, 5}, Size{37, 23}, Size{333, 1000}, Size{70001, 3}})
    for (const bool opaque : {true, false}) {
      const Image img = testPicture(size.w, size.h, opaque, unsigned(size.w + size.h));
      for (int level = 0; level <= 9; ++level) {
        SCOPED_TRACE(std::to_string(size.w) + "x" + std::to_string(size.h) + (opaque ? " opaque" : " transparent") +
                     " level " + std::to_string(level));
        const std::string bytes = encodeImage(img, ".png", level);
        ASSERT_GT(bytes.size(), 33u);
        EXPECT_EQ(int(std::uint8_t(bytes[25])), 6);  // IHDR colour type: RGBA, opaque or not (the `warp` contract)
        EXPECT_EQ(maxDifference(viaLibpng(bytes), img), 0);
        const cv::Mat m = openCvDecode(bytes);
        ASSERT_FALSE(m.empty());
        EXPECT_EQ(m.channels(), 4);
        EXPECT_EQ(maxDifference(viaOpenCv(m), img), 0);
      }
    }
}

TEST(PngCodec, WrittenFilesReadBackWithOpenCvImreadAndKcwarp) {
  const fs::path dir = freshDir("write");
  for (const bool opaque : {true, false}) {
    const Image img = testPicture(61, 29, opaque, 3);
    for (int level : {0, 1, 6, 9}) {
      const fs::path file = dir / (std::to_string(level) + (opaque ? "o" : "t") + ".png");
      saveImage(file.string(), img, level);
      EXPECT_EQ(maxDifference(viaOpenCv(file), img), 0) << "level " << level;
      EXPECT_EQ(maxDifference(loadImage(file.string()), img), 0) << "level " << level;
    }
  }
}

struct Chunk {
  std::string type, data;
};

std::uint32_t bigEndian32(const std::string& bytes, std::size_t at) {
  std::uint32_t v = 0;
  for (int k = 0; k < 4; ++k) v = (v << 8) | std::uint8_t(bytes[at + std::size_t(k)]);
  return v;
}

/// The chunks of PNG content, each CRC checked.
std::vector<Chunk> pngChunks(const std::string& png) {
  std::vector<Chunk> out;
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  std::size_t at = 8;
  while (at + 12 <= png.size()) {
    const std::uint32_t n = bigEndian32(png, at);
    if (at + 12 + n > png.size()) break;
    out.push_back({png.substr(at + 4, 4), png.substr(at + 8, n)});
    const uLong crc = crc32(0, reinterpret_cast<const Bytef*>(png.data() + at + 4), uInt(n + 4));
    EXPECT_EQ(crc, bigEndian32(png, at + 8 + n)) << "CRC of chunk " << out.size() << " (" << out.back().type << ")";
    at += 12 + n;
  }
  EXPECT_EQ(at, png.size()) << "bytes after the last whole chunk";
  return out;
}

TEST(PngCodec, IdatChunksHoldOneZlibStreamOfUpFilteredRowsAsSmallAsOneDeflateCall) {
  for (const bool opaque : {true, false})
    for (int level : {1, 6, 9}) {
      SCOPED_TRACE(std::string(opaque ? "opaque" : "transparent") + " level " + std::to_string(level));
      const Image img = testPicture(333, 1000, opaque, 5);
      const std::string png = encodeImage(img, ".png", level);
      const std::vector<Chunk> chunks = pngChunks(png);
      ASSERT_GE(chunks.size(), 3u);
      EXPECT_EQ(chunks.front().type, "IHDR");
      EXPECT_EQ(chunks.back().type, "IEND");
      std::string stream;
      int idat = 0;
      for (const Chunk& c : chunks)
        if (c.type == "IDAT") stream += c.data, ++idat;
      EXPECT_GE(idat, 2);  // strips compressed apart
      // One zlib stream (uncompress checks its Adler-32) of exactly the filtered rows.
      const std::size_t channels = 4, rowBytes = 1 + channels * std::size_t(img.width);
      std::string rows(rowBytes * std::size_t(img.height) + 1, '\0');
      uLongf n = uLongf(rows.size());
      ASSERT_EQ(uncompress(reinterpret_cast<Bytef*>(rows.data()), &n, reinterpret_cast<const Bytef*>(stream.data()),
                           uLong(stream.size())),
                Z_OK);
      ASSERT_EQ(n, rowBytes * std::size_t(img.height));
      int wrong = 0;
      for (int y = 0; y < img.height; ++y) {
        const char* row = rows.data() + std::size_t(y) * rowBytes;
        wrong += row[0] != (y == 0 ? 0 : 2);  // None for the first row, Up for the others
        for (int x = 0; x < img.width; ++x)
          for (std::size_t c = 0; c < channels; ++c)
            wrong += std::uint8_t(row[1 + channels * std::size_t(x) + c]) !=
                     std::uint8_t(img.pixel(x, y)[c] - (y > 0 ? img.pixel(x, y - 1)[c] : 0));
      }
      EXPECT_EQ(wrong, 0);
      // Compressed apart, the strips are within 1% of one deflate call over the same rows.
      std::string single(compressBound(n), '\0');
      uLongf singleSize = uLongf(single.size());
      ASSERT_EQ(compress2(reinterpret_cast<Bytef*>(single.data()), &singleSize, reinterpret_cast<const Bytef*>(rows.data()),
                          n, level),
                Z_OK);
      EXPECT_LE(double(stream.size()), 1.01 * double(singleSize)) << stream.size() << " against " << singleSize;
    }
}

TEST(PngCodec, WrittenBytesDoNotDependOnTheThreadCount) {
  const Image img = testPicture(333, 1000, false, 9);
  std::string bytes[3];
  for (int threads : {1, 2, 3}) {
    ScopedThreadCount scoped(threads);
    bytes[threads - 1] = encodeImage(img, ".png", 1);
  }
  EXPECT_EQ(bytes[0], bytes[1]);
  EXPECT_EQ(bytes[0], bytes[2]);
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
