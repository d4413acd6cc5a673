#include "kc/app/image_io.h"

#include <algorithm>
#include <sstream>
#include <iostream>
#include <cctype>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "image_codecs.h"
#include "jpeg_codec.h"
#include "kc/app/errors.h"
#include "kc/app/file_io.h"
#include "kc/app/image_header.h"
#include "kc/app/limits.h"
#include "kc/core/parallel.h"
#include "png_codec.h"

namespace kc::app {
namespace {

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

}  // namespace

ImageHeader checkImageFile(const std::string& bytes, const std::string& path) {
  ImageHeader header;
  std::string problem;
  if (!readImageHeader(bytes, header, problem)) throw InputError(path, problem);
  checkImageSize(header.width, header.height, path, header.format + " image");
  return header;
}

ImageHeader readImageFileHeader(const std::string& path) {
  return checkImageFile(readTextFile(path, kMaxImageFileBytes), path);
}

namespace {

/// Redirects std::cerr into `text` while alive: OpenCV's imdecode reports a failed decode there
/// (its own line before kcwarp's) instead of throwing.
class CerrCapture {
 public:
  explicit CerrCapture(std::string& text) : m_text(text), m_old(std::cerr.rdbuf(m_buffer.rdbuf())) {}
  ~CerrCapture() {
    std::cerr.rdbuf(m_old);
    m_text = m_buffer.str();
  }
  CerrCapture(const CerrCapture&) = delete;
  CerrCapture& operator=(const CerrCapture&) = delete;

 private:
  std::string& m_text;
  std::ostringstream m_buffer;
  std::streambuf* m_old;
};

/// ": <reason>" from an OpenCV error line ("... error: (-2:Unspecified error) <reason> in function
/// '...'"), at most 120 characters on one line; "" when there is none.
std::string decoderReason(const std::string& said) {
  const std::size_t open = said.find("error: (");
  if (open == std::string::npos) return "";
  const std::size_t close = said.find(") ", open);
  if (close == std::string::npos) return "";
  std::string reason = said.substr(close + 2, said.find(" in function", close) - (close + 2));
  for (char& c : reason)
    if (c == '\n' || c == '\r') c = ' ';
  if (reason.size() > 120) reason = reason.substr(0, 117) + "...";
  return reason.empty() ? "" : ": " + reason;
}

}  // namespace

Image orientImage(const Image& stored, int orientation) {
  if (orientation < 1 || orientation > 8) throw std::invalid_argument("image orientation must be 1..8, got " + std::to_string(orientation));
  if (orientation == 1) return stored;
  const int W = stored.width, H = stored.height;
  const bool swap = orientation >= 5;
  Image out(swap ? H : W, swap ? W : H);
  // The stored pixel shown at (x, y), for the table in the header.
  auto source = [&](int x, int y) -> std::pair<int, int> {
    switch (orientation) {
      case 2: return {W - 1 - x, y};
      case 3: return {W - 1 - x, H - 1 - y};
      case 4: return {x, H - 1 - y};
      case 5: return {y, x};
      case 6: return {y, H - 1 - x};
      case 7: return {W - 1 - y, H - 1 - x};
      default: return {W - 1 - y, x};  // 8
    }
  };
  // In tiles of kTile × kTile: a turn reads the stored picture down its columns, and a tile's
  // columns stay in the cache while it is copied.
  constexpr int kTile = 32;
  const int tilesY = (out.height + kTile - 1) / kTile;
  parallelFor(tilesY, [&](Index ty) {
    const int y0 = int(ty) * kTile, y1 = std::min(out.height, y0 + kTile);
    for (int x0 = 0; x0 < out.width; x0 += kTile) {
      const int x1 = std::min(out.width, x0 + kTile);
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
          const auto [sx, sy] = source(x, y);
          std::copy_n(stored.pixel(sx, sy), 4, out.pixel(x, y));
        }
    }
  }, 1);
  return out;
}

Image loadImage(const std::string& path, ImageOrientation orientation) {
  const std::string bytes = readTextFile(path, kMaxImageFileBytes);
  const ImageHeader header = checkImageFile(bytes, path);
  if (header.format == "PNG") {  // libpng directly: OpenCV's codecs are loaded only for other formats
    Image img;
    std::string problem;
    if (!detail::decodePng(bytes, img, problem)) throw InputError(path, "cannot decode the PNG image: " + problem);
    return img;  // its size is the IHDR's, which checkImageFile read and checked
  }
  if (header.format == "JPEG") {  // libjpeg directly, its warnings (truncated or corrupt data) refused
    Image img;
    std::string problem;
    if (!detail::decodeJpeg(bytes, int(header.width), int(header.height), img, problem))
      throw InputError(path, "cannot decode the JPEG image: " + problem);
    return orientation == ImageOrientation::Upright ? orientImage(img, header.orientation) : img;
  }
  cv::Mat m;
  std::string said;  // what OpenCV's decoder wrote to std::cerr, kept for kcwarp's one line
  try {
    const CerrCapture capture(said);
    m = detail::imdecode(cv::Mat(1, static_cast<int>(bytes.size()), CV_8U, const_cast<char*>(bytes.data())), cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    throw InputError(path, "cannot decode the " + header.format + " image: " + e.msg);
  }
  if (m.empty())
    throw InputError(path, "cannot decode the " + header.format + " image (corrupt or truncated)" + decoderReason(said));
  // OpenCV's decoders turn a TIFF by its Orientation tag (ImageHeader::orientation; 1 for the others).
  if (m.cols != header.uprightWidth() || m.rows != header.uprightHeight())
    throw InputError(path, "the " + header.format + " header says " + std::to_string(header.uprightWidth()) + "x" +
                               std::to_string(header.uprightHeight()) + " but the pixels are " + std::to_string(m.cols) + "x" +
                               std::to_string(m.rows));
  if (m.depth() == CV_16U) m.convertTo(m, CV_8U, 1.0 / 257.0);
  else if (m.depth() != CV_8U) throw InputError(path, "unsupported pixel depth (need 8 or 16 bit)");
  cv::Mat rgba;
  switch (m.channels()) {
    case 1: cv::cvtColor(m, rgba, cv::COLOR_GRAY2RGBA); break;
    case 3: cv::cvtColor(m, rgba, cv::COLOR_BGR2RGBA); break;
    case 4: cv::cvtColor(m, rgba, cv::COLOR_BGRA2RGBA); break;
    default: throw InputError(path, "unsupported channel count " + std::to_string(m.channels()));
  }
  Image img(rgba.cols, rgba.rows);
  for (int y = 0; y < rgba.rows; ++y) std::copy_n(rgba.ptr<std::uint8_t>(y), std::size_t(rgba.cols) * 4, img.pixel(0, y));
  if (orientation == ImageOrientation::Upright || header.orientation == 1) return img;
  const int o = header.orientation;
  return orientImage(img, o == 6 ? 8 : o == 8 ? 6 : o);  // back as stored: 6 and 8 undo each other, the rest undo themselves
}

std::string encodeImage(const Image& image, const std::string& ext, int pngCompression) {
  if (pngCompression < 0 || pngCompression > 9)
    throw std::invalid_argument("PNG compression must be 0..9, got " + std::to_string(pngCompression));
  image.validate();
  if (image.empty()) throw std::invalid_argument("cannot encode an empty image");
  if (ext == ".png") return detail::encodePng(image, pngCompression);
  if (ext != ".jpg" && ext != ".jpeg") throw std::invalid_argument("unknown image format '" + ext + "' (use .png or .jpg)");
  return detail::encodeJpeg(image, 92);
}

std::string imageExtension(const std::string& path) {
  const std::string ext = lowerExtension(path);
  if (ext != ".png" && ext != ".jpg" && ext != ".jpeg")
    throw InputError(path, "unknown image format '" + ext + "' (use .png or .jpg)");
  return ext;
}

void saveImage(const std::string& path, const Image& image, int pngCompression) {
  const std::string ext = imageExtension(path);
  std::string bytes;
  try {
    bytes = encodeImage(image, ext, pngCompression);
  } catch (const std::invalid_argument& e) {
    throw InputError(path, e.what());
  }
  writeFileAtomic(path, bytes);
}

}  // namespace kc::app
