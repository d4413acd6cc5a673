// End to end: kcwarp in a real window under its own Xvfb (Mesa llvmpipe), driven with real X
// input events (xdotool): drag a control point, paint a stroke, switch method, export, save,
// undo. The app's --ready-file state (JSON) says when it is idle and where things are on screen.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <thread>

#include "cli_run.h"
#include "kc/app/image_io.h"

namespace kc::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

pid_t spawn(const std::vector<std::string>& argv, const std::string& display, const fs::path& log) {
  const pid_t pid = fork();
  if (pid == 0) {
    if (!display.empty()) setenv("DISPLAY", display.c_str(), 1);
    FILE* f = std::fopen(log.c_str(), "w");
    if (f) {
      dup2(fileno(f), 1);
      dup2(fileno(f), 2);
    }
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execvp(args[0], args.data());
    _exit(127);
  }
  return pid;
}

void stop(pid_t pid) {
  if (pid <= 0) return;
  kill(pid, SIGTERM);
  for (int k = 0; k < 50; ++k) {
    if (waitpid(pid, nullptr, WNOHANG) == pid) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  kill(pid, SIGKILL);
  waitpid(pid, nullptr, 0);
}

class GuiSession : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = scratchDir("gui_e2e");
    for (int n = 50 + getpid() % 40; n < 140; ++n)  // a free display number
      if (!fs::exists("/tmp/.X11-unix/X" + std::to_string(n)) && !fs::exists("/tmp/.X" + std::to_string(n) + "-lock")) {
        display = ":" + std::to_string(n);
        break;
      }
    ASSERT_FALSE(display.empty());
    xvfb = spawn({"Xvfb", display, "-screen", "0", "1600x1000x24", "-nolisten", "tcp"}, "", dir / "xvfb.log");
    for (int k = 0; k < 100 && !fs::exists("/tmp/.X11-unix/X" + display.substr(1)); ++k)
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    ASSERT_TRUE(fs::exists("/tmp/.X11-unix/X" + display.substr(1))) << "Xvfb did not start";
  }
  void TearDown() override {
    stop(app);
    stop(xvfb);
  }

  void startApp(const std::vector<std::string>& extra) {
    const std::string src = KC_SOURCE_DIR;
    std::vector<std::string> argv = {KC_GUI_PATH,      "--ready-file", (dir / "state.json").string(),
                                     "--screenshot-dir", (dir / "shots").string(), "--export", (dir / "export.png").string(),
                                     "--recovery",     (dir / "recovery.kcw.json").string(), "--frame-log",
                                     (dir / "frames.csv").string()};
    argv.insert(argv.end(), extra.begin(), extra.end());
    app = spawn(argv, display, dir / "app.log");
  }

  json state() {
    std::ifstream in(dir / "state.json");
    json j;
    try {
      in >> j;
    } catch (...) {
    }
    return j;
  }

  /// Waits up to `seconds` for pred(state) to hold.
  json waitFor(const std::function<bool(const json&)>& pred, double seconds = 30.0) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
      json j = state();
      if (!j.is_null() && pred(j)) return j;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    ADD_FAILURE() << "timed out; last state: " << state().dump().substr(0, 2000) << "\napp log: " << slurp(dir / "app.log");
    return state();
  }

  void xdo(const std::string& args) {
    const std::string cmd = "DISPLAY=" + display + " xdotool " + args;
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  }
  void pause(int ms) { std::this_thread::sleep_for(std::chrono::milliseconds(ms)); }
  /// ImGui 1.86 samples key and button state once per frame: hold each event for a few frames.
  void key(const std::string& k) {
    xdo("keydown " + k);
    pause(250);
    xdo("keyup " + k);
    pause(250);
  }
  void drag(double x0, double y0, double x1, double y1, int button, int steps = 15) {
    xdo("mousemove " + std::to_string(int(x0)) + " " + std::to_string(int(y0)));
    pause(150);
    xdo("mousedown " + std::to_string(button));
    pause(150);
    for (int k = 1; k <= steps; ++k) {
      xdo("mousemove " + std::to_string(int(x0 + (x1 - x0) * k / steps)) + " " + std::to_string(int(y0 + (y1 - y0) * k / steps)));
      pause(40);
    }
    pause(150);
    xdo("mouseup " + std::to_string(button));
    pause(200);
  }
  void click(double x, double y) { drag(x, y, x, y, 1, 0); }
  /// Takes a screenshot (F12) and returns its path.
  fs::path screenshot(const std::string& name) {
    const int before = state().value("screenshots", 0);
    key("F12");
    waitFor([&](const json& j) { return j.value("screenshots", 0) > before; }, 10);
    char file[32];
    std::snprintf(file, sizeof file, "shot-%03d.png", before + 1);
    const fs::path p = dir / name;
    fs::copy_file(dir / "shots" / file, p, fs::copy_options::overwrite_existing);
    return p;
  }

  fs::path dir;
  std::string display;
  pid_t xvfb = -1, app = -1;
};

/// Pixels (in the rectangle x0..x1 × y0..y1) whose RGB differs by more than `tol`.
long differingPixels(const Image& a, const Image& b, int x0, int y0, int x1, int y1, int tol = 8) {
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
  const double mx = s["widgets"]["method_l1"][0].get<double>() + wx, my = s["widgets"]["method_l1"][1].get<double>() + wy;
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
  std::error_code ec;
  fs::create_directories("/tmp/kcwarp-shots", ec);
  for (const char* f : {"01-rest.png", "02-dragged.png", "03-painted.png", "04-l1.png"})
    fs::copy_file(dir / f, fs::path("/tmp/kcwarp-shots") / (std::string("e2e-") + f), fs::copy_options::overwrite_existing, ec);
}

}  // namespace
}  // namespace kc::test
