// End to end, input faster than the frames: kcwarp in a real window under Xvfb with every frame
// slowed on purpose (--slow-frames), clicked by xdotool faster than it draws. The window's mouse
// callbacks queue each press and release with its position (AppState::pointerInputs), so every
// click reaches the tool, where ImGui's once-per-frame mouse would merge those of one frame.
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
  Image plain(600, 400);
  for (std::size_t k = 0; k < plain.rgba.size(); ++k) plain.rgba[k] = k % 4 == 3 ? 255 : 180;
  app::saveImage((dir / "plain.png").string(), plain);
  startApp({(dir / "plain.png").string(), "--slow-frames", "300"}, false);
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

}  // namespace
}  // namespace kc::test
