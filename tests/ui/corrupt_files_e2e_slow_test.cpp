// End to end: corrupt files opened in the real window (under its own Xvfb) — a session cut off
// mid-file, a cage holding a 100 KB unterminated string, a PNG given as a session — opened with
// File > Open over a picture. Each is refused with a short error on the canvas, the picture stays,
// and the window stays open and keeps drawing.
#include <fstream>

#include "gui_session.h"

namespace kc::test {
namespace {

void writeBytes(const fs::path& p, const std::string& bytes) {
  std::ofstream out(p, std::ios::binary);
  out << bytes;
}

/// Messages that are errors, in the app's state.
std::vector<std::string> errors(const json& st) {
  std::vector<std::string> out;
  for (const json& m : st.value("messages", json::array()))
    if (m.value("error", false)) out.push_back(m.value("text", ""));
  return out;
}

/// Pixels of the error banner's dark red in `shot`.
long bannerPixels(const Image& shot) {
  long n = 0;
  for (int y = 0; y < shot.height; ++y)
    for (int x = 0; x < shot.width; ++x) {
      const std::uint8_t* p = shot.pixel(x, y);
      n += p[0] >= 70 && p[0] <= 110 && p[1] <= 30 && p[2] <= 35;
    }
  return n;
}

TEST_F(GuiSession, CorruptFilesAreRefusedWithAShortErrorAndTheWindowStaysOpen) {
  const std::string session = slurp(fs::path(KC_SOURCE_DIR) / "tests/fuzz/corpus/session/kc_square.kcw.json");
  ASSERT_GT(session.size(), 1000u);
  const fs::path truncated = dir / "truncated.kcw.json";
  writeBytes(truncated, session.substr(0, session.size() / 2));
  const fs::path longString = dir / "long_string.json";  // a cage file: the GUI tries it as a cage, then as a session
  writeBytes(longString, "{\"version\": 1, \"points\": [[0, 0], [10, 0], [0, 10]], \"name\": \"" + std::string(100000, 'A'));
  const fs::path png = dir / "picture.kcw.json";
  fs::copy_file(fs::path(KC_SOURCE_DIR) / "images/checker.png", png);

  // A picture first (the app writes its state once something is open), then each corrupt file.
  startApp({std::string(KC_SOURCE_DIR) + "/images/checker.png"}, false);
  json s = waitFor([](const json& j) { return !j.value("image_size", json::array()).empty() && !j.value("busy", true); }, 60);
  const json pictureSize = s["image_size"];
  std::size_t seen = 0;
  auto expectRefused = [&](const fs::path& file, const char* problem) {
    const std::vector<std::string> e = errors(s);
    ASSERT_EQ(e.size(), seen) << file;
    EXPECT_NE(e.back().find(file.filename().string()), std::string::npos) << e.back();
    EXPECT_NE(e.back().find(problem), std::string::npos) << e.back();
    EXPECT_LT(e.back().size(), 700u) << e.back();
    EXPECT_FALSE(s.value("bound", true)) << "a failed load left a session open";
    EXPECT_EQ(s["image_size"], pictureSize) << "a failed load changed the document";
  };

  // File > Open (Ctrl+O): type the path into the dialog.
  auto openByDialog = [&](const fs::path& file) {
    focusApp();
    key("ctrl+o");
    pause(300);
    xdo("key --delay 20 ctrl+a");
    xdo("type --delay 5 '" + file.string() + "'");
    key("Return");
    ++seen;
    s = waitFor([&](const json& j) { return errors(j).size() == seen && !j.value("busy", true); }, 60);
  };
  openByDialog(truncated);
  expectRefused(truncated, "the file looks truncated");
  openByDialog(longString);
  expectRefused(longString, "malformed JSON at byte");
  openByDialog(png);
  expectRefused(png, "malformed JSON at byte 0");

  // Still drawing frames, and the banner is on screen.
  const Image shot = app::loadImage(screenshot("refused.png").string());
  EXPECT_GT(bannerPixels(shot), 2000) << "no error banner drawn";
  EXPECT_EQ(waitExit(0.5), -1) << "the window closed: " << slurp(dir / "app.log");
  keepShots("corrupt-", {"refused.png"});
}

}  // namespace
}  // namespace kc::test
