#pragma once
// Test support: corrupt, lying and oversized files of every kind kcwarp reads (sessions, cages,
// pictures), each with a part of the message that must refuse it — the cases of the bad-input
// tests (bad_input_cli_test.cpp, session_test.cpp, image_io_test.cpp) as files, for the tests that
// open them elsewhere (the GUI's).

#include <sys/stat.h>

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli_run.h"

namespace kc::test {

/// Big-endian 32-bit field of a PNG file.
inline std::string pngBe32(std::uint32_t v) { return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)}; }

/// A PNG file chunk: its length field (`claimedLength`), type, data and CRC.
inline std::string pngChunk(const std::string& type, const std::string& data, std::uint32_t claimedLength) {
  const std::string td = type + data;
  std::uint32_t c = 0xFFFFFFFFu;
  for (unsigned char b : td) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return pngBe32(claimedLength) + td + pngBe32(c ^ 0xFFFFFFFFu);
}

/// A small PNG whose header claims width×height RGBA pixels (its data holds a few zero bytes).
inline std::string pngClaiming(std::uint32_t width, std::uint32_t height) {
  const std::string ihdr = pngBe32(width) + pngBe32(height) + std::string("\x08\x06\x00\x00\x00", 5);
  const std::string idat("\x78\x9c\x63\x60\x00\x00\x00\x02\x00\x01", 10);  // zlib stream of a few zero bytes
  return std::string("\x89PNG\r\n\x1a\n", 8) + pngChunk("IHDR", ihdr, 13) + pngChunk("IDAT", idat, 10) + pngChunk("IEND", "", 0);
}

/// A 56-byte PNG of 16×16 RGBA pixels whose text chunk's length field claims `length` bytes (its
/// data is 11 bytes).
inline std::string pngTextChunkClaiming(std::uint32_t length) {
  const std::string ihdr("\x00\x00\x00\x10\x00\x00\x00\x10\x08\x06\x00\x00\x00", 13);
  return std::string("\x89PNG\r\n\x1a\n", 8) + pngChunk("IHDR", ihdr, 13) + pngChunk("tEXt", std::string("Comment\0abc", 11), length);
}

/// Base64 of `bytes` zero bytes.
inline std::string base64OfZeroBytes(std::size_t bytes) {
  std::string b64((bytes + 2) / 3 * 4, 'A');
  if (bytes % 3 == 1) b64.replace(b64.size() - 2, 2, "==");
  if (bytes % 3 == 2) b64.back() = '=';
  return b64;
}

/// A file a loader must refuse, and a part of the message that refuses it.
struct BadFile {
  std::filesystem::path path;
  std::string problem;
};

/// Writes the bad-input cases into `dir` and returns them: corruptions of `session` (a bound kernel
/// session with compact weights, as `kcwarp-cli bind` writes it), of `jpeg` (the bytes of a JPEG
/// picture of 320×320 pixels) and of `png` (any PNG picture's bytes); bad cages; pictures whose
/// headers lie; files that are not regular; a file whose JSON would need more memory to parse than
/// kcwarp allows (160 MB on disk).
inline std::vector<BadFile> writeBadFiles(const std::filesystem::path& dir, const nlohmann::json& session, const std::string& jpeg,
                                          const std::string& png) {
  namespace fs = std::filesystem;
  using nlohmann::json;
  std::vector<BadFile> out;
  auto add = [&](const std::string& name, const std::string& bytes, const std::string& problem) {
    writeText(dir / name, bytes);
    out.push_back({dir / name, problem});
  };
  auto addSession = [&](const std::string& name, const json& j, const std::string& problem) { add(name, j.dump(), problem); };

  // Sessions: out-of-range numbers, corrupt weights, wrong but well-formed content, broken JSON.
  json j = session;
  j["image_size"] = {4294967552ull, 256};
  addSession("image_size_beyond_int.kcw.json", j, "image_size[0] = 4294967552 is out of range");
  j = session;
  j["image_size"] = {20000, 20000};
  addSession("image_size_400mp.kcw.json", j, "megapixels");
  j = session;
  std::string& text = j["weights"]["optimized_b64"]["base64"].get_ref<std::string&>();
  text[text.size() / 2] = '*';
  addSession("weights_not_base64.kcw.json", j, "weights.optimized_b64.base64 is not valid base64");
  j = session;
  std::string& cut = j["weights"]["initial_b64"]["base64"].get_ref<std::string&>();
  cut.resize(cut.size() / 2 / 4 * 4);
  addSession("weights_cut.kcw.json", j, "weights.initial_b64.base64 has");
  j = session;
  std::size_t edge = 0;
  while (j["samples"]["kinds"][edge] != "edge") ++edge;
  j["samples"]["edge_ends"][edge] = {4294967298ull, 1};
  addSession("edge_end_wraps.kcw.json", j, "is out of range");
  j = session;
  j["params"]["heat_iterations"] = 1000000000000ll;
  addSession("heat_iterations.kcw.json", j, "params.heat_iterations");
  j = session;
  json& block = j["weights"]["optimized_b64"];
  block["base64"] = base64OfZeroBytes(block["shape"][0].get<std::size_t>() * block["shape"][1].get<std::size_t>() * 8);
  addSession("weights_all_zero.kcw.json", j, "sums to 0 (partition of unity");
  j = session;
  j["field"] = {{"kind", "mesh"}, {"vertices", j["cage"]["points"]}, {"triangles", {{0, 1, 2}, {0, 2, 3}}}};
  addSession("kernel_with_mesh_field.kcw.json", j, "does not match params.backend");
  std::string nan = session.dump();
  const std::size_t sigma = nan.find("\"sigma\":") + 8;
  nan.replace(sigma, nan.find(',', sigma) - sigma, "NaN");
  add("nan_literal.kcw.json", nan, "malformed JSON");
  const std::string whole = session.dump(1);
  add("truncated.kcw.json", whole.substr(0, whole.size() / 2), "the file looks truncated");
  add("picture.kcw.json", png, "this file is a PNG image, not JSON text");
  std::string huge = R"({"version": 1, "cage": {"points": [[16,16],[80,16],[80,80],[16,80]]}, "junk": [)";
  huge.reserve(huge.size() + 160'000'010);
  for (int i = 0; i < 40'000'000; ++i) huge += "0,0,";
  add("parse_cost.kcw.json", huge + "0]}", "parsing this file would need more than");
  std::string().swap(huge);

  // Cages.
  add("cage_long_string.json",
      "{\"version\": 1, \"points\": [[0, 0], [10, 0], [0, 10]], \"name\": \"" + std::string(100000, 'A'), "malformed JSON at byte");
  add("cage_edge_wraps.json",
      R"({"version":1,"points":[[10,10],[50,10],[50,50],[10,50]],"closed":true,"edges":[[0,1],[1,2],[2,4294967298],[3,0]]})",
      "is out of range");
  add("cage_far.json", R"({"version":1,"points":[[10,10],[1e300,10],[50,50]],"closed":true})", "is out of range");
  // Too large for a cage; File > Open then tries it as a session (whose limit is larger): malformed.
  add("cage_17mb.json", "{", "");
  fs::resize_file(dir / "cage_17mb.json", 17u << 20);  // sparse: costs no disk

  // Pictures.
  add("claims_60000_squared.png", pngClaiming(60000, 60000), "above kcwarp's limit");
  add("claims_20000_squared.png", pngClaiming(20000, 20000), "megapixels");
  add("text.png", "just text, not a picture\n", "not an image kcwarp reads");
  add("chunk_claims_2gb.png", pngTextChunkClaiming(0x7ffffff0u), "a chunk claims 2147483632 bytes");
  add("truncated.png", png.substr(0, png.size() / 2), "cannot decode the PNG image");
  add("truncated.jpg", jpeg.substr(0, jpeg.size() * 2 / 3), "cannot decode the JPEG image");
  std::string lying = jpeg;
  const std::size_t sof = lying.find("\xff\xc0");
  if (sof != std::string::npos) lying.replace(sof + 5, 4, std::string("\x1f\x40\x1f\x40", 4));  // 8000x8000
  add("lying_8000_squared.jpg", lying, "cannot decode the JPEG image");

  // Files that are not regular files.
  out.push_back({"/dev/zero", "not a regular file"});
  ::mkfifo((dir / "fifo.kcw.json").c_str(), 0600);
  out.push_back({dir / "fifo.kcw.json", "not a regular file"});
  return out;
}

}  // namespace kc::test
