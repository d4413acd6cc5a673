// Files of the document (document.h) and the two file jobs of jobs.h: open session, export.
#include "kc/ui/document.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <new>
#include <nlohmann/json.hpp>

#include "kc/app/errors.h"
#include "kc/app/export.h"
#include "kc/app/draft_cage.h"
#include "kc/app/file_io.h"
#include "kc/app/image_io.h"
#include "kc/app/process.h"
#include "kc/ui/edits.h"
#include "kc/ui/jobs.h"
#include "kc/ui/panels/panels.h"
#include "kc/ui/recent_files.h"

namespace kc::ui {
namespace {

namespace fs = std::filesystem;

bool endsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

}  // namespace

namespace {

/// Forgets the document (picture, session, cage, pose, undo) and the interaction tied to it.
void clearDocument(AppState& state) {
  state.source = Image();
  state.imagePath.clear();
  state.imageUpright = true;
  state.sourceVersion.bump();
  state.session.reset();
  state.bound.reset();
  state.solvingRigidity.reset();
  state.lines = {};
  state.lineSelection.clear();
  state.lineTool.cancel(state);
  state.mesh = WarpMesh{};
  state.meshVersion.bump();
  state.pose.clear();
  state.poseVersion.bump();
  state.selection.clear();
  state.pivot.reset();
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
}

/// The keys of a JSON text's top-level object, read without building anything below it.
class TopLevelKeys final : public nlohmann::json_sax<nlohmann::json> {
 public:
  std::vector<std::string> keys;

  bool null() override { return true; }
  bool boolean(bool) override { return true; }
  bool number_integer(number_integer_t) override { return true; }
  bool number_unsigned(number_unsigned_t) override { return true; }
  bool number_float(number_float_t, const string_t&) override { return true; }
  bool string(string_t&) override { return true; }
  bool binary(binary_t&) override { return true; }
  bool start_object(std::size_t) override { return ++m_depth, true; }
  bool key(string_t& k) override {
    if (m_depth == 1) keys.push_back(k);
    return true;
  }
  bool end_object() override { return --m_depth, true; }
  bool start_array(std::size_t) override { return ++m_depth, true; }
  bool end_array() override { return --m_depth, true; }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override { return false; }

 private:
  int m_depth = 0;
};

/// A JSON file holding a cage (not a session), for Open and drop: a *.json file (not *.kcw.json)
/// that loads as a cage, or one with a mistake that is still meant as a cage — its top-level object
/// has "points" and no "samples" — so that opening it reports the cage's problem, not a session's.
bool isCageFile(const std::string& path) {
  if (endsWith(path, ".kcw.json") || !endsWith(path, ".json")) return false;
  try {
    const std::string text = app::readTextFile(path);  // a cage file's size limit: larger files are sessions
    try {
      app::cageFromJson(text, path);
      return true;
    } catch (const app::InputError&) {
      TopLevelKeys top;
      nlohmann::json::sax_parse(text, &top);
      const auto has = [&](const char* k) { return std::find(top.keys.begin(), top.keys.end(), k) != top.keys.end(); };
      return has("points") && !has("samples");
    }
  } catch (const std::bad_alloc&) {
    app::keepMemoryReserve();  // the session loader tries it next and reports
    return false;
  } catch (const std::exception&) {
    return false;
  }
}

/// The advice of failureText for a file that did not fit in memory.
constexpr const char* kLoadNeedsMore = "opening it needs more memory than is free; nothing was changed";

/// False, with a message naming the path, when there is no such file.
bool fileExists(AppState& state, const std::string& path) {
  std::error_code ec;
  if (fs::exists(path, ec)) return true;
  postMessage(state, "Cannot open " + path + ": no such file.", true);
  return false;
}

}  // namespace

bool openImage(AppState& state, const std::string& path, app::ImageOrientation orientation) {
  Image img;
  const double t0 = nowSeconds();
  try {
    img = app::loadImage(path, orientation);
  } catch (const std::exception& e) {
    postMessage(state, "Cannot open image: " + failureText(e, path, kLoadNeedsMore), true);
    return false;
  }
  if (state.worker.busy()) {
    postMessage(state, "Busy: open the image after the current job has finished.", false);
    return false;
  }
  clearDocument(state);
  state.timings.openMs = 1e3 * (nowSeconds() - t0);
  state.source = std::move(img);
  state.imagePath = fs::absolute(path).string();
  state.imageUpright = orientation == app::ImageOrientation::Upright;
  rememberFile(state, path);
  postMessage(state, "Opened " + path + ": click on the picture to draw a cage around what you want to bend, then Bind.", false);
  return true;
}

void newDocument(AppState& state) {
  if (state.worker.busy()) {
    postMessage(state, "Busy: wait for the current job (or cancel it) first.", false);
    return;
  }
  clearDocument(state);
  postMessage(state, "Open a picture (Ctrl+O) or drop one onto the window.", false);
}

bool openPath(AppState& state, const std::string& path) {
  if (endsWith(path, ".json")) return startOpenSession(state, path);
  return openImage(state, path);
}

bool openAnyFile(AppState& state, const std::string& path) {
  if (!fileExists(state, path)) return false;
  if (isCageFile(path)) return loadCageAndBind(state, path);
  unlessUnsaved(state, "Open", [path](AppState& st) { openPath(st, path); });
  return true;
}

void unlessUnsaved(AppState& state, std::string what, std::function<void(AppState&)> action) {
  if (!state.unsaved) {
    action(state);
    return;
  }
  state.unsavedPrompt = PendingAction{std::move(what), std::move(action)};
}

void openDroppedFiles(AppState& state) {
  if (state.droppedPaths.empty()) return;
  std::vector<std::string> paths;
  paths.swap(state.droppedPaths);
  // The one picture or session replaces the document first (asking when work is unsaved); a cage
  // dropped with a picture then goes onto that picture, whatever order the file manager sent.
  std::string document, cage;
  for (const std::string& p : paths) {
    std::string& slot = isCageFile(p) ? cage : document;
    if (slot.empty()) slot = p;
    else postMessage(state, "Dropped several " + std::string(&slot == &cage ? "cages" : "pictures or sessions") +
                                ": opened only " + slot + ".", false);
  }
  if (document.empty()) {
    if (!cage.empty()) loadCageAndBind(state, cage);
    return;
  }
  if (!fileExists(state, document)) return;
  unlessUnsaved(state, "Open", [document, cage](AppState& st) {
    if (!openPath(st, document) || cage.empty()) return;
    if (endsWith(document, ".json"))
      postMessage(st, "A session brings its own cage: " + cage + " was not loaded.", false);
    else
      loadCageAndBind(st, cage);
  });
}

void rememberFile(AppState& state, const std::string& path) { addRecentFile(state.recentFiles, path, state.recentFilesPath); }

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
        img = app::loadImage(imagePath, s->imageUpright ? app::ImageOrientation::Upright : app::ImageOrientation::AsStored);
        if (img.width != s->imageWidth || img.height != s->imageHeight)
          throw app::InputError(imagePath, "image size differs from the session's");
      } catch (const std::exception& e) {
        warning = failureText(e, imagePath, "the picture needs more memory than is free") + " — showing a grey placeholder.";
        img = Image(s->imageWidth, s->imageHeight, Rgba{128, 128, 128, 255});
        imagePath.clear();
      }
      ctx.progress("warp mesh", 0.8);
      DisplayMesh display =
          buildDisplayMesh(*s, app::warpMeshOptionsFor(*s, sessionOutsideMode(*s)));
      auto image = std::make_shared<Image>(std::move(img));
      return [s, display, image, imagePath, path, warning](AppState& st) {
        st.source = std::move(*image);
        st.sourceVersion.bump();
        st.imagePath = imagePath.empty() ? std::string() : fs::absolute(imagePath).string();
        st.imageUpright = s->imageUpright;
        installSession(st, s, display);
        st.sessionPath = path;
        st.unsaved = false;
        st.tool = Tool::Pose;
        rememberFile(st, path);
        st.fitPending = true;
        postMessage(st, warning.empty() ? "Opened " + path : warning, !warning.empty());
      };
    } catch (const std::exception& e) {
      const std::string text = "Cannot open session: " + failureText(e, path, kLoadNeedsMore);
      return [text](AppState& st) { postMessage(st, text, true); };
    }
  });
  return true;
}

std::string failureText(const std::exception& e, const std::string& where, const std::string& advice) {
  if (dynamic_cast<const std::bad_alloc*>(&e) == nullptr) return e.what();
  app::keepMemoryReserve();
  return (where.empty() ? std::string() : app::oneLine(where, app::kMaxMessageWhere) + ": ") + "out of memory: " + advice;
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
  options.mesh = app::warpMeshOptionsFor(*s, state.outside);  // the view's mesh and mode, as `kcwarp-cli warp --outside`
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
        ++st.exportCount;
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

bool startSaveSession(AppState& state, const std::string& path, bool autosave) {
  if (!state.session || state.worker.busy()) {
    if (!autosave)
      postMessage(state, state.bound ? "Busy: save after the current job has finished." : "Nothing to save: bind a cage first.", false);
    return false;
  }
  auto s = std::move(state.session);
  // The job owns the session meanwhile: set the pose and the image path the file refers to.
  s->pose = state.pose;
  s->outside = state.outside;
  const std::string storedImage = s->image;
  if (!state.imagePath.empty()) s->image = app::imagePathForSession(state.imagePath, path);
  const Version pose = state.poseVersion;
  state.worker.submit(autosave ? "Autosaving" : "Saving",
                      [s, path, storedImage, autosave, pose](JobContext& ctx) -> Worker::Apply {
                        std::string error;
                        try {
                          ctx.progress("writing", 0.3);
                          if (autosave) fs::create_directories(fs::path(path).parent_path());
                          app::writeFileAtomic(path, app::sessionToJson(*s));
                        } catch (const std::exception& e) {
                          error = e.what();
                        }
                        s->image = storedImage;
                        return [s, path, autosave, pose, error](AppState& st) {
                          st.session = s;
                          if (!error.empty()) {
                            st.afterSave = nullptr;
                            postMessage(st, std::string(autosave ? "Autosave failed: " : "Save failed: ") + error, true);
                            return;
                          }
                          if (autosave) return;
                          st.sessionPath = path;
                          st.unsaved = st.poseVersion != pose;  // a drag during the save is still unsaved
                          rememberFile(st, path);
                          postMessage(st, "Saved " + path, false);
                          if (auto then = std::move(st.afterSave)) {
                            st.afterSave = nullptr;
                            then(st);
                          }
                        };
                      });
  return true;
}

bool saveSessionFile(AppState& state, const std::string& path) { return startSaveSession(state, path, false); }

void whenIdle(AppState& state, std::function<void(AppState&)> action) {
  if (state.worker.busy() || (state.bound && !state.session)) {
    postMessage(state, "After the current job: " + state.worker.name() + "...", false);
    state.deferred.push_back(std::move(action));
    return;
  }
  action(state);
}

void runDeferred(AppState& state) {
  if (state.deferred.empty() || state.worker.busy() || (state.bound && !state.session)) return;
  auto action = std::move(state.deferred.front());
  state.deferred.erase(state.deferred.begin());
  action(state);
}

namespace {
/// `path` when no file is there, else the first of <stem>-2<ext>, <stem>-3<ext>, … that is free.
std::string freeName(const fs::path& path, const std::string& ext) {
  std::error_code ec;
  const fs::path stem = path.parent_path() / path.filename().string().substr(0, path.filename().string().size() - ext.size());
  fs::path p = path;
  for (int k = 2; fs::exists(p, ec) && k < 10000; ++k) p = stem.string() + "-" + std::to_string(k) + ext;
  return p.string();
}

/// The picture's path without its extension ("untitled" in the working folder without one).
fs::path pictureStem(const AppState& state) {
  if (state.imagePath.empty()) return "untitled";
  fs::path p(state.imagePath);
  return p.parent_path() / p.stem();
}
}  // namespace

std::string proposedSessionPath(const AppState& state) { return freeName(pictureStem(state).string() + ".kcw.json", ".kcw.json"); }

std::string proposedExportPath(const AppState& state) {
  if (!state.exportPath.empty()) {
    const fs::path e(state.exportPath);
    return freeName(e, e.extension().string());
  }
  return freeName(pictureStem(state).string() + "-warped.png", ".png");
}

void saveCommand(AppState& state, bool saveAs) {
  whenIdle(state, [saveAs](AppState& st) {
    if (!st.session) return;
    if (saveAs || st.sessionPath.empty())
      requestPath(st, PathPurpose::SaveSession, st.sessionPath.empty() ? proposedSessionPath(st) : st.sessionPath);
    else
      saveSessionFile(st, st.sessionPath);
  });
}

void exportCommand(AppState& state, bool exportAs) {
  whenIdle(state, [exportAs](AppState& st) {
    if (!st.session) return;
    if (exportAs || st.exportPath.empty()) requestPath(st, PathPurpose::Export, proposedExportPath(st));
    else startExport(st, st.exportPath);
  });
}

bool saveCageFile(AppState& state, const std::string& path) {
  try {
    app::saveCage(path, state.cage);
  } catch (const std::exception& e) {
    state.afterSave = nullptr;
    postMessage(state, std::string("Cannot save cage: ") + e.what(), true);
    return false;
  }
  postMessage(state, "Saved cage " + path, false);
  rememberFile(state, path);
  if (!state.bound) state.unsaved = false;  // an unbound cage is the whole of the work
  if (auto then = std::move(state.afterSave)) {
    state.afterSave = nullptr;
    then(state);
  }
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
    postMessage(state, "Cannot load cage: " + failureText(e, path, kLoadNeedsMore), true);
    return false;
  }
  postMessage(state, "Loaded cage " + path + (state.cageValid ? "." : ": " + state.cageStatus), !state.cageValid);
  return true;
}

bool loadCageAndBind(AppState& state, const std::string& path) {
  if (state.source.empty()) {
    postMessage(state, "Open a picture first, then its cage.", true);
    return false;
  }
  if (!loadCageFile(state, path)) return false;
  rememberFile(state, path);
  if (state.cageValid) requestBind(state);
  return true;
}

std::string defaultRecoveryPath() {
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  const char* home = std::getenv("HOME");
  fs::path base = xdg && *xdg ? fs::path(xdg) : fs::path(home ? home : "/tmp") / ".cache";
  return (base / "kcwarp" / "recovery.kcw.json").string();
}

std::string recoveryCagePath(const AppState& state) {
  std::string p = state.recoveryPath;
  if (endsWith(p, ".kcw.json")) p.resize(p.size() - 9);
  return p.empty() ? p : p + ".cage.json";
}

namespace {

/// The recovery copy of an unbound draft cage: its points, edges, closed flag and the picture.
void writeCageRecovery(const AppState& state) {
  fs::create_directories(fs::path(recoveryCagePath(state)).parent_path());
  app::saveDraftCage(recoveryCagePath(state), {state.cage, state.imagePath, state.imageUpright});
}

}  // namespace

bool maybeAutosave(AppState& state, double now, double interval) {
  if (!state.unsaved || state.recoveryPath.empty() || now - state.lastAutosave < interval) return false;
  if (state.session) {
    if (state.worker.busy()) return false;
    state.lastAutosave = now;
    return startSaveSession(state, state.recoveryPath, true);
  }
  if (state.bound || state.cage.size() == 0 || state.imagePath.empty()) return false;  // a job holds the session, or nothing to keep
  state.lastAutosave = now;
  try {
    writeCageRecovery(state);
  } catch (const std::exception& e) {
    postMessage(state, std::string("Autosave failed: ") + e.what(), true);
    return false;
  }
  return true;
}

bool hasRecoveryCopy(const AppState& state) {
  std::error_code ec;
  return !state.recoveryPath.empty() && (fs::exists(state.recoveryPath, ec) || fs::exists(recoveryCagePath(state), ec));
}

bool openRecoveryCopy(AppState& state) {
  std::error_code ec;
  if (fs::exists(state.recoveryPath, ec)) return startOpenSession(state, state.recoveryPath);
  try {
    app::DraftCage draft = app::loadDraftCage(recoveryCagePath(state));
    if (!openImage(state, draft.image, draft.imageUpright ? app::ImageOrientation::Upright : app::ImageOrientation::AsStored))
      return false;
    setDraftCage(state, std::move(draft.cage));
    state.unsaved = true;  // recovered work is not saved anywhere else
    postMessage(state, "Recovered the cage on " + draft.image + (state.cageValid ? ": press Bind." : "."), false);
    return true;
  } catch (const std::exception& e) {
    postMessage(state, "Cannot open the recovery copy: " + failureText(e, recoveryCagePath(state), kLoadNeedsMore), true);
    return false;
  }
}

void discardRecoveryCopy(const AppState& state) {
  std::error_code ec;
  if (state.recoveryPath.empty()) return;
  fs::remove(state.recoveryPath, ec);
  fs::remove(recoveryCagePath(state), ec);
}

std::string windowTitle(const AppState& state) {
  std::string name = !state.sessionPath.empty() ? fs::path(state.sessionPath).filename().string()
                     : !state.imagePath.empty() ? fs::path(state.imagePath).filename().string()
                                                : std::string("untitled");
  return "kcwarp - " + name + (state.unsaved ? " *" : "");
}

}  // namespace kc::ui
