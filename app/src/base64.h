#pragma once
// Private to kc::app: base64 (RFC 4648, standard alphabet, '=' padding) for the compact weight
// matrices of session files.

#include <cstddef>
#include <string>
#include <string_view>

namespace kc::app::detail {

/// The base64 text of `bytes` bytes at `data`: 4 characters per 3 bytes, the last group padded
/// with '='; length 4·⌈bytes/3⌉.
std::string base64Encode(const void* data, std::size_t bytes);

/// The bytes of base64 `text` appended to `out`. False, with `problem` saying what is wrong (a
/// length that is not a multiple of 4, a character outside the alphabet, misplaced padding), when
/// the text is not canonical base64; `out` is then unspecified.
bool base64Decode(std::string_view text, std::string& out, std::string& problem);

/// The number of bytes base64 text of `length` characters ending in `padding` '=' decodes to.
inline std::size_t base64DecodedSize(std::size_t length, std::size_t padding) { return length / 4 * 3 - padding; }

}  // namespace kc::app::detail
