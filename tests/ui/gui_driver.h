#pragma once
// Drives kcwarp in a real window under its own Xvfb (Mesa llvmpipe) with real X input events
// (xdotool); the app's --ready-file state (JSON) says when it is idle and where things are on
// screen. No test framework: the end-to-end tests (gui_session.h) and the GUI benchmark
// (bench/gui_bench.cpp) share it.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

namespace kc::test {

namespace fs = std::filesystem;
using nlohmann::json;

/// Starts argv[0] with `argv` (on `display` when not empty), stdout and stderr to `log`.
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

/// SIGTERM, then SIGKILL after 5 s.
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

class GuiDriver {
 public:
  /// Starts Xvfb (`screen` = WxHxD) on a free display number; false if it did not come up. Two tests
  /// starting together may pick the same number: the Xvfb that finds the display taken exits, and
  /// its test tries the next number, so no two tests ever share a display (and the keyboard focus).
  bool startXvfb(const std::string& screen = "1600x1000x24") {
    for (int n = 50 + getpid() % 40; n < 140; ++n) {
      const std::string socket = "/tmp/.X11-unix/X" + std::to_string(n);
      if (fs::exists(socket) || fs::exists("/tmp/.X" + std::to_string(n) + "-lock")) continue;
      const pid_t server =
          spawn({"Xvfb", ":" + std::to_string(n), "-screen", "0", screen, "-nolisten", "tcp"}, "", dir / "xvfb.log");
      bool exited = false;
      for (int k = 0; k < 100 && !exited && !fs::exists(socket); ++k) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        exited = waitpid(server, nullptr, WNOHANG) == server;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(100));  // a server that lost the display exits at once
      if (exited || waitpid(server, nullptr, WNOHANG) == server || !fs::exists(socket)) {
        if (!exited) stop(server);
        continue;
      }
      xvfb = server;
      display = ":" + std::to_string(n);
      return true;
    }
    return false;
  }
  /// Starts `gui` (the kcwarp executable) with the state file, screenshots, frame log and
  /// recovery path in `dir`, then `extra`.
  void launch(const std::string& gui, const std::vector<std::string>& extra) {
    std::vector<std::string> argv = {gui,          "--ready-file", (dir / "state.json").string(), "--screenshot-dir",
                                     (dir / "shots").string(), "--recovery", (dir / "recovery.kcw.json").string(),
                                     "--frame-log", (dir / "frames.csv").string()};
    argv.insert(argv.end(), extra.begin(), extra.end());
    std::error_code ec;
    fs::remove(dir / "state.json", ec);
    app = spawn(argv, display, dir / "app.log");
  }
  /// Ends the app (SIGTERM: it writes its frame log) and Xvfb.
  void shutDown() {
    stop(app);
    app = -1;
    stop(xvfb);
    xvfb = -1;
  }

  json state() const {
    std::ifstream in(dir / "state.json");
    json j;
    try {
      in >> j;
    } catch (...) {
    }
    return j;
  }
  /// Waits up to `seconds` for pred(state) to hold; the last state, and `ok` whether it held.
  json waitUntil(const std::function<bool(const json&)>& pred, double seconds, bool& ok) const {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
      json j = state();
      if (!j.is_null() && pred(j)) {
        ok = true;
        return j;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    ok = false;
    return state();
  }

  /// Runs `xdotool args` on the display; false when it failed.
  bool runXdo(const std::string& args) const {
    const std::string cmd = "DISPLAY=" + display + " xdotool " + args;
    return std::system(cmd.c_str()) == 0;
  }
  static void pause(int ms) { std::this_thread::sleep_for(std::chrono::milliseconds(ms)); }
  /// ImGui samples key and button state once per frame: each event is held for a few frames.
  void key(const std::string& k) {
    runXdo("keydown " + k);
    pause(250);
    runXdo("keyup " + k);
    pause(250);
  }
  /// Presses `button` at (x0, y0), moves to (x1, y1) in `steps` steps `stepMs` apart, releases.
  void drag(double x0, double y0, double x1, double y1, int button, int steps = 15, int stepMs = 40) {
    runXdo("mousemove " + std::to_string(int(x0)) + " " + std::to_string(int(y0)));
    pause(150);
    runXdo("mousedown " + std::to_string(button));
    pause(400);  // a frame must see the press before the mouse moves (frames are slow on a loaded software renderer)
    for (int k = 1; k <= steps; ++k) {
      runXdo("mousemove " + std::to_string(int(x0 + (x1 - x0) * k / steps)) + " " + std::to_string(int(y0 + (y1 - y0) * k / steps)));
      pause(stepMs);
    }
    pause(150);
    runXdo("mouseup " + std::to_string(button));
    pause(200);
  }

  fs::path dir;
  std::string display;
  pid_t xvfb = -1, app = -1;
};

}  // namespace kc::test
