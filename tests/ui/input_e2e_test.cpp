// End to end, input faster than the frames: kcwarp in a real window under Xvfb with every frame
// slowed on purpose (--slow-frames), clicked by xdotool faster than it draws. The window's mouse
// callbacks queue each press and release with its position (AppState::pointerInputs), so every
// click reaches the tool, where ImGui's once-per-frame mouse would merge those of one frame; keys
// tapped between two frames reach the shortcuts and the file dialog (AppState::tappedKeys), the
// side panel's widgets get a button change per frame (feedMouse in window.cpp), and
// input that arrives while the window draws its last frames after an event gets frames of its own.
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

#include "gui_session.h"

namespace kc::test {
namespace {

/// Per-frame times (ms) of the app's frame log (frames.csv, written at exit).
std::vector<double> frameTimes(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);  // header
  std::vector<double> ms;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::string cell;
    for (int k = 0; k < 3 && std::getline(row, cell, ','); ++k)
      if (k == 2) ms.push_back(std::stod(cell));
  }
  return ms;
}

TEST_F(GuiSession, CageClicksFasterThanTheFramesAllArrive) {
  startOnPlainPicture(600, 400, {"--slow-frames", "300"});
  json s = waitFor([](const json& j) { return j.value("tool", "") == "cage" && !j.value("busy", true) && j["view"]["zoom"].get<double>() > 0; });
  ASSERT_EQ(s["cage"].size(), 0u);
  const int wx = s["window"][0], wy = s["window"][1];

  // Eight points on a circle, clicked 0.1 s apart: three or four clicks fall in each 300 ms frame.
  std::vector<Vec2> screen;
  for (int k = 0; k < 8; ++k) {
    const double a = 2.0 * std::numbers::pi * k / 8;
    screen.push_back(screenOf(s, Vec2(300 + 140 * std::cos(a), 200 + 140 * std::sin(a))));
  }
  for (const Vec2& p : screen) {
    xdo("mousemove " + std::to_string(int(std::lround(p.x()))) + " " + std::to_string(int(std::lround(p.y()))) + " click 1");
    pause(100);
  }
  s = waitFor([](const json& j) { return j["cage"].size() >= 8 && j.value("idle", false); }, 20);
  ASSERT_EQ(s["cage"].size(), 8u) << "clicks were lost";
  for (std::size_t k = 0; k < 8; ++k) {
    EXPECT_NEAR(s["cage"][k][0].get<double>() + wx, std::lround(screen[k].x()), 1.5) << "point " << k;
    EXPECT_NEAR(s["cage"][k][1].get<double>() + wy, std::lround(screen[k].y()), 1.5) << "point " << k;
  }

  // The frames were as slow as asked (else the clicks did not outpace them).
  shutDown();
  const std::vector<double> ms = frameTimes(dir / "frames.csv");
  ASSERT_GE(ms.size(), 2u);
  EXPECT_GE(*std::min_element(ms.begin(), ms.end()), 290.0);
}

TEST_F(GuiSession, SidePanelClicksFasterThanTheFramesAllArrive) {
  // Frames of 300 ms; the Bind panel's three check boxes clicked once each, 100 ms apart, three
  // times over: two or three clicks fall in each frame, on different widgets. Each box must flip
  // with each click (ImGui alone would see one click per frame, at the last place, or a press on
  // one box released on the next).
  startOnPlainPicture(600, 400, {"--slow-frames", "300"});
  json s = waitFor([](const json& j) { return !j.value("image_size", json::array()).empty() && j.value("idle", false); });
  const std::vector<std::string> boxes = {"Auto spacing", "Auto sigma", "Local targets"};
  const std::vector<std::string> keys = {"auto_spacing", "auto_sigma", "local_targets"};
  std::vector<Vec2> at;
  for (std::size_t k = 0; k < boxes.size(); ++k) {
    ASSERT_TRUE(s["widgets"].contains(boxes[k])) << boxes[k] << " not drawn";
    ASSERT_TRUE(s["bind_switches"][keys[k]].get<bool>()) << keys[k] << " is off at start";
    // A check box's item takes its label too: a click on the item's centre flips it.
    const double cx = s["widgets"][boxes[k]][0], cy = s["widgets"][boxes[k]][1];
    at.emplace_back(cx, cy);
  }
  const int wx = s["window"][0], wy = s["window"][1];
  for (int round = 1; round <= 3; ++round) {
    for (const Vec2& p : at) {
      xdo("mousemove " + std::to_string(int(std::lround(p.x())) + wx) + " " + std::to_string(int(std::lround(p.y())) + wy) +
          " click 1");
      pause(100);
    }
    const bool on = round % 2 == 0;
    bool ok = false;
    s = waitUntil(
        [&](const json& j) {
          if (!j.value("idle", false)) return false;
          for (const std::string& k : keys)
            if (j["bind_switches"][k].get<bool>() != on) return false;
          return true;
        },
        10, ok);
    EXPECT_TRUE(ok) << "round " << round << ": " << s["bind_switches"].dump();
  }
  shutDown();
  const std::vector<double> ms = frameTimes(dir / "frames.csv");
  ASSERT_GE(ms.size(), 2u);
  EXPECT_GE(*std::min_element(ms.begin(), ms.end()), 290.0) << "the frames were not slowed";
}

TEST_F(GuiSession, ADragFasterThanTheFramesEndsWhereTheMouseWasReleased) {
  // Frames of 800 ms (a big picture on a slow machine); a control dragged in 12 steps 25 ms apart
  // and released: the whole drag falls within one or two frames, and the point must end under the
  // mouse, not at a position of the last frame that drew it.
  const std::string images = std::string(KC_SOURCE_DIR) + "/images/";
  startApp({images + "checker.png", "--cage", images + "checker.cage.json", "--spacing", "16", "--slow-frames", "800"});
  json s = waitFor([](const json& j) { return j.value("bound", false) && !j.value("busy", true); }, 90);
  ASSERT_TRUE(s.value("bound", false));
  const int wx = s["window"][0], wy = s["window"][1];
  const double zoom = s["view"]["zoom"];
  const double cx = s["controls"][1][0].get<double>() + wx, cy = s["controls"][1][1].get<double>() + wy;
  drag(cx, cy, cx - 60, cy + 40, 1, 12, 25);
  s = waitFor([](const json& j) { return j.value("undo", 0) == 1 && j.value("idle", false); }, 30);
  const json t = s["pose_translate"][1];
  EXPECT_NEAR(t[0].get<double>(), -60.0 / zoom, 1.5 / zoom) << s["pose_translate"].dump();
  EXPECT_NEAR(t[1].get<double>(), 40.0 / zoom, 1.5 / zoom) << s["pose_translate"].dump();
  for (std::size_t k = 0; k < s["pose_translate"].size(); ++k) {
    if (k == 1) continue;
    EXPECT_EQ(s["pose_translate"][k], json::array({0.0, 0.0})) << "control " << k << " moved";
  }
  shutDown();
  const std::vector<double> ms = frameTimes(dir / "frames.csv");
  ASSERT_GE(ms.size(), 2u);
  EXPECT_GE(*std::min_element(ms.begin(), ms.end()), 790.0) << "the frames were not slowed";
}

TEST_F(GuiSession, KeysTappedBetweenFramesOpenAndCloseTheFileDialog) {
  // Frames of 300 ms. Ctrl is held, and O tapped (down and up within a few ms, between two
  // frames) at several moments of the frames the window draws after the Ctrl press: the dialog
  // opens with its path field taking the keyboard without any further input, also when the tap
  // lands in the last of those frames (its field takes the keyboard a frame after the dialog
  // appears). A quick Escape then closes it.
  startOnPlainPicture(400, 300, {"--slow-frames", "300"});
  json s = waitFor([](const json& j) { return !j.value("image_size", json::array()).empty() && j.value("idle", false); });
  for (int offsetMs : {400, 700, 800}) {
    focusApp();
    pause(1200);  // the window asleep again
    runXdo("keydown ctrl");
    pause(offsetMs);
    runXdo("key o");
    pause(50);
    runXdo("keyup ctrl");
    bool ok = false;
    s = waitUntil([](const json& j) { return j.value("file_dialog", false) && j.value("file_dialog_focused", false); }, 6, ok);
    EXPECT_TRUE(ok) << "O tapped " << offsetMs << " ms after Ctrl: dialog " << s.value("file_dialog", false) << ", field focused "
                    << s.value("file_dialog_focused", false);
    pause(1200);
    runXdo("key Escape");
    s = waitUntil([](const json& j) { return !j.value("file_dialog", true); }, 6, ok);
    EXPECT_TRUE(ok) << "a quick Escape did not close the dialog (O tapped " << offsetMs << " ms after Ctrl)";
    if (!ok) {  // closed by a held Escape, for the next round
      key("Escape");
      waitUntil([](const json& j) { return !j.value("file_dialog", true); }, 6, ok);
      ASSERT_TRUE(ok);
    }
  }
}

TEST_F(GuiSession, TypingFasterThanTheFramesEditsTheFieldInOrder) {
  // Frames of 300 ms. In the file dialog's path field: Ctrl+A, "abc", Backspace, "d", Left, "x",
  // sent within a few frames. Each key reaches the field in order, also a Backspace or an arrow
  // that goes down and up between two frames: "abxd".
  startOnPlainPicture(300, 200, {"--slow-frames", "300"});
  json s = waitFor([](const json& j) { return !j.value("image_size", json::array()).empty() && j.value("idle", false); });
  focusApp();
  runXdo("key ctrl+o");
  s = waitFor([](const json& j) { return j.value("file_dialog", false) && j.value("file_dialog_focused", false); }, 10);
  ASSERT_TRUE(s.value("file_dialog_focused", false));
  runXdo("key --delay 1 ctrl+a a b c BackSpace d Left x");
  bool ok = false;
  s = waitUntil([](const json& j) { return j.value("file_dialog_text", "") == "abxd"; }, 10, ok);
  EXPECT_TRUE(ok) << "the field holds '" << s.value("file_dialog_text", "") << "'";
  runXdo("key Escape");
  waitFor([](const json& j) { return !j.value("file_dialog", true); }, 10);
}

}  // namespace
}  // namespace kc::test
