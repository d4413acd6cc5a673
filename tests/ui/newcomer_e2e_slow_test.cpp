// End to end, a newcomer's whole path in the real window under Xvfb, on a generated picture with
// a background (not a bundled example): open the picture through File > Open's browser, click a
// cage around the character and close it, click Bind, drag a point, paint a stroke, switch
// method, export, save, quit, start again on the saved session. Asserts on pixels and files;
// screenshots are kept in build/artifacts/newcomer/ for people to look at.
#include "gui_session.h"
#include "kc/app/file_io.h"
#include "scene_image.h"

namespace kc::test {
namespace {

class Newcomer : public GuiSession {
 protected:
  /// Screen position of image pixel p in the current view.
  Vec2 onScreen(const json& s, const Vec2& p) {
    const double zoom = s["view"]["zoom"];
    return Vec2(s["window"][0].get<double>() + s["view"]["origin"][0].get<double>() + zoom * p.x(),
                s["window"][1].get<double>() + s["view"]["origin"][1].get<double>() + zoom * p.y());
  }
  Vec2 widget(const json& s, const std::string& label) {
    EXPECT_TRUE(s["widgets"].contains(label)) << "no widget labelled " << label;
    return Vec2(s["window"][0].get<double>() + s["widgets"][label][0].get<double>(),
                s["window"][1].get<double>() + s["widgets"][label][1].get<double>());
  }
  void clickAt(const Vec2& p) { click(p.x(), p.y()); }
  /// The state a few frames later: a frame that switched tools by a key drew the old layout.
  json settled() {
    pause(400);
    return state();
  }
  /// Types `text` into the focused field and presses Return (no Ctrl+A first: the field's text
  /// must be selected when it opens, so typing replaces it).
  void typeAndEnter(const std::string& text) {
    pause(300);
    xdo("type --delay 15 '" + text + "'");
    key("Return");
  }
  void keep(const fs::path& shot) {
    const fs::path out = fs::path(KC_ARTIFACTS_DIR) / "newcomer";
    std::error_code ec;
    fs::create_directories(out, ec);
    fs::copy_file(shot, out / shot.filename(), fs::copy_options::overwrite_existing, ec);
  }
};

TEST_F(Newcomer, OpenCageBindPosePaintExportSaveQuitReopen) {
  const fs::path picture = dir / "my drawing.png";
  const Image source = sceneImage(800, 600);
  app::saveImage(picture.string(), source);

  // Start with no file: the bundled example opens bound and is not "unsaved".
  startApp({}, false);
  json s = waitFor([](const json& j) { return j.value("bound", false) && !j.value("busy", true); }, 90);
  EXPECT_FALSE(s.value("unsaved", true)) << "the untouched example is not unsaved work";

  // 1. File > Open (Ctrl+O): the browser's path field is selected; type the picture's path.
  xdo("mousemove 400 400");
  key("ctrl+o");
  s = waitFor([](const json& j) { return j.value("file_dialog", false); }, 10);
  typeAndEnter(picture.string());
  waitFor([](const json& j) { return j.value("tool", "") == "cage" && j["image_size"][0] == 800; }, 20);
  s = settled();  // the view fits the new picture on the next frame
  EXPECT_EQ(s.value("prompt", "x"), "") << "opening over the untouched example must not ask";
  keep(screenshot("01-opened.png"));

  // 2. Click a cage around the character (image pixels), then the first point to close it.
  const std::vector<Vec2> cage = {{300, 100}, {500, 100}, {590, 220}, {590, 290}, {480, 470}, {320, 470}, {210, 290}, {210, 220}};
  for (const Vec2& p : cage) clickAt(onScreen(s, p));
  clickAt(onScreen(s, cage[0]));
  waitFor([](const json& j) { return j.value("cage_valid", false); }, 10);
  s = settled();
  EXPECT_EQ(s["cage"].size(), cage.size());
  EXPECT_TRUE(s.value("unsaved", false)) << "a drawn cage is work to keep";
  keep(screenshot("02-cage.png"));

  // 3. Click Bind (found by its label); afterwards the pose tool is active.
  clickAt(widget(s, "Bind"));
  s = waitFor([](const json& j) { return j.value("bound", false) && !j.value("busy", true) && j["controls"].size() == 8; }, 180);
  EXPECT_EQ(s.value("tool", ""), "pose");
  const fs::path bound = screenshot("03-bound.png");
  keep(bound);

  // 4. Drag the right arm's point (2) up and out.
  const Vec2 arm = onScreen(s, cage[2]), raised = onScreen(s, cage[2] + Vec2(40, -90));
  drag(arm.x(), arm.y(), raised.x(), raised.y(), 1);
  s = waitFor([](const json& j) { return j.value("undo", 0) == 1 && j.value("idle", false); });
  EXPECT_NEAR(s["pose_translate"][2][0].get<double>(), 40.0, 3.0);
  EXPECT_NEAR(s["pose_translate"][2][1].get<double>(), -90.0, 3.0);
  const fs::path posed = screenshot("04-posed.png");
  keep(posed);
  const Vec2 a = onScreen(s, Vec2(560, 120)), b = onScreen(s, Vec2(700, 300));
  EXPECT_GT(differingPixels(app::loadImage(bound.string()), app::loadImage(posed.string()), int(a.x()), int(a.y()), int(b.x()),
                            int(b.y())),
            500)
      << "the arm did not follow its point";

  // 5. Brush (B): paint a stroke over the body for the active point.
  key("b");
  s = waitFor([](const json& j) { return j.value("tool", "") == "brush"; });
  const long meshBefore = s["mesh_revision"];
  const Vec2 p0 = onScreen(s, Vec2(360, 300)), p1 = onScreen(s, Vec2(450, 330));
  drag(p0.x(), p0.y(), p1.x(), p1.y(), 1, 20);
  s = waitFor([&](const json& j) { return j.value("undo", 0) == 2 && !j.value("busy", true) && j.value("mesh_revision", 0L) > meshBefore; }, 60);
  keep(screenshot("05-painted.png"));

  // 6. Method: click "L1".
  key("p");
  waitFor([](const json& j) { return j.value("tool", "") == "pose"; });
  s = settled();
  clickAt(widget(s, "L1"));
  s = waitFor([](const json& j) { return j.value("method", "") == "l1" && !j.value("busy", true) && j.value("undo", 0) == 3; }, 60);
  xdo("mousemove 400 400");  // away from L1: its tooltip would cover part of the canvas
  pause(300);
  const fs::path beforeQuit = screenshot("06-l1.png");
  keep(beforeQuit);

  // 7. Export (Ctrl+E): the dialog suggests warped.png, selected; type a path of our own.
  xdo("mousemove 400 400");
  key("ctrl+e");
  waitFor([](const json& j) { return j.value("file_dialog", false); }, 10);
  const fs::path exported = dir / "arm up.png";
  typeAndEnter(exported.string());
  s = waitFor([](const json& j) { return j.value("exports", 0) == 1 && !j.value("busy", true); }, 60);
  ASSERT_TRUE(fs::exists(exported)) << "export wrote nothing";
  const Image out = app::loadImage(exported.string());
  ASSERT_EQ(out.width, 800);
  ASSERT_EQ(out.height, 600);
  EXPECT_GT(differingPixels(out, source, 500, 100, 700, 320), 1000) << "the exported arm is not raised";

  // 8. Save (Ctrl+S): untitled.kcw.json suggested; type our path.
  key("ctrl+s");
  waitFor([](const json& j) { return j.value("file_dialog", false); }, 10);
  const fs::path session = dir / "my drawing.kcw.json";
  typeAndEnter(session.string());
  s = waitFor([](const json& j) { return !j.value("unsaved", true) && !j.value("busy", true); }, 60);
  ASSERT_TRUE(fs::exists(session));
  const std::vector<json> controlsBefore = s["controls"];
  EXPECT_EQ(s["recent_files"][0], session.string());

  // 9. Quit (Ctrl+Q): nothing unsaved, so no question; the program ends normally.
  key("ctrl+q");
  EXPECT_EQ(waitExit(15), 0);

  // 10. Start again on the saved session: same pose, same method, same picture on screen.
  startApp({session.string()}, false);
  s = waitFor([](const json& j) { return j.value("bound", false) && !j.value("busy", true) && j.value("method", "") == "l1"; }, 90);
  ASSERT_EQ(s["controls"].size(), controlsBefore.size());
  for (std::size_t i = 0; i < controlsBefore.size(); ++i) {
    EXPECT_NEAR(s["controls"][i][0].get<double>(), controlsBefore[i][0].get<double>(), 0.5);
    EXPECT_NEAR(s["controls"][i][1].get<double>(), controlsBefore[i][1].get<double>(), 0.5);
  }
  EXPECT_FALSE(s.value("unsaved", true));
  focusApp();
  const fs::path reopened = screenshot("07-reopened.png");
  keep(reopened);
  // The picture as it was (overlays such as the selected point may differ): far fewer changed
  // pixels than the pose itself changed.
  const int canvasRight = 1400 - 350;
  const long poseChange = differingPixels(app::loadImage(bound.string()), app::loadImage(posed.string()), 0, 40, canvasRight, 840);
  const long reopenChange = differingPixels(app::loadImage(beforeQuit.string()), app::loadImage(reopened.string()), 0, 40, canvasRight, 840);
  EXPECT_LT(reopenChange * 10, poseChange) << "the reopened session does not look like the saved one (" << reopenChange << " vs "
                                           << poseChange << " pixels)";
  for (const json& m : s["messages"]) EXPECT_FALSE(m["error"].get<bool>()) << m["text"];
}

}  // namespace
}  // namespace kc::test
