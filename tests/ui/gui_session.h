#pragma once
// Test support for end-to-end GUI tests: kcwarp in a real window under its own Xvfb (Mesa
// llvmpipe), driven with real X input events (xdotool, gui_driver.h). The app's --ready-file
// state (JSON) says when it is idle and where things are on screen.
#include <gtest/gtest.h>

#include "cli_run.h"
#include "gui_driver.h"
#include "kc/app/image_io.h"

namespace kc::test {

class GuiSession : public ::testing::Test, protected GuiDriver {
 protected:
  void SetUp() override {
    dir = scratchDir(std::string("gui_e2e_") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    // Private settings, recent list and recovery folders; the in-app file browser (not zenity).
    setenv("XDG_CONFIG_HOME", (dir / "config").c_str(), 1);
    setenv("XDG_CACHE_HOME", (dir / "cache").c_str(), 1);
    setenv("KCWARP_NO_NATIVE_DIALOG", "1", 1);
    ASSERT_TRUE(startXvfb()) << "Xvfb did not start";
  }
  void TearDown() override { shutDown(); }

  /// Starts kcwarp with the state file, screenshots, frame log and recovery path in `dir`;
  /// `withExport` also gives it --export (Ctrl+E then writes there without asking).
  void startApp(const std::vector<std::string>& extra, bool withExport = true) {
    std::vector<std::string> args;
    if (withExport) args = {"--export", (dir / "export.png").string()};
    args.insert(args.end(), extra.begin(), extra.end());
    launch(KC_GUI_PATH, args);
  }
  /// Starts kcwarp (startApp, without --export) on a plain grey w × h picture written to `dir`.
  void startOnPlainPicture(int w, int h, const std::vector<std::string>& extra) {
    Image plain(w, h);
    for (std::size_t k = 0; k < plain.rgba.size(); ++k) plain.rgba[k] = k % 4 == 3 ? 255 : 180;
    app::saveImage((dir / "plain.png").string(), plain);
    std::vector<std::string> args{(dir / "plain.png").string()};
    args.insert(args.end(), extra.begin(), extra.end());
    startApp(args, false);
  }

  /// Gives the app's window the keyboard focus (Xvfb has no window manager: after a window
  /// closes, the focus does not move to the next one by itself).
  void focusApp() { xdo("search --name '^kcwarp' windowfocus"); }
  /// Waits up to `seconds` for the app to exit by itself; its exit code, or −1 if it did not.
  int waitExit(double seconds) {
    for (int k = 0; k < seconds * 10; ++k) {
      int status = 0;
      if (waitpid(app, &status, WNOHANG) == app) {
        app = -1;
        return WIFEXITED(status) ? WEXITSTATUS(status) : -2;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    return -1;
  }

  /// Waits up to `seconds` for pred(state) to hold (a test failure when it does not).
  json waitFor(const std::function<bool(const json&)>& pred, double seconds = 30.0) {
    bool ok = false;
    json j = waitUntil(pred, seconds, ok);
    if (!ok) ADD_FAILURE() << "timed out; last state: " << j.dump().substr(0, 2000) << "\napp log: " << slurp(dir / "app.log");
    return j;
  }

  void xdo(const std::string& args) { ASSERT_TRUE(runXdo(args)) << "xdotool " << args; }
  void click(double x, double y) { drag(x, y, x, y, 1, 0); }
  /// Takes a screenshot (F12) and returns its path.
  fs::path screenshot(const std::string& name) {
    const int before = state().value("screenshots", 0);
    const auto taken = [&](const json& j) { return j.value("screenshots", 0) > before; };
    focusApp();  // the key goes to the focused window: make sure it is the app's
    key("F12");
    bool ok = false;
    waitUntil(taken, 10, ok);
    if (!ok) {  // a key lost on its way to the window on a loaded machine: focus and press once more
      focusApp();
      key("F12");
      waitFor(taken, 20);
    }
    char file[32];
    std::snprintf(file, sizeof file, "shot-%03d.png", before + 1);
    const fs::path p = dir / name;
    fs::copy_file(dir / "shots" / file, p, fs::copy_options::overwrite_existing);
    return p;
  }

  /// Switches to the brush (key B) and paints the checker example's stroke across the middle of the
  /// picture (image pixels (60, 120) → (190, 140)); returns the state once the stroke's weights are
  /// in (the undo stack at `undoAfter`).
  json paintCheckerStroke(int undoAfter) {
    key("b");
    json s = waitFor([](const json& j) { return j.value("tool", "") == "brush"; });
    const double wx = s["window"][0], wy = s["window"][1], zoom = s["view"]["zoom"];
    const double ox = s["view"]["origin"][0].get<double>() + wx, oy = s["view"]["origin"][1].get<double>() + wy;
    const long meshBefore = s["mesh_revision"];
    drag(ox + 60 * zoom, oy + 120 * zoom, ox + 190 * zoom, oy + 140 * zoom, 1, 20);
    return waitFor([&](const json& j) {
      return j.value("undo", 0) == undoAfter && !j.value("busy", true) && j.value("mesh_revision", 0L) > meshBefore;
    });
  }
  /// Root-window position of picture pixel p (image pixels) in the app's state `st`.
  static Vec2 screenOf(const json& st, const Vec2& p) {
    const double zoom = st["view"]["zoom"];
    return Vec2(st["view"]["origin"][0].get<double>() + st["window"][0].get<double>() + p.x() * zoom,
                st["view"]["origin"][1].get<double>() + st["window"][1].get<double>() + p.y() * zoom);
  }
  /// Copies files of `dir` to /tmp/kcwarp-shots/<prefix><name> for people to look at.
  void keepShots(const std::string& prefix, std::initializer_list<const char*> files) {
    std::error_code ec;
    fs::create_directories("/tmp/kcwarp-shots", ec);
    for (const char* f : files)
      fs::copy_file(dir / f, fs::path("/tmp/kcwarp-shots") / (prefix + f), fs::copy_options::overwrite_existing, ec);
  }
};

/// Pixels (in the rectangle x0..x1 × y0..y1) whose RGB differs by more than `tol`.
inline long differingPixels(const Image& a, const Image& b, int x0, int y0, int x1, int y1, int tol = 8) {
  long n = 0;
  for (int y = y0; y < std::min({y1, a.height, b.height}); ++y)
    for (int x = x0; x < std::min({x1, a.width, b.width}); ++x)
      for (int c = 0; c < 3; ++c)
        if (std::abs(int(a.pixel(x, y)[c]) - int(b.pixel(x, y)[c])) > tol) {
          ++n;
          break;
        }
  return n;
}

}  // namespace kc::test
