#pragma once
/// What the window exposes for tests and measurement: the state file (JSON: readiness, job state,
/// screen positions of control points and named widgets), screenshots and the frame-time log.

#include <cstdio>
#include <string>
#include <vector>

#include "kc/ui/app_state.h"

namespace kc::ui {

/// The state file's content for the current frame. `window` = x, y, width, height of the window
/// on the screen; positions are window-relative (add x, y for screen coordinates).
std::string stateJson(const AppState& state, const int window[4], int screenshots, int exports);

/// Writes `text` to `path` atomically (temporary file + rename); false on failure.
bool writeAtomically(const std::string& path, const std::string& text);

/// Reads the current back buffer (fbWidth×fbHeight) and saves it as PNG. False on failure.
bool saveScreenshot(const std::string& path, int fbWidth, int fbHeight);

/// Per-frame times, written as CSV at the end.
class FrameLog {
 public:
  struct Row {
    double time = 0.0, frameMs = 0.0, deformMs = 0.0, uploadMs = 0.0;
    bool dragging = false, deformed = false;
    long vertices = 0;
    long uploadBytes = 0;  ///< Vertex data sent to the GPU in the frame.
    /// Of frameMs: a finished job's result taken (pollWorker), the user interface built (panels,
    /// tools, deformation), the picture and the interface sent to OpenGL (uploads included), the
    /// buffer swap (where a software renderer draws).
    double applyMs = 0.0, uiMs = 0.0, glMs = 0.0, swapMs = 0.0;
  };
  void add(const Row& row) { m_rows.push_back(row); }
  bool write(const std::string& path) const;

 private:
  std::vector<Row> m_rows;
};

}  // namespace kc::ui
