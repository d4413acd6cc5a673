#include "kc/app/image_header.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "kc/app/errors.h"
#include "kc/app/image_io.h"
#include "kc/app/limits.h"

namespace kc::app {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Every seed of the header fuzz target is a 5×3 picture written by another program (ImageMagick,
// or by hand for big-endian TIFF and ASCII PPM) but the JPEG variants (progressive 24×16, grey 20×12,
// CMYK 16×16): the header must say so, and OpenCV must agree.
TEST(ImageHeader, ReadsTheSizeOfEveryFormat) {
  const fs::path dir = fs::path(KC_SOURCE_DIR) / "tests/fuzz/corpus/image_header";
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    ImageHeader h;
    std::string problem;
    ASSERT_TRUE(readImageHeader(slurp(e.path()), h, problem)) << e.path() << ": " << problem;
    const std::string stem = e.path().stem().string();
    const int w = stem == "seed-progressive" ? 24 : stem == "seed-grey" ? 20 : stem == "seed-cmyk" ? 16 : 5;
    const int hh = stem == "seed-progressive" ? 16 : stem == "seed-grey" ? 12 : stem == "seed-cmyk" ? 16 : 3;
    EXPECT_EQ(h.width, w) << e.path();
    EXPECT_EQ(h.height, hh) << e.path();
    const std::string ext = e.path().extension().string();
    const char* expected = ext == ".png" ? "PNG" : ext == ".jpg" ? "JPEG" : ext == ".bmp" ? "BMP" : ext == ".tiff" ? "TIFF"
                           : ext == ".webp" ? "WebP" : "PNM";
    EXPECT_EQ(h.format, expected) << e.path();
    if (e.path().filename() != "seed-be.tiff") {  // a header without pixels
      const Image img = loadImage(e.path().string());
      EXPECT_EQ(img.width, w) << e.path();
      EXPECT_EQ(img.height, hh) << e.path();
    }
    ++files;
  }
  EXPECT_GE(files, 10);
}

TEST(ImageHeader, RefusesTruncatedAndUnknownData) {
  const std::string png = slurp(fs::path(KC_SOURCE_DIR) / "tests/fuzz/corpus/image_header/seed.png");
  ImageHeader h;
  std::string problem;
  for (std::size_t n = 0; n < 24; ++n) {
    EXPECT_FALSE(readImageHeader(png.substr(0, n), h, problem)) << n;
    EXPECT_FALSE(problem.empty());
  }
  EXPECT_FALSE(readImageHeader("GIF89a....", h, problem));
  EXPECT_NE(problem.find("not an image kcwarp reads"), std::string::npos) << problem;
  EXPECT_FALSE(readImageHeader("P6\n99999999999999 3\n", h, problem));  // more digits than a size has
  const std::string riff("RIFF\x10\0\0\0WEBPVP8 ", 16);  // shorter than a WebP header: refused, not read past its end
  for (std::size_t n = 4; n < riff.size(); ++n) {
    EXPECT_NO_THROW(EXPECT_FALSE(readImageHeader(riff.substr(0, n), h, problem)) << n);
  }
}

TEST(ImageHeader, ImageSizeLimits) {
  EXPECT_NO_THROW(checkImageSize(8192, 8192, "x"));
  EXPECT_THROW(checkImageSize(8193, 8192, "x"), InputError);  // above 64 megapixels
  EXPECT_THROW(checkImageSize(32769, 16, "x"), InputError);
  EXPECT_THROW(checkImageSize(0, 16, "x"), InputError);
  EXPECT_THROW(checkImageSize(4294967552ll, 256, "x"), InputError);
}

}  // namespace
}  // namespace kc::app
