#pragma once
/// The kcwarp window: GLFW + OpenGL 3.3 core + Dear ImGui, the frame loop, screenshots, the
/// frame-time log and the state file that end-to-end tests read.

#include <string>

namespace kc::ui {

struct WindowOptions {
  std::string input;          ///< Image (PNG/JPEG) or session (*.kcw.json); empty = bundled example.
  std::string cage;           ///< With an image: a cage file, bound at startup.
  std::string examplesDir;    ///< Where the bundled examples live.
  std::string readyFile;      ///< Written (JSON, atomic) once the first frame is idle, then on every change.
  std::string frameLog;       ///< CSV of per-frame times (written at exit).
  std::string screenshotDir;  ///< F12 writes screenshots here (shot-NNN.png).
  std::string exportPath;     ///< Target of Ctrl+E.
  std::string recoveryPath;   ///< Autosave file (default ~/.cache/kcwarp/recovery.kcw.json).
  double spacing = 0.0;       ///< Bind spacing for the startup bind (0 = the CLI default).
  int width = 1400, height = 900;
  int slowFramesMs = 0;       ///< Each frame lasts at least this long (tests of input faster than the frames).
  bool help = false;
  std::string error;          ///< Set by parseWindowOptions on bad arguments.
};

/// Parses `kcwarp [INPUT] [--cage C] [--ready-file F] [--frame-log F] [--screenshot-dir D]
/// [--export PNG] [--recovery F] [--size WxH] [--spacing H] [--slow-frames MS]`.
WindowOptions parseWindowOptions(int argc, char** argv);
/// One paragraph of usage text.
const char* usageText();

/// Opens the window and runs until it is closed or the process gets SIGTERM or SIGINT (which keep
/// the recovery copy). Returns the process exit code: 1 when the window cannot be opened, else 0.
int runWindow(const WindowOptions& options);

}  // namespace kc::ui
