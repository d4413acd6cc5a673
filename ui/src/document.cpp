// Files of the document (document.h) and the two file jobs of jobs.h: open session, export.
#include "kc/ui/document.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "kc/app/errors.h"
#include "kc/app/export.h"
#include "kc/app/file_io.h"
#include "kc/app/image_io.h"
#include "kc/ui/edits.h"
#include "kc/ui/jobs.h"

namespace kc::ui {
namespace {

namespace fs = std::filesystem;

bool endsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

/// The session to save: the document's session with the current pose.
std::string sessionJson(const AppState& state, const std::string& path) {
  app::Session& s = *state.session;
  s.pose = state.pose;
  s.outside = toString(state.outside);
  const std::string stored = s.image;
  if (!state.imagePath.empty() && !path.empty()) s.image = app::imagePathForSession(state.imagePath, path);
  std::string text = app::sessionToJson(s);
  s.image = stored;
  return text;
}

}  // namespace

bool openImage(AppState& state, const std::string& path) {
  Image img;
  try {
    img = app::loadImage(path);
  } catch (const std::exception& e) {
    postMessage(state, std::string("Cannot open image: ") + e.what(), true);
    return false;
  }
  if (state.worker.busy()) {
    postMessage(state, "Busy: open the image after the current job has finished.", false);
    return false;
  }
  state.source = std::move(img);
  state.imagePath = fs::absolute(path).string();
  ++state.sourceRevision;
  state.session.reset();
  state.bound = false;
  state.boundCage = Cage{};
  state.samples = SampleSet{};
  state.mesh = WarpMesh{};
  ++state.meshRevision;
  state.pose.clear();
  ++state.poseRevision;
  state.selection.clear();
  state.activeControl = -1;
  state.sessionPath.clear();
  state.undo.clear();
  state.diagnostics.reset();
  Cage empty;
  empty.closed = false;
  setDraftCage(state, empty);
  state.tool = Tool::Cage;
  state.fitPending = true;
  state.unsaved = false;
  postMessage(state, "Opened " + path + ": click on the picture to draw a cage, then Bind.", false);
  return true;
}

bool openPath(AppState& state, const std::string& path) {
  if (endsWith(path, ".json")) return startOpenSession(state, path);
  return openImage(state, path);
}

bool startOpenSession(AppState& state, const std::string& path) {
  if (state.worker.busy()) {
    postMessage(state, "Busy: open the session after the current job has finished.", false);
    return false;
  }
  state.worker.submit("Opening session", [path](JobContext& ctx) -> Worker::Apply {
    try {
      ctx.progress("reading", 0.1);
      auto s = std::make_shared<app::Session>(app::loadSession(path));
      ctx.progress("image", 0.6);
      std::string imagePath = app::resolveSessionImage(s->image, path);
      Image img;
      std::string warning;
      try {
        if (imagePath.empty()) throw app::InputError(path, "the session names no image");
        img = app::loadImage(imagePath);
        if (img.width != s->imageWidth || img.height != s->imageHeight)
          throw app::InputError(imagePath, "image size differs from the session's");
      } catch (const std::exception& e) {
        warning = std::string(e.what()) + " — showing a grey placeholder.";
        img = Image(s->imageWidth, s->imageHeight, Rgba{128, 128, 128, 255});
        imagePath.clear();
      }
      ctx.progress("warp mesh", 0.8);
      DisplayMesh display =
          buildDisplayMesh(*s, displayMeshOptions(s->imageWidth, s->imageHeight, sessionOutsideMode(*s)));
      auto image = std::make_shared<Image>(std::move(img));
      return [s, display, image, imagePath, path, warning](AppState& st) {
        st.source = std::move(*image);
        ++st.sourceRevision;
        st.imagePath = imagePath.empty() ? std::string() : fs::absolute(imagePath).string();
        installSession(st, s, display);
        st.sessionPath = path;
        st.unsaved = false;
        st.tool = Tool::Pose;
        st.fitPending = true;
        postMessage(st, warning.empty() ? "Opened " + path : warning, !warning.empty());
      };
    } catch (const std::exception& e) {
      const std::string text = std::string("Cannot open session: ") + e.what();
      return [text](AppState& st) { postMessage(st, text, true); };
    }
  });
  return true;
}

bool startExport(AppState& state, const std::string& path) {
  if (!state.session || state.worker.busy()) {
    postMessage(state, state.bound ? "Busy: export after the current job has finished." : "Bind a cage before exporting.", false);
    return false;
  }
  auto s = std::move(state.session);
  auto source = std::make_shared<const Image>(state.source);
  const Pose pose = state.pose;
  app::WarpExportOptions options;
  options.mesh.outside = state.outside;  // the same mode as the view, as `kcwarp-cli warp --outside`
  state.worker.submit("Exporting", [s, source, pose, path, options](JobContext& ctx) -> Worker::Apply {
    try {
      const auto t0 = std::chrono::steady_clock::now();
      ctx.progress("warping", 0.2);
      app::WarpExportReport report;
      const Image out = app::warpSessionImage(*s, *source, pose, options, &report);
      ctx.progress("writing", 0.8);
      app::saveImage(path, out);
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      char text[512];
      std::snprintf(text, sizeof text, "Exported %s (%dx%d, %ld flipped triangles) in %.0f ms.", path.c_str(), out.width,
                    out.height, long(report.deform.flippedTriangles), ms);
      const std::string message = text;
      return [s, message](AppState& st) {
        st.session = s;
        postMessage(st, message, false);
      };
    } catch (const std::exception& e) {
      const std::string text = std::string("Export failed: ") + e.what();
      return [s, text](AppState& st) {
        st.session = s;
        postMessage(st, text, true);
      };
    }
  });
  return true;
}

bool saveSessionFile(AppState& state, const std::string& path) {
  if (!state.session) {
    postMessage(state, state.bound ? "Busy: save after the current job has finished." : "Nothing to save: bind a cage first.", false);
    return false;
  }
  try {
    app::writeFileAtomic(path, sessionJson(state, path));
  } catch (const std::exception& e) {
    postMessage(state, std::string("Save failed: ") + e.what(), true);
    return false;
  }
  state.sessionPath = path;
  state.unsaved = false;
  postMessage(state, "Saved " + path, false);
  return true;
}

bool saveCageFile(AppState& state, const std::string& path) {
  try {
    app::saveCage(path, state.cage);
  } catch (const std::exception& e) {
    postMessage(state, std::string("Cannot save cage: ") + e.what(), true);
    return false;
  }
  postMessage(state, "Saved cage " + path, false);
  return true;
}

bool loadCageFile(AppState& state, const std::string& path) {
  try {
    Cage cage = app::loadCage(path);
    const Cage before = state.cage;
    setDraftCage(state, std::move(cage));
    commitCage(state, before, "load cage");
    state.tool = Tool::Cage;
  } catch (const std::exception& e) {
    postMessage(state, std::string("Cannot load cage: ") + e.what(), true);
    return false;
  }
  postMessage(state, "Loaded cage " + path + (state.cageValid ? ": press Bind." : ": " + state.cageStatus), !state.cageValid);
  return true;
}

std::string defaultRecoveryPath() {
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  const char* home = std::getenv("HOME");
  fs::path base = xdg && *xdg ? fs::path(xdg) : fs::path(home ? home : "/tmp") / ".cache";
  return (base / "kcwarp" / "recovery.kcw.json").string();
}

bool maybeAutosave(AppState& state, double now, double interval) {
  if (!state.unsaved || !state.session || state.recoveryPath.empty()) return false;
  if (now - state.lastAutosave < interval) return false;
  state.lastAutosave = now;
  try {
    fs::create_directories(fs::path(state.recoveryPath).parent_path());
    app::writeFileAtomic(state.recoveryPath, sessionJson(state, state.recoveryPath));
  } catch (const std::exception& e) {
    postMessage(state, std::string("Autosave failed: ") + e.what(), true);
    return false;
  }
  return true;
}

bool hasRecoveryCopy(const AppState& state) {
  std::error_code ec;
  return !state.recoveryPath.empty() && fs::exists(state.recoveryPath, ec);
}

void discardRecoveryCopy(const AppState& state) {
  std::error_code ec;
  if (!state.recoveryPath.empty()) fs::remove(state.recoveryPath, ec);
}

std::string windowTitle(const AppState& state) {
  std::string name = !state.sessionPath.empty() ? fs::path(state.sessionPath).filename().string()
                     : !state.imagePath.empty() ? fs::path(state.imagePath).filename().string()
                                                : std::string("untitled");
  return "kcwarp - " + name + (state.unsaved ? " *" : "");
}

}  // namespace kc::ui
