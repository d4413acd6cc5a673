#pragma once
// Test support for end-to-end GUI tests: kcwarp in a real window under its own Xvfb (Mesa
// llvmpipe), driven with real X input events (xdotool). The app's --ready-file state (JSON) says
// when it is idle and where things are on screen.
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

namespace fs = std::filesystem;
using nlohmann::json;

inline pid_t spawn(const std::vector<std::string>& argv, const std::string& display, const fs::path& log) {
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

inline void stop(pid_t pid) {
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
    dir = scratchDir(std::string("gui_e2e_") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    // Private settings, recent list and recovery folders; the in-app file browser (not zenity).
    setenv("XDG_CONFIG_HOME", (dir / "config").c_str(), 1);
    setenv("XDG_CACHE_HOME", (dir / "cache").c_str(), 1);
    setenv("KCWARP_NO_NATIVE_DIALOG", "1", 1);
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

  /// Starts kcwarp with the state file, screenshots, frame log and recovery path in `dir`;
  /// `withExport` also gives it --export (Ctrl+E then writes there without asking).
  void startApp(const std::vector<std::string>& extra, bool withExport = true) {
    std::vector<std::string> argv = {KC_GUI_PATH,      "--ready-file", (dir / "state.json").string(),
                                     "--screenshot-dir", (dir / "shots").string(),
                                     "--recovery",     (dir / "recovery.kcw.json").string(), "--frame-log",
                                     (dir / "frames.csv").string()};
    if (withExport) argv.insert(argv.end(), {"--export", (dir / "export.png").string()});
    argv.insert(argv.end(), extra.begin(), extra.end());
    std::error_code ec;
    fs::remove(dir / "state.json", ec);
    app = spawn(argv, display, dir / "app.log");
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
    pause(400);  // a frame must see the press before the mouse moves (frames are slow on a loaded software renderer)
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

  fs::path dir;
  std::string display;
  pid_t xvfb = -1, app = -1;
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
