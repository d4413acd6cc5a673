#pragma once
/// Image files ↔ the core's plain RGBA image (OpenCV lives only in app/src).

#include <string>

#include "kc/app/image_header.h"
#include "kc/core/rasterize.h"

namespace kc::app {

/// How loadImage lays out a picture whose header says how it is shown (ImageHeader::orientation:
/// a phone's photo stored sideways with an Exif Orientation, a scan with a TIFF Orientation tag).
enum class ImageOrientation {
  Upright,   ///< Turned and mirrored as the header says: as viewers and painting programs show it.
  AsStored,  ///< The decoder's rows and columns (how sessions written before kcwarp read the
             ///< orientation saw the picture: Session::imageUpright false).
};

/// Loads a PNG, JPEG, BMP, TIFF, WebP or PNM file as RGBA8: grey, BGR and BGRA, 8 or 16 bit, are
/// converted; images without alpha get alpha 255; a JPEG's Exif orientation and a TIFF's
/// Orientation tag are applied unless `orientation` is AsStored. The file is read whole (a regular
/// file of at most kMaxImageFileBytes), its header checked against kMaxImageSide and
/// kMaxImagePixels before a pixel is decoded, then decoded from memory. Throws InputError (a std::runtime_error) naming
/// the file when it is missing, too large, or cannot be decoded.
Image loadImage(const std::string& path, ImageOrientation orientation = ImageOrientation::Upright);

/// `stored` turned and mirrored as Exif orientation `orientation` (1–8, ImageHeader::orientation)
/// says it is shown: the result is uprightWidth × uprightHeight, and its pixel (x, y) is stored's
/// pixel at (x, y) for 1, (W−1−x, y) for 2, (W−1−x, H−1−y) for 3, (x, H−1−y) for 4, (y, x) for 5,
/// (y, H−1−x) for 6, (W−1−y, H−1−x) for 7 and (W−1−y, x) for 8 (W × H the stored size).
/// std::invalid_argument for an orientation outside 1–8.
Image orientImage(const Image& stored, int orientation);

/// The format, size and orientation of an image file from its header, checked like loadImage but
/// without decoding; InputError naming the file otherwise.
ImageHeader readImageFileHeader(const std::string& path);
/// The header of the image file content `bytes` (read from `path`), checked against the limits.
ImageHeader checkImageFile(const std::string& bytes, const std::string& path);

/// PNG compression (zlib level) when none is asked for: the fastest level that compresses (with
/// the Up filter, in parallel strips, app/src/png_codec.h). Higher levels cost several times the
/// time for files a few percent (photos) to tens of percent (smooth pictures) smaller
/// (docs/notes/cli-stats-demo-png.md has the measurements).
inline constexpr int kDefaultPngCompression = 1;

/// Saves an RGBA8 image; the format follows the extension (.png keeps alpha: RGBA always, .jpg/.jpeg
/// drop it).
/// `pngCompression` 0..9 as in encodeImage (ignored for JPEG).
/// Atomic: encoded in memory, written to a temporary file in the same folder, then renamed.
/// Throws InputError naming the file on an unknown extension or a failed write.
void saveImage(const std::string& path, const Image& image, int pngCompression = kDefaultPngCompression);

/// The lower-case extension of `path` when kcwarp can write it (".png", ".jpg", ".jpeg"); InputError
/// naming the file otherwise.
std::string imageExtension(const std::string& path);

/// The image encoded as `ext` (".png", ".jpg") in memory. PNG: `pngCompression` is the zlib level
/// 0..9 (0 stores, 1 fastest, 9 smallest and slowest). std::invalid_argument on an unknown
/// extension or a level outside 0..9.
std::string encodeImage(const Image& image, const std::string& ext, int pngCompression = kDefaultPngCompression);

}  // namespace kc::app
