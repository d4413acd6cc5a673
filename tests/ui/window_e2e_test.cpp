// End to end: kcwarp in a real window under its own Xvfb (Mesa llvmpipe), driven with real X
// input events (xdotool): drag a control point, paint a stroke, switch method, export, save,
// undo. The app's --ready-file state (JSON) says when it is idle and where things are on screen.
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
  key("b");
  s = waitFor([](const json& j) { return j.value("tool", "") == "brush"; });
  const double zoom = s["view"]["zoom"], ox = s["view"]["origin"][0].get<double>() + wx, oy = s["view"]["origin"][1].get<double>() + wy;
  const long meshBefore = s["mesh_revision"];
  drag(ox + 60 * zoom, oy + 120 * zoom, ox + 190 * zoom, oy + 140 * zoom, 1, 20);
  s = waitFor([&](const json& j) { return j.value("undo", 0) == 2 && !j.value("busy", true) && j.value("mesh_revision", 0L) > meshBefore; });
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

}  // namespace
}  // namespace kc::test
