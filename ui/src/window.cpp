#include "kc/ui/window.h"

#include <algorithm>
#include <GL/gl.h>
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <array>
#include <atomic>
#include <chrono>
#include <csignal>
#include <deque>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <unistd.h>

#include "kc/app/file_io.h"
#include "kc/ui/automation.h"
#include "kc/ui/canvas.h"
#include "kc/ui/document.h"
#include "kc/ui/edits.h"
#include "kc/ui/frame.h"
#include "kc/ui/jobs.h"
#include "kc/ui/panels/panels.h"
#include "kc/ui/recent_files.h"
#include "kc/ui/renderer.h"
#include "kc/ui/shortcuts.h"

namespace kc::ui {
namespace {

std::atomic<bool> g_terminate{false};  // set by SIGTERM/SIGINT only (signal handlers need a global)
int g_signalPipe[2] = {-1, -1};         // the handler's byte wakes the loop's glfwWaitEvents

void onSignal(int) {
  g_terminate = true;
  const char byte = 1;
  if (g_signalPipe[1] >= 0) [[maybe_unused]] auto n = ::write(g_signalPipe[1], &byte, 1);  // async-signal-safe
}

/// While the window waits for input without a timeout, a signal alone would not wake it: this
/// thread turns the handler's byte into an empty GLFW event. A zero byte ends it.
class SignalWaker {
 public:
  SignalWaker() {
    if (::pipe(g_signalPipe) != 0) return;
    m_thread = std::thread([] {
      char byte = 0;
      while (::read(g_signalPipe[0], &byte, 1) == 1 && byte != 0) glfwPostEmptyEvent();
    });
  }
  ~SignalWaker() {
    if (!m_thread.joinable()) return;
    const char stop = 0;
    [[maybe_unused]] auto n = ::write(g_signalPipe[1], &stop, 1);
    m_thread.join();
    const int fds[2] = {g_signalPipe[0], g_signalPipe[1]};
    g_signalPipe[0] = g_signalPipe[1] = -1;
    ::close(fds[0]);
    ::close(fds[1]);
  }
  bool waitsForever() const { return m_thread.joinable(); }

 private:
  std::thread m_thread;
};

void applyStyle() {
  ImGui::StyleColorsDark();
  ImGuiStyle& s = ImGui::GetStyle();
  s.WindowRounding = 0.0f;
  s.FrameRounding = 3.0f;
  s.GrabRounding = 3.0f;
  s.FramePadding = ImVec2(6, 4);
  s.ItemSpacing = ImVec2(8, 6);
  s.WindowPadding = ImVec2(10, 10);
  s.Colors[ImGuiCol_WindowBg].w = 0.97f;
}

/// The document at startup: INPUT, IMAGE + --cage, or the bundled figure example (bound).
void openStartup(AppState& state, const WindowOptions& o) {
  std::string image = o.input, cage = o.cage;
  if (image.empty()) {
    const std::string dir = o.examplesDir.empty() ? std::string("images") : o.examplesDir;
    image = dir + "/figure.png";
    cage = dir + "/figure.cage.json";
  }
  if (o.spacing > 0.0) {
    state.bindParams.spacing = o.spacing;
    state.autoSpacing = false;
  }
  if (!openPath(state, image) || cage.empty()) return;
  if (loadCageFile(state, cage) && state.cageValid) {
    state.undo.clear();
    state.unsaved = false;           // the picture and the cage are files on disk
    startBind(state, false);
  }
}

/// A job's first second without progress redraws: a stroke's re-optimization or a bind of a
/// typical cage usually ends within it, and a frame drawn meanwhile takes cores from it (a software
/// renderer spends 0.05–0.3 s of both cores on one) and makes its result wait for the frame's end;
/// a wait under a second needs no progress shown.
constexpr double kQuietJobSeconds = 1.0;
/// After them, progress redraws take at most this share of the time (a frame of 50 ms, as a
/// software renderer draws one, every 0.25 s), and come at most 10 times a second.
constexpr double kProgressFrameShare = 0.2;

double msBetween(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

/// Shrinks the window to the primary monitor's work area when it does not fit there (the default
/// 1400×900 on a 1366×768 laptop screen) and moves it inside, frame included; a window that fits
/// is left as it is.
void fitToWorkArea(GLFWwindow* window) {
  GLFWmonitor* monitor = glfwGetPrimaryMonitor();
  if (!monitor) return;
  int x = 0, y = 0, w = 0, h = 0;
  glfwGetMonitorWorkarea(monitor, &x, &y, &w, &h);
  if (w <= 0 || h <= 0) return;
  int left = 0, top = 0, right = 0, bottom = 0, ww = 0, wh = 0;
  glfwGetWindowFrameSize(window, &left, &top, &right, &bottom);
  glfwGetWindowSize(window, &ww, &wh);
  const int fitW = std::max(1, w - left - right), fitH = std::max(1, h - top - bottom);
  if (ww <= fitW && wh <= fitH) return;
  glfwSetWindowSize(window, std::min(ww, fitW), std::min(wh, fitH));
  glfwSetWindowPos(window, x + left, y + top);
}

/// GLFW with an OpenGL 3.3 core window and ImGui on it; nullptr (after a message on stderr, GLFW
/// terminated) when either cannot start.
GLFWwindow* openWindow(const WindowOptions& o) {
  glfwSetErrorCallback([](int code, const char* text) { std::fprintf(stderr, "kcwarp: GLFW error %d: %s\n", code, text); });
  if (!glfwInit()) {
    std::fprintf(stderr, "kcwarp: cannot initialize GLFW (is DISPLAY set? try kcwarp-cli for headless use)\n");
    return nullptr;
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  GLFWwindow* window = glfwCreateWindow(o.width, o.height, "kcwarp", nullptr, nullptr);
  if (!window) {
    std::fprintf(stderr, "kcwarp: cannot open an OpenGL 3.3 window\n");
    glfwTerminate();
    return nullptr;
  }
  fitToWorkArea(window);
  glfwMakeContextCurrent(window);
  glfwSwapInterval(1);
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;
  applyStyle();
  ImGui_ImplGlfw_InitForOpenGL(window, true);
  ImGui_ImplOpenGL3_Init("#version 330");
  return window;
}

/// ImGui and GLFW shut down, the window destroyed.
void closeWindow(GLFWwindow* window) {
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(window);
  glfwTerminate();
}

/// A key or character event from GLFW's callbacks.
struct KeyEvent {
  bool character = false;
  int key = 0, scancode = 0, action = 0, mods = 0;  // a key event
  unsigned int codepoint = 0;                       // a character
};

/// What the window's callbacks reach through GLFW's user pointer: the state, the key and
/// character events and the mouse events not yet given to ImGui (feedKeys, feedMouse), and a count
/// of every input event (the frame pacing draws a few frames after each, also after one that
/// arrived while it polled).
struct WindowInput {
  AppState* state = nullptr;
  std::deque<KeyEvent> keys;
  std::deque<PointerInput> mouse;
  std::array<bool, 3> down{};  ///< The buttons as ImGui was last given them (feedMouse).
  Vec2 at = Vec2::Zero();      ///< The position ImGui was last given (feedMouse).
  unsigned long events = 0;
};

/// The keys that edit a text field or act in a dialog without typing a character.
bool editingKey(int key, int mods) {
  if (mods & (GLFW_MOD_CONTROL | GLFW_MOD_SUPER)) return true;  // Ctrl+A, Ctrl+Z, … and the shortcuts
  switch (key) {
    case GLFW_KEY_BACKSPACE: case GLFW_KEY_DELETE: case GLFW_KEY_LEFT: case GLFW_KEY_RIGHT: case GLFW_KEY_UP:
    case GLFW_KEY_DOWN: case GLFW_KEY_HOME: case GLFW_KEY_END: case GLFW_KEY_PAGE_UP: case GLFW_KEY_PAGE_DOWN:
    case GLFW_KEY_ENTER: case GLFW_KEY_KP_ENTER: case GLFW_KEY_TAB: case GLFW_KEY_ESCAPE: case GLFW_KEY_INSERT:
      return true;
    default:
      return false;
  }
}

/// Gives ImGui the queued key and character events, in order, as far as this frame can take them.
/// ImGui 1.86 reads key state once per frame: an editing key (Backspace, arrows, Ctrl+…) that went
/// down and up since the last frame would never be seen down, and a text field reads a frame's
/// characters before its keys. So an editing key changes at most once per frame (the modifiers
/// released after it wait behind it, in order), and a character after one waits for the next
/// frame; what is left stays queued (the window draws on while it is). Keys that type characters
/// pass freely: the characters carry the text, and their presses reach the shortcuts as taps.
/// Each press given is also kept for handleShortcuts (AppState::tappedKeys). True when it gave any.
bool feedKeys(GLFWwindow* window, WindowInput& input) {
  if (input.keys.empty()) return false;
  const std::size_t queued = input.keys.size();
  std::vector<int> changed;  // keys that went down or up this frame
  bool edited = false;
  while (!input.keys.empty()) {
    const KeyEvent& e = input.keys.front();
    if (e.character) {
      if (edited) break;
      ImGui_ImplGlfw_CharCallback(window, e.codepoint);
    } else {
      const bool held = e.action != GLFW_REPEAT && editingKey(e.key, e.mods);
      if (held && std::find(changed.begin(), changed.end(), e.key) != changed.end()) break;
      ImGui_ImplGlfw_KeyCallback(window, e.key, e.scancode, e.action, e.mods);
      if (held) changed.push_back(e.key);
      if (e.action == GLFW_PRESS) {
        input.state->tappedKeys.emplace_back(e.key, e.mods);
        edited = edited || editingKey(e.key, e.mods);
      }
    }
    input.keys.pop_front();
  }
  return input.keys.size() != queued;
}

/// Gives ImGui the queued mouse events as far as this frame can take them (after ImGui's backend
/// read the mouse, before ImGui::NewFrame). ImGui 1.86 reads the mouse once per frame: two clicks
/// within one frame would be one, at the later place, and a press on one widget with its release
/// on the next a drag between them. So a button changes at most once per frame, at the position it
/// changed at, after the moves before it; what is left stays queued (the window draws on while it
/// is). The canvas reads the same events all at once (AppState::pointerInputs), so both the side
/// panel and the tools get every click at any frame rate. With nothing queued ImGui keeps what its
/// backend read.
void feedMouse(WindowInput& input) {
  ImGuiIO& io = ImGui::GetIO();
  if (input.mouse.empty()) {
    for (std::size_t b = 0; b < input.down.size(); ++b) input.down[b] = io.MouseDown[b];
    return;
  }
  while (!input.mouse.empty()) {
    const PointerInput e = input.mouse.front();
    input.mouse.pop_front();
    input.at = e.screen;
    if (e.kind == PointerInput::Kind::Move) continue;
    bool& down = input.down[static_cast<std::size_t>(e.button)];
    if (down == (e.kind == PointerInput::Kind::Press)) continue;
    down = !down;
    break;
  }
  io.MousePos = ImVec2(static_cast<float>(input.at.x()), static_cast<float>(input.at.y()));
  for (std::size_t b = 0; b < input.down.size(); ++b) io.MouseDown[b] = input.down[b];
}

/// The window's input callbacks for `input`, installed after ImGui's backend installed its own:
/// keys and characters are queued for feedKeys; mouse buttons and moves are queued in order with
/// their positions for the canvas (AppState::pointerInputs) and for ImGui (feedMouse); dropped files are kept
/// (AppState::droppedPaths). Every event counts in WindowInput::events.
void installInputCallbacks(GLFWwindow* window, WindowInput& input) {
  glfwSetWindowUserPointer(window, &input);
  glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int scancode, int action, int mods) {
    auto* in = static_cast<WindowInput*>(glfwGetWindowUserPointer(w));
    ++in->events;
    in->keys.push_back({false, key, scancode, action, mods, 0});
  });
  glfwSetCharCallback(window, [](GLFWwindow* w, unsigned int c) {
    auto* in = static_cast<WindowInput*>(glfwGetWindowUserPointer(w));
    ++in->events;
    in->keys.push_back({true, 0, 0, 0, 0, c});
  });
  glfwSetScrollCallback(window, [](GLFWwindow* w, double dx, double dy) {
    ImGui_ImplGlfw_ScrollCallback(w, dx, dy);
    ++static_cast<WindowInput*>(glfwGetWindowUserPointer(w))->events;
  });
  input.state->pointerQueued = true;
  glfwSetMouseButtonCallback(window, [](GLFWwindow* w, int button, int action, int mods) {
    ImGui_ImplGlfw_MouseButtonCallback(w, button, action, mods);  // buttons beyond the queue's three
    auto* in = static_cast<WindowInput*>(glfwGetWindowUserPointer(w));
    ++in->events;
    AppState* st = in->state;
    if (button > 2 || action == GLFW_REPEAT) return;
    if (!st->pointerAt) {  // no move seen yet: where the pointer is now
      double x = 0.0, y = 0.0;
      glfwGetCursorPos(w, &x, &y);
      st->pointerAt = Vec2(x, y);
    }
    st->pointerInputs.push_back({action == GLFW_PRESS ? PointerInput::Kind::Press : PointerInput::Kind::Release, button,
                                 *st->pointerAt, (mods & GLFW_MOD_SHIFT) != 0, (mods & GLFW_MOD_CONTROL) != 0});
    in->mouse.push_back(st->pointerInputs.back());
  });
  glfwSetCursorPosCallback(window, [](GLFWwindow* w, double x, double y) {
    auto* in = static_cast<WindowInput*>(glfwGetWindowUserPointer(w));
    ++in->events;
    AppState* st = in->state;
    st->pointerAt = Vec2(x, y);
    st->pointerInputs.push_back({PointerInput::Kind::Move, 0, Vec2(x, y)});
    in->mouse.push_back(st->pointerInputs.back());
  });
  glfwSetDropCallback(window, [](GLFWwindow* w, int count, const char** paths) {
    AppState* st = static_cast<WindowInput*>(glfwGetWindowUserPointer(w))->state;
    for (int k = 0; k < count; ++k) st->droppedPaths.emplace_back(paths[k]);
  });
}

/// ImGui's own callbacks back, the state detached (before the state goes).
void removeInputCallbacks(GLFWwindow* window) {
  glfwSetDropCallback(window, nullptr);
  glfwSetKeyCallback(window, ImGui_ImplGlfw_KeyCallback);
  glfwSetCharCallback(window, ImGui_ImplGlfw_CharCallback);
  glfwSetScrollCallback(window, ImGui_ImplGlfw_ScrollCallback);
  glfwSetMouseButtonCallback(window, ImGui_ImplGlfw_MouseButtonCallback);
  glfwSetCursorPosCallback(window, nullptr);
  glfwSetWindowUserPointer(window, nullptr);
}

/// When the loop draws the next frame. Display rate while dragging or for a few frames after an
/// event, counted from the last event also when it arrived while a frame polled (ImGui settles
/// hover, popups and keyboard focus over two or three frames); a running job gets a few
/// progress redraws per second once it has run kQuietJobSeconds (at most kProgressFrameShare of
/// the time; before that, only input or its end wakes the loop); otherwise sleep until input arrives (no redraw while nothing changes). A
/// timeout wakes the loop only for a blinking text cursor and for the next autosave of unsaved work.
struct FramePacing {
  int settleFrames = 3;
  bool wasBusy = false;
  double jobSince = 0.0;  // seconds (nowSeconds) when the running job was first seen

  /// Polls or waits for events as above. `waitsForever`: a signal can wake a wait without timeout.
  /// Key and mouse events still queued (feedKeys, feedMouse) get the next frame at once.
  void waitForEvents(const AppState& state, const WindowInput& input, bool waitsForever) {
    const double progressInterval = std::max(0.1, 1e-3 * state.timings.frameMs / kProgressFrameShare);
    const bool busy = state.worker.busy();
    if (busy && !wasBusy) jobSince = nowSeconds();
    wasBusy = busy;
    const double quietLeft = busy ? kQuietJobSeconds - (nowSeconds() - jobSince) : 0.0;
    if (!input.keys.empty() || !input.mouse.empty() || state.canvasDrag.button >= 0 || (settleFrames > 0 && quietLeft <= 0.0)) {
      const unsigned long before = input.events;
      glfwPollEvents();
      // Input in this poll, and a drag's end, get their settle frames too (the release's full
      // deform may post a message, a fold, after the status bar was drawn).
      settleFrames = state.canvasDrag.button >= 0 || input.events != before ? 3 : std::max(settleFrames - 1, 0);
      return;
    }
    if (busy) glfwWaitEventsTimeout(std::max(quietLeft, progressInterval));
    else if (ImGui::GetIO().WantTextInput) glfwWaitEventsTimeout(0.5);
    else if (state.unsaved) glfwWaitEventsTimeout(std::max(1.0, state.lastAutosave + kAutosaveSeconds - nowSeconds()));
    else if (waitsForever) glfwWaitEvents();
    else glfwWaitEventsTimeout(1.0);
    settleFrames = 3;
  }
};

/// The --ready-file: the app's state (stateJson) rewritten atomically whenever it changes, from the
/// first idle frame with a picture on.
struct StateFile {
  explicit StateFile(std::string file) : path(std::move(file)) {}
  std::string path, last;
  bool written = false;

  void update(GLFWwindow* window, const AppState& state, int screenshots) {
    if (path.empty() || !(written || (!state.worker.busy() && !state.source.empty()))) return;
    int win[4];
    glfwGetWindowPos(window, &win[0], &win[1]);
    glfwGetWindowSize(window, &win[2], &win[3]);
    const std::string text = stateJson(state, win, screenshots, state.exportCount);
    if (text != last && writeAtomically(path, text)) {
      last = text;
      written = true;
    }
  }
};

/// F12 with --screenshot-dir: the framebuffer to shot-NNN.png there; `screenshots` counts them.
void saveScreenshotOnF12(const std::string& dir, int fbw, int fbh, int& screenshots) {
  if (dir.empty() || !ImGui::IsKeyPressed(GLFW_KEY_F12, false)) return;
  char name[64];
  std::snprintf(name, sizeof name, "shot-%03d.png", ++screenshots);
  std::filesystem::create_directories(dir);
  if (!saveScreenshot((std::filesystem::path(dir) / name).string(), fbw, fbh)) --screenshots;
}

}  // namespace

int runWindow(const WindowOptions& o) {
  GLFWwindow* window = openWindow(o);
  if (!window) return 1;
  std::signal(SIGTERM, onSignal);
  std::signal(SIGINT, onSignal);

  {
    SignalWaker waker;  // ends (joined) before glfwTerminate
    auto state = std::make_unique<AppState>();
    Renderer renderer;
    if (!renderer.init()) postMessage(*state, "OpenGL: " + renderer.error(), true);
    state->wakeup = [] { glfwPostEmptyEvent(); };
    state->worker.setWakeup(state->wakeup);
    state->nativeDialogs = true;
    state->recentFilesPath = defaultRecentFilesPath();
    state->recentFiles = loadRecentFiles(state->recentFilesPath);
    WindowInput input;
    input.state = state.get();
    installInputCallbacks(window, input);
    state->recoveryPath = o.recoveryPath.empty() ? defaultRecoveryPath() : o.recoveryPath;
    state->exportPath = o.exportPath;
    state->lastAutosave = nowSeconds();
    const bool recovered = hasRecoveryCopy(*state);
    openStartup(*state, o);
    if (recovered)
      postMessage(*state, "Unsaved work from an earlier run was kept: File > Open recovery copy (" + state->recoveryPath + ").",
                  false);

    FrameLog frameLog;
    FramePacing pacing;
    StateFile stateFile(o.readyFile);
    std::string title;
    int screenshots = 0;
    auto previous = std::chrono::steady_clock::now();
    const auto start = previous;
    while (!state->quitConfirmed && !g_terminate) {
      pacing.waitForEvents(*state, input, waker.waitsForever());
      if (glfwWindowShouldClose(window)) {
        glfwSetWindowShouldClose(window, GLFW_FALSE);
        state->quitRequested = true;
      }
      const auto t0 = std::chrono::steady_clock::now();
      pollWorker(*state);
      const auto tApplied = std::chrono::steady_clock::now();
      if (feedKeys(window, input)) pacing.settleFrames = 3;  // the frames ImGui takes to answer them
      ImGui_ImplOpenGL3_NewFrame();
      ImGui_ImplGlfw_NewFrame();
      feedMouse(input);
      ImGui::NewFrame();
      const bool deformed = drawFrame(*state);
      ImGui::Render();
      const auto tUi = std::chrono::steady_clock::now();
      int fbw = 0, fbh = 0;
      glfwGetFramebufferSize(window, &fbw, &fbh);
      glViewport(0, 0, fbw, fbh);
      glClearColor(0.13f, 0.13f, 0.15f, 1.0f);
      glClear(GL_COLOR_BUFFER_BIT);
      const ImVec2 display = ImGui::GetIO().DisplaySize;
      state->frameWanted = false;
      renderer.draw(*state, fbw, fbh, display.x, display.y);
      if (state->frameWanted) pacing.settleFrames = std::max(pacing.settleFrames, 1);  // e.g. the detail texture, once the view is still
      ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
      saveScreenshotOnF12(o.screenshotDir, fbw, fbh, screenshots);
      if (o.slowFramesMs > 0) std::this_thread::sleep_until(t0 + std::chrono::milliseconds(o.slowFramesMs));
      const auto tSubmitted = std::chrono::steady_clock::now();
      glfwSwapBuffers(window);  // a software renderer draws here
      const auto t1 = std::chrono::steady_clock::now();
      state->timings.frameMs = msBetween(t0, t1);
      if (state->releaseStart > 0.0) {  // this frame drew a stroke's (or method switch's) result
        state->timings.releaseToPictureMs = 1e3 * (nowSeconds() - state->releaseStart);
        state->timings.releaseFrameMs = state->timings.frameMs;
        state->releaseStart = 0.0;
      }
      if (!o.frameLog.empty())
        frameLog.add({std::chrono::duration<double>(t1 - start).count(), msBetween(previous, t1), state->timings.deformMs * deformed,
                      state->timings.uploadMs, state->canvasDrag.button >= 0, deformed, long(state->mesh.restVertices().rows()),
                      long(state->timings.uploadBytes), msBetween(t0, tApplied), msBetween(tApplied, tUi), msBetween(tUi, tSubmitted),
                      msBetween(tSubmitted, t1)});
      previous = t1;

      if (const std::string t = windowTitle(*state); t != title) glfwSetWindowTitle(window, (title = t).c_str());
      maybeAutosave(*state, nowSeconds());
      stateFile.update(window, *state, screenshots);
    }
    if (!o.frameLog.empty()) frameLog.write(o.frameLog);
    if (state->quitConfirmed) discardRecoveryCopy(*state);  // a crash or a signal keeps it
    state->worker.cancel();
    pollWorker(*state);
    glfwHideWindow(window);  // the window goes at once; an abandoned bind may still end its solver call
    removeInputCallbacks(window);
  }
  closeWindow(window);
  return 0;
}

}  // namespace kc::ui
