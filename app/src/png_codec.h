#pragma once
/// PNG ↔ RGBA8. Reading goes through libpng directly; writing is kcwarp's own (zlib, in parallel
/// strips). PNG is kcwarp's own format (examples, exports, heatmaps), and libpng with zlib loads in
/// about a millisecond, where OpenCV's image codecs pull in ~140 shared libraries (0.2 s CPU, 0.5 s
/// wall on a busy machine) on first use: with this, a command or a test that only reads and writes
/// PNG never loads them. JPEG goes through libjpeg (jpeg_codec.h), other formats through OpenCV
/// (image_codecs.h).

#include <string>

#include "kc/core/rasterize.h"

namespace kc::app::detail {

/// Decodes PNG file content `bytes` to RGBA8. Every PNG kind is converted the way OpenCV's
/// IMREAD_UNCHANGED followed by kcwarp's conversion did: palette and grey expand to RGB, a tRNS
/// chunk becomes alpha, images without alpha get alpha 255, 16-bit samples scale to 8 bit
/// (v·255/65535, rounded), interlaced images are de-interlaced; gamma and colour chunks are
/// ignored. A chunk other than IDAT longer than 8 MiB, more than 1000 ancillary chunks or a side
/// beyond kMaxImageSide is refused before it is read into memory. Returns false with `problem` set (libpng's message, e.g. a CRC error or truncated data)
/// when the content cannot be decoded; `out` is then unspecified.
bool decodePng(const std::string& bytes, Image& out, std::string& problem);

/// Encodes an RGBA8 image (non-empty, validated by the caller) as an 8-bit PNG with zlib level
/// `level` (0..9, checked by the caller): colour type RGBA, opaque or not (what `warp` promises in
/// ARCHITECTURE.md); every row filtered with Up (row 0: None), zlib's
/// default strategy. The IDAT stream is one zlib stream made of independent deflate pieces, one per
/// strip of rows (about 512 KB of filtered rows, at least one row), compressed in parallel (kc::parallelFor) and each ended with
/// a full flush so that they concatenate; each piece's window is primed with the 32 KB of filtered
/// rows before it, so the pieces compress nearly as one stream would. Each piece is its own IDAT
/// chunk, the zlib header in the first and the Adler-32 (combined from the pieces') in the last.
/// The bytes do not depend on the thread count. Throws std::runtime_error if zlib fails.
std::string encodePng(const Image& image, int level);

}  // namespace kc::app::detail
