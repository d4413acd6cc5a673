#include "kc/app/image_io.h"

#include <gtest/gtest.h>
#include <sys/resource.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <iterator>
#include <stdexcept>
#include <utility>

#include "bad_files.h"
#include "exif_jpeg.h"
#include "kc/app/errors.h"

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

TEST(ImageIo, JpegIsWrittenByLibjpegAndReadsTheSameInOpenCv) {
  // Odd sizes (the chroma planes are subsampled 2×2) and a smooth picture with an edge.
  Image img(97, 61);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      std::uint8_t* p = img.pixel(x, y);
      p[0] = std::uint8_t(2 * x), p[1] = std::uint8_t(3 * y), p[2] = x > 48 ? 220 : 30, p[3] = 7;  // alpha is dropped
    }
  const std::string bytes = encodeImage(img, ".jpg");
  ASSERT_GT(bytes.size(), 100u);
  EXPECT_EQ(bytes.substr(0, 3), "\xFF\xD8\xFF");
  const fs::path file = freshDir("jpeg_write") / "w.jpg";
  test::writeBytes(file, bytes);
  const Image back = loadImage(file.string());
  ASSERT_EQ(back.width, 97);
  ASSERT_EQ(back.height, 61);
  Image opaque = img;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) opaque.pixel(x, y)[3] = 255;
  EXPECT_GT(psnr(back, opaque), 30.0);
  const cv::Mat cv = cv::imdecode(cv::Mat(1, int(bytes.size()), CV_8U, const_cast<char*>(bytes.data())), cv::IMREAD_COLOR);
  ASSERT_EQ(cv.cols, 97);
  int worst = 0;
  for (int y = 0; y < cv.rows; ++y)
    for (int x = 0; x < cv.cols; ++x)
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(int(cv.at<cv::Vec3b>(y, x)[2 - c]) - int(back.pixel(x, y)[c])));
  EXPECT_LE(worst, 1) << "OpenCV reads kcwarp's JPEG as kcwarp does";
}

TEST(ImageIo, ExifOrientationLaysTheJpegOutAsViewersShowIt) {
  // A phone stores its photo as the sensor saw it and says in the Exif block how to turn it. The
  // layouts below are the Exif specification's (row 0 and column 0 of the stored picture go to the
  // named sides), written out for the quadrant picture: top-left, top-right, bottom-left,
  // bottom-right as shown.
  const fs::path dir = freshDir("exif");
  const std::string stored = encodeImage(test::quadrantPicture(48, 32), ".jpg");
  const char* shown[9] = {"", "RGBW", "GRWB", "WBGR", "BWRG", "RBGW", "BRWG", "WGBR", "GWRB"};
  for (const bool bigEndian : {false, true})
    for (int o = 1; o <= 8; ++o) {
      const fs::path file = dir / (std::to_string(o) + (bigEndian ? "m" : "i") + ".jpg");
      test::writeBytes(file, test::withSegment(stored, test::exifSegment(test::orientationEntry(o, bigEndian), bigEndian)));
      const ImageHeader header = readImageFileHeader(file.string());
      EXPECT_EQ(header.orientation, o);
      EXPECT_EQ(header.width, 48);
      EXPECT_EQ(header.uprightWidth(), o >= 5 ? 32 : 48);
      const Image upright = loadImage(file.string());
      ASSERT_EQ(upright.width, o >= 5 ? 32 : 48) << o;
      ASSERT_EQ(upright.height, o >= 5 ? 48 : 32) << o;
      EXPECT_EQ(test::quadrantLayout(upright), shown[o]) << "orientation " << o << (bigEndian ? " MM" : " II");
      const Image asStored = loadImage(file.string(), ImageOrientation::AsStored);
      ASSERT_EQ(asStored.width, 48);
      EXPECT_EQ(test::quadrantLayout(asStored), "RGBW");
      EXPECT_EQ(orientImage(asStored, o).rgba, upright.rgba);  // the same turn, to the byte
    }
  EXPECT_THROW(orientImage(test::quadrantPicture(4, 4), 9), std::invalid_argument);
}

TEST(ImageIo, ATiffIsLaidOutAsItsOrientationTagSays) {
  // Scanners and cameras write TIFFs stored one way with an Orientation tag (the Exif tag, in the
  // TIFF's own first directory); OpenCV's TIFF decoder turns the pixels by it. The header must say
  // the same size, and AsStored must give the rows and columns as stored.
  const fs::path dir = freshDir("tiff_orientation");
  const Image picture = test::quadrantPicture(48, 32);
  const char* shown[9] = {"", "RGBW", "GRWB", "WBGR", "BWRG", "RBGW", "BRWG", "WGBR", "GWRB"};
  for (int o = 0; o <= 8; ++o) {  // 0: no Orientation tag
    SCOPED_TRACE("orientation " + std::to_string(o));
    const fs::path file = dir / (std::to_string(o) + ".tif");
    test::writeBytes(file, test::orientedTiff(picture, o));
    const ImageHeader header = readImageFileHeader(file.string());
    EXPECT_EQ(header.format, "TIFF");
    EXPECT_EQ(header.orientation, std::max(o, 1));
    EXPECT_EQ(header.width, 48);
    const bool turned = o >= 5;
    const Image upright = loadImage(file.string());
    ASSERT_EQ(upright.width, turned ? 32 : 48);
    ASSERT_EQ(upright.height, turned ? 48 : 32);
    EXPECT_EQ(test::quadrantLayout(upright), shown[std::max(o, 1)]);
    const Image asStored = loadImage(file.string(), ImageOrientation::AsStored);
    ASSERT_EQ(asStored.width, 48);
    EXPECT_EQ(asStored.rgba, picture.rgba) << "the pixels as stored, to the byte";
  }
  // A tiled TIFF with an orientation (OpenCV 4.6 scrambles its tiles) is refused from its header;
  // without one it is not.
  test::writeBytes(dir / "tiled6.tif", test::orientedTiff(picture, 6, true));
  try {
    readImageFileHeader((dir / "tiled6.tif").string());
    ADD_FAILURE() << "a tiled TIFF with orientation 6 was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("tiled6.tif"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("a tiled TIFF turned by its Orientation tag is not supported"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(loadImage((dir / "tiled6.tif").string()), InputError);
  test::writeBytes(dir / "tiled1.tif", test::orientedTiff(picture, 1, true));
  EXPECT_EQ(readImageFileHeader((dir / "tiled1.tif").string()).orientation, 1);
}

TEST(ImageIo, AMalformedExifBlockLeavesThePictureAsStored) {
  // Viewers ignore Exif they cannot read; so does kcwarp: the picture loads, as stored.
  const fs::path dir = freshDir("bad_exif");
  const std::string stored = encodeImage(test::quadrantPicture(48, 32), ".jpg");
  const std::string good = test::exifSegment(test::orientationEntry(6, false), false);
  std::string wrongType = test::orientationEntry(6, false);
  wrongType[2] = '\x04';  // LONG instead of SHORT
  std::string badMagic = good;
  badMagic[4 + 6 + 2] = 'X';
  std::string hugeCount = test::exifSegment("", false);
  hugeCount[4 + 6 + 8] = '\xFF', hugeCount[4 + 6 + 9] = '\xFF';  // 65,535 entries in a 14-byte directory
  std::string farDirectory = good;
  farDirectory[4 + 6 + 4] = '\xF0';  // the directory offset past the block
  const std::string cases[] = {test::exifSegment(test::orientationEntry(0, false), false),
                               test::exifSegment(test::orientationEntry(9, true), true),
                               test::exifSegment(wrongType, false),
                               test::exifSegment("", false),
                               badMagic,
                               hugeCount,
                               farDirectory,
                               good.substr(0, 12)};  // the segment cut short (its length still says more)
  int k = 0;
  for (const std::string& segment : cases) {
    const fs::path file = dir / ("bad" + std::to_string(k++) + ".jpg");
    test::writeBytes(file, test::withSegment(stored, segment));
    ImageHeader header;
    std::string problem;
    const std::string bytes = test::slurpBytes(file);
    if (k == 8) {  // the cut segment: its length runs into the next segment, so the JPEG itself is malformed
      EXPECT_FALSE(readImageHeader(bytes, header, problem));
      EXPECT_EQ(problem, "malformed JPEG: expected a marker");
      continue;
    }
    ASSERT_TRUE(readImageHeader(bytes, header, problem)) << "case " << k - 1 << ": " << problem;
    EXPECT_EQ(header.orientation, 1) << "case " << k - 1;
    const Image img = loadImage(file.string());
    EXPECT_EQ(img.width, 48) << "case " << k - 1;
    EXPECT_EQ(test::quadrantLayout(img), "RGBW") << "case " << k - 1;
  }
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

/// The message of the InputError that loading `bytes` (written to `dir`/`name`) throws, with what
/// was printed on stderr meanwhile; "" when it loads.
std::pair<std::string, std::string> refusal(const fs::path& dir, const std::string& name, const std::string& bytes) {
  std::ofstream(dir / name, std::ios::binary) << bytes;
  testing::internal::CaptureStderr();
  std::string message;
  try {
    loadImage((dir / name).string());
  } catch (const InputError& e) {
    message = e.what();
  }
  return {message, testing::internal::GetCapturedStderr()};
}

std::string fileBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(ImageIo, JpegDecodesLikeOpenCvAndRefusesTruncatedOrLyingFiles) {
  const fs::path dir = freshDir("jpeg_strict");
  const Image img = pattern(320, 320);
  cv::Mat bgr(320, 320, CV_8UC3), grey(320, 320, CV_8U);
  for (int y = 0; y < 320; ++y)
    for (int x = 0; x < 320; ++x) {
      const std::uint8_t* p = img.pixel(x, y);
      bgr.at<cv::Vec3b>(y, x) = cv::Vec3b(p[2], p[1], p[0]);
      grey.at<std::uint8_t>(y, x) = p[0];
    }
  // Good files: the pixels OpenCV's decoder gives, nothing printed.
  for (const auto& [name, mat] : {std::pair{"colour.jpg", bgr}, std::pair{"grey.jpg", grey}}) {
    ASSERT_TRUE(cv::imwrite((dir / name).string(), mat));
    testing::internal::CaptureStderr();
    const Image got = loadImage((dir / name).string());
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
    const cv::Mat ref = cv::imread((dir / name).string(), cv::IMREAD_COLOR);
    ASSERT_EQ(got.width, ref.cols);
    ASSERT_EQ(got.height, ref.rows);
    long differing = 0;
    for (int y = 0; y < ref.rows; ++y)
      for (int x = 0; x < ref.cols; ++x) {
        const cv::Vec3b b = ref.at<cv::Vec3b>(y, x);
        const std::uint8_t* p = got.pixel(x, y);
        differing += p[0] != b[2] || p[1] != b[1] || p[2] != b[0] || p[3] != 255;
      }
    EXPECT_EQ(differing, 0) << name;
  }
  const std::string good = fileBytes(dir / "colour.jpg");

  // Truncated: refused with libjpeg's message in kcwarp's one line, nothing printed by libjpeg.
  for (const std::size_t keep : {good.size() * 2 / 3, good.size() - 2, std::size_t(700)}) {
    const auto [message, printed] = refusal(dir, "cut.jpg", good.substr(0, keep));
    EXPECT_NE(message.find("cut.jpg: cannot decode the JPEG image: "), std::string::npos) << keep << ": " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos);
    EXPECT_EQ(printed, "") << keep;
  }
  // A header claiming 8000x8000 over the 320x320 picture's data.
  std::string lying = good;
  const std::size_t sof = lying.find("\xff\xc0");
  ASSERT_NE(sof, std::string::npos);
  lying.replace(sof + 5, 4, std::string("\x1f\x40\x1f\x40", 4));  // height, width: 8000 (0x1f40)
  const auto [message, printed] = refusal(dir, "lying.jpg", lying);
  EXPECT_NE(message.find("lying.jpg: cannot decode the JPEG image"), std::string::npos) << message;
  EXPECT_EQ(printed, "");
}

TEST(ImageIo, PngChunkClaimingGigabytesIsRefusedWithoutAllocatingThem) {
  const fs::path dir = freshDir("png_chunk");
  // 8 + 25 + 23 = 56 bytes: the text chunk's length field says 0x7ffffff0, its data is 11 bytes.
  const std::string bytes = test::pngTextChunkClaiming(0x7ffffff0u);
  ASSERT_EQ(bytes.size(), 56u);
  struct rusage before{}, after{};
  getrusage(RUSAGE_SELF, &before);
  const auto [message, printed] = refusal(dir, "chunk.png", bytes);
  getrusage(RUSAGE_SELF, &after);
  EXPECT_NE(message.find("chunk.png: cannot decode the PNG image: "), std::string::npos) << message;
  EXPECT_EQ(printed, "");
  EXPECT_LT(after.ru_maxrss - before.ru_maxrss, 64 * 1024) << "peak memory grew by " << (after.ru_maxrss - before.ru_maxrss) << " KiB";
}

}  // namespace
}  // namespace kc::app
