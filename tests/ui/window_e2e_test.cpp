// End to end: kcwarp in a real window under its own Xvfb (Mesa llvmpipe), driven with real X
// input events (xdotool): drag a control point, paint a stroke, switch method, export, save,
// undo; a picture wider than the display texture, fitted and zoomed in. The app's --ready-file
// state (JSON) says when it is idle and where things are on screen.
#include <cmath>

#include "gui_session.h"

namespace kc::test {
namespace {

TEST_F(GuiSession, DragPaintSwitchMethodExportSaveUndo) {
  const std::string images = std::string(KC_SOURCE_DIR) + "/images/";
  startApp({images + "checker.png", "--cage", images + "checker.cage.json"});
  json s = waitFor([](const json& j) { return j.value("bound", false) && !j.value("busy", true); }, 60);
  ASSERT_TRUE(s.value("bound", false));
  ASSERT_EQ(s["controls"].size(), 4u);
  const int wx = s["window"][0], wy = s["window"][1];
  const fs::path rest = screenshot("01-rest.png");

  // 1. Drag control point 1 (top right) down and left.
  const double cx = s["controls"][1][0].get<double>() + wx, cy = s["controls"][1][1].get<double>() + wy;
  drag(cx, cy, cx - 90, cy + 70, 1);
  s = waitFor([](const json& j) { return j.value("undo", 0) == 1 && j.value("idle", false); });
  EXPECT_NEAR(s["controls"][1][0].get<double>() + wx, cx - 90, 3.0);
  EXPECT_NEAR(s["controls"][1][1].get<double>() + wy, cy + 70, 3.0);
  EXPECT_EQ(s["active_control"], 1);
  const fs::path dragged = screenshot("02-dragged.png");
  const int canvasRight = 1400 - 350;
  EXPECT_GT(differingPixels(app::loadImage(rest.string()), app::loadImage(dragged.string()), 0, 30, canvasRight, 850), 5000)
      << "the picture did not follow the control point";

  // 2. Brush tool (key B): paint a stroke across the middle of the picture for control 1.
  s = paintCheckerStroke(2);
  EXPECT_GT(s["timings"]["reoptimize_samples"].get<long>(), 20);
  const fs::path painted = screenshot("03-painted.png");
  EXPECT_GT(differingPixels(app::loadImage(dragged.string()), app::loadImage(painted.string()), 0, 30, canvasRight, 850), 2000)
      << "no heatmap / picture change after the stroke";

  // 3. Switch method to L1 with the radio button.
  const double mx = s["widgets"]["L1"][0].get<double>() + wx, my = s["widgets"]["L1"][1].get<double>() + wy;
  click(mx, my);
  s = waitFor([](const json& j) { return j.value("method", "") == "l1" && !j.value("busy", true) && j.value("undo", 0) == 3; });
  screenshot("04-l1.png");

  // 4. Export (Ctrl+E) to --export; compare with the source picture.
  xdo("mousemove 500 500");
  key("ctrl+e");
  s = waitFor([](const json& j) { return j.value("exports", 0) == 1 && !j.value("busy", true); });
  ASSERT_TRUE(fs::exists(dir / "export.png"));
  const Image exported = app::loadImage((dir / "export.png").string());
  const Image source = app::loadImage(images + "checker.png");
  ASSERT_EQ(exported.width, source.width);
  ASSERT_EQ(exported.height, source.height);
  EXPECT_GT(differingPixels(exported, source, 0, 0, source.width, source.height), 2000) << "export is not warped";

  // 5. Save the session through the path dialog (Ctrl+S), then the CLI warps it identically.
  key("ctrl+s");
  pause(300);
  xdo("key --delay 20 ctrl+a");
  xdo("type --delay 15 '" + (dir / "saved.kcw.json").string() + "'");
  key("Return");
  s = waitFor([](const json& j) { return !j.value("unsaved", true); });
  ASSERT_TRUE(fs::exists(dir / "saved.kcw.json"));
  const CliResult cli = runCli("warp --session saved.kcw.json --image '" + images + "checker.png' -o cli.png", dir);
  ASSERT_EQ(cli.code, 0) << cli.err;
  const Image viaCli = app::loadImage((dir / "cli.png").string());
  EXPECT_EQ(viaCli.rgba, exported.rgba) << "GUI export and kcwarp-cli warp differ";

  // 6. Undo (Ctrl+Z) the method switch: back to QP, title shows unsaved changes again.
  key("ctrl+z");
  s = waitFor([](const json& j) { return j.value("method", "") == "qp" && !j.value("busy", true); });
  EXPECT_EQ(s["undo"], 2);
  EXPECT_TRUE(s["unsaved"].get<bool>());
  for (const json& m : s["messages"]) EXPECT_FALSE(m["error"].get<bool>()) << m["text"];

  // Keep a few screenshots for people to look at.
  keepShots("e2e-", {"01-rest.png", "02-dragged.png", "03-painted.png", "04-l1.png"});
}


/// 8192×600: a colour ramp (red along x, green along y) with a band of one-pixel black and white
/// checks in the middle. The display texture (4096 wide: half the picture) averages each 2×2 of
/// them to one flat grey; only the full-resolution picture shows them.
Image rampWithFineChecks() {
  Image img(8192, 600);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      std::uint8_t* p = img.pixel(x, y);
      const bool checks = x >= 3996 && x < 4196 && y >= 250 && y < 350;
      const std::uint8_t v = (x + y) % 2 ? 255 : 0;
      p[0] = checks ? v : static_cast<std::uint8_t>(255 * x / img.width);
      p[1] = checks ? v : static_cast<std::uint8_t>(255 * y / img.height);
      p[2] = checks ? v : 80;
      p[3] = 255;
    }
  return img;
}

/// Standard deviation of red in the rectangle of `shot`: about 127 where one-pixel black and
/// white checks are drawn sharp (or magnified), near 0 where they are averaged to grey.
double contrast(const Image& shot, int x0, int y0, int x1, int y1) {
  double sum = 0.0, sum2 = 0.0;
  long n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x, ++n) {
      const double r = shot.pixel(x, y)[0];
      sum += r;
      sum2 += r * r;
    }
  return n ? std::sqrt(std::max(0.0, sum2 / n - (sum / n) * (sum / n))) : 0.0;
}

TEST_F(GuiSession, OnAScreenSmallerThanTheWindowTheWindowFitsTheScreen) {
  shutDown();
  ASSERT_TRUE(startXvfb("1280x720x24")) << "Xvfb did not start";
  startApp({std::string(KC_SOURCE_DIR) + "/images/star.png"});
  const json s = waitFor([](const json& j) { return j.contains("window") && !j.value("busy", true); });
  const int x = s["window"][0], y = s["window"][1], w = s["window"][2], h = s["window"][3];
  EXPECT_GE(x, 0);
  EXPECT_GE(y, 0);
  EXPECT_LE(x + w, 1280) << "the default window is 1400 px wide";
  EXPECT_LE(y + h, 720) << "the default window is 900 px high";
  EXPECT_GE(w, 1000) << "it fills the screen's width";
  // The framebuffer (the F12 screenshot) is the fitted window's, so the panels laid out against its
  // right edge are on the screen.
  const Image shot = app::loadImage(screenshot("small-screen.png").string());
  EXPECT_EQ(shot.width, w);
  EXPECT_EQ(shot.height, h);
}

TEST_F(GuiSession, BigPictureIsDrawnFromAScreenSizedTextureAndSharpWhenZoomedIn) {
  const Image picture = rampWithFineChecks();
  app::saveImage((dir / "wide.png").string(), picture);
  startApp({(dir / "wide.png").string()});
  json s = waitFor([](const json& j) { return j.value("image_size", json::array()) == json::array({8192, 600}) && !j.value("busy", true); });
  // The display texture: the longest side at 4096 (the floor of the limit for this window), not 8192.
  EXPECT_EQ(s["display_texture"], json::array({4096, 300}));
  EXPECT_EQ(s["detail_texture"]["size"], json::array({0, 0})) << "the fitted view needs no detail";
  const int wx = s["window"][0], wy = s["window"][1];
  const Image fitted = app::loadImage(screenshot("01-fitted.png").string());
  // The ramp is where the picture is: the screenshot's colour at picture points away from the checks.
  for (const Vec2& p : {Vec2(300, 100), Vec2(1500, 500), Vec2(6000, 300), Vec2(7800, 50), Vec2(2000, 300)}) {
    const Vec2 q = screenOf(s, p) - Vec2(wx, wy);
    const std::uint8_t* got = fitted.pixel(int(q.x()), int(q.y()));
    EXPECT_NEAR(got[0], 255.0 * p.x() / 8192, 12) << p.transpose();
    EXPECT_NEAR(got[1], 255.0 * p.y() / 600, 12) << p.transpose();
    EXPECT_NEAR(got[2], 80, 12) << p.transpose();
  }
  const Vec2 a = screenOf(s, Vec2(4016, 260)) - Vec2(wx, wy), b = screenOf(s, Vec2(4176, 340)) - Vec2(wx, wy);
  EXPECT_LT(contrast(fitted, int(a.x()), int(a.y()), int(b.x()), int(b.y())), 8) << "checks finer than a screen pixel average to grey";

  // Zoom in on the checks (wheel) past one screen pixel per picture pixel: the detail texture
  // (the part on screen at full resolution) shows every check.
  const Vec2 centre = screenOf(s, Vec2(4096, 300));
  xdo("mousemove " + std::to_string(int(centre.x())) + " " + std::to_string(int(centre.y())));
  pause(200);
  xdo("click --repeat 16 --delay 80 4");
  s = waitFor([](const json& j) { return j["view"]["zoom"].get<double>() >= 1.0 && j["detail_texture"]["scale"].get<double>() == 1.0; });
  const Image zoomed = app::loadImage(screenshot("02-zoomed.png").string());
  const Vec2 c = screenOf(s, Vec2(4016, 260)) - Vec2(wx, wy), d = screenOf(s, Vec2(4176, 340)) - Vec2(wx, wy);
  // (From the display texture they would be flat grey, magnified.)
  EXPECT_GT(contrast(zoomed, int(c.x()), int(c.y()), int(d.x()), int(d.y())), 25) << "the checks are blurred: no full-resolution detail";
  EXPECT_LT(s["detail_texture"]["size"][0].get<int>(), 4096) << "the detail covers the screen, not the picture";
  const Vec2 ramp = screenOf(s, Vec2(3900, 100)) - Vec2(wx, wy);  // left of the checks, on screen
  EXPECT_NEAR(zoomed.pixel(int(ramp.x()), int(ramp.y()))[0], 255.0 * 3900 / 8192, 8);
  keepShots("big-", {"01-fitted.png", "02-zoomed.png"});
}

}  // namespace
}  // namespace kc::test
