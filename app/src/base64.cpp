#include "base64.h"

#include <array>
#include <cstdint>

namespace kc::app::detail {
namespace {

constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

/// Character → 6-bit value, 255 for characters outside the alphabet.
constexpr std::array<std::uint8_t, 256> decodeTable() {
  std::array<std::uint8_t, 256> t{};
  for (auto& v : t) v = 255;
  for (int i = 0; i < 64; ++i) t[static_cast<unsigned char>(kAlphabet[i])] = static_cast<std::uint8_t>(i);
  return t;
}
constexpr std::array<std::uint8_t, 256> kDecode = decodeTable();

}  // namespace

std::string base64Encode(const void* data, std::size_t bytes) {
  const auto* in = static_cast<const unsigned char*>(data);
  std::string out((bytes + 2) / 3 * 4, '=');
  std::size_t o = 0, i = 0;
  for (; i + 3 <= bytes; i += 3) {
    const std::uint32_t v = std::uint32_t(in[i]) << 16 | std::uint32_t(in[i + 1]) << 8 | in[i + 2];
    out[o++] = kAlphabet[v >> 18];
    out[o++] = kAlphabet[(v >> 12) & 63];
    out[o++] = kAlphabet[(v >> 6) & 63];
    out[o++] = kAlphabet[v & 63];
  }
  if (const std::size_t rest = bytes - i; rest > 0) {
    const std::uint32_t v = std::uint32_t(in[i]) << 16 | (rest == 2 ? std::uint32_t(in[i + 1]) << 8 : 0u);
    out[o++] = kAlphabet[v >> 18];
    out[o++] = kAlphabet[(v >> 12) & 63];
    if (rest == 2) out[o++] = kAlphabet[(v >> 6) & 63];
  }
  return out;
}

bool base64Decode(std::string_view text, std::string& out, std::string& problem) {
  if (text.size() % 4 != 0) {
    problem = "its length " + std::to_string(text.size()) + " is not a multiple of 4 (truncated?)";
    return false;
  }
  std::size_t padding = 0;
  while (padding < 2 && padding < text.size() && text[text.size() - 1 - padding] == '=') ++padding;
  const std::size_t start = out.size();
  out.resize(start + base64DecodedSize(text.size(), padding));
  std::size_t o = start;
  const std::size_t end = text.size() - padding;
  std::uint32_t v = 0;
  int bits = 0;
  for (std::size_t i = 0; i < end; ++i) {
    const std::uint8_t d = kDecode[static_cast<unsigned char>(text[i])];
    if (d == 255) {
      problem = "character " + std::to_string(i) + " is not base64 ('" + std::string(1, text[i]) + "')";
      return false;
    }
    v = (v << 6) | d;
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out[o++] = static_cast<char>((v >> bits) & 0xFF);
    }
  }
  if ((v & ((1u << bits) - 1)) != 0) {
    problem = "the bits after the last byte are not zero (not canonical base64)";
    return false;
  }
  return true;
}

}  // namespace kc::app::detail
