#include "kc/ui/document.h"

#include <GLFW/glfw3.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <chrono>
#include <fstream>
#include <optional>
#include <thread>

#include "cli_run.h"
#include "exif_jpeg.h"
#include "kc/app/draft_cage.h"
#include "kc/app/file_io.h"
#include "kc/app/image_io.h"
#include "kc/app/pipeline.h"
#include "kc/ui/file_dialog.h"
#include "kc/ui/panels/panels.h"
#include "kc/ui/recent_files.h"
#include "kc/ui/shortcuts.h"
#include "scene_image.h"
#include "ui_fixture.h"

namespace kc::test {
namespace {

namespace fs = std::filesystem;

TEST(Recovery, AutosaveWritesALoadableCopyAndANormalQuitRemovesIt) {
  auto state = boundState();
  const auto dir = scratchDir("ui_recovery");
  state->recoveryPath = (dir / "recovery.kcw.json").string();
  state->lastAutosave = 0.0;

  state->unsaved = false;
  EXPECT_FALSE(ui::maybeAutosave(*state, 1000.0));  // nothing unsaved: nothing written
  EXPECT_FALSE(ui::hasRecoveryCopy(*state));

  state->unsaved = true;
  EXPECT_FALSE(ui::maybeAutosave(*state, 30.0));    // less than a minute since the last one
  EXPECT_TRUE(ui::maybeAutosave(*state, 61.0));     // a save job (inline in tests)
  ui::pollWorker(*state);
  ASSERT_TRUE(state->session);
  ASSERT_TRUE(ui::hasRecoveryCopy(*state));
  EXPECT_TRUE(state->unsaved) << "an autosave is not a save";
  const app::Session copy = app::loadSession(state->recoveryPath);
  EXPECT_EQ(copy.W, state->session->W);
  EXPECT_EQ(copy.cage.C, state->session->cage.C);

  ui::discardRecoveryCopy(*state);
  EXPECT_FALSE(ui::hasRecoveryCopy(*state));
}

TEST(Recovery, AnUnboundCageIsAutosavedAndRecovered) {
  const auto dir = scratchDir("ui_recovery_cage");
  const std::string image = (dir / "scene.png").string();
  app::saveImage(image, sceneImage(300, 200));
  ui::AppState s;
  s.worker.setSynchronous(true);
  s.recoveryPath = (dir / "recovery.kcw.json").string();
  ASSERT_TRUE(ui::openImage(s, image));
  EXPECT_FALSE(s.unsaved);
  Points C(3, 2);
  C << 100, 50, 200, 60, 150, 150;
  const Cage before = s.cage;
  ui::setDraftCage(s, Cage::polygon(C));
  ui::commitCage(s, before, "draw");
  ASSERT_TRUE(s.unsaved);
  ASSERT_TRUE(ui::maybeAutosave(s, 100.0));
  ASSERT_TRUE(ui::hasRecoveryCopy(s));
  EXPECT_TRUE(fs::exists(ui::recoveryCagePath(s)));

  ui::AppState t;  // a later run
  t.worker.setSynchronous(true);
  t.recoveryPath = s.recoveryPath;
  ASSERT_TRUE(ui::openRecoveryCopy(t));
  EXPECT_EQ(t.source.width, 300);
  EXPECT_TRUE(t.cage.closed);
  EXPECT_EQ(t.cage.C, C);
  EXPECT_TRUE(t.cageValid);
  ui::discardRecoveryCopy(t);
  EXPECT_FALSE(ui::hasRecoveryCopy(t));
}

TEST(Recovery, AnUnfinishedCageIsRecoveredAsDrawn) {
  // Open, two points, and a closed one crossing itself: drafts, kept as they were.
  const auto dir = scratchDir("ui_recovery_draft");
  const std::string image = (dir / "scene.png").string();
  app::saveImage(image, sceneImage(300, 200));
  Points open(2, 2), bow(4, 2);
  open << 10, 10, 50, 20;
  bow << 100, 50, 200, 150, 200, 50, 100, 150;
  for (const Cage& drawn : {Cage{open, {{0, 1}}, false}, Cage::polygon(bow)}) {
    app::saveDraftCage((dir / "recovery.cage.json").string(), {drawn, image});
    ui::AppState t;
    t.worker.setSynchronous(true);
    t.recoveryPath = (dir / "recovery.kcw.json").string();
    ASSERT_TRUE(ui::openRecoveryCopy(t)) << (t.messages.empty() ? "" : t.messages.back().text);
    EXPECT_EQ(t.cage.C, drawn.C);
    EXPECT_EQ(t.cage.edges, drawn.edges);
    EXPECT_EQ(t.cage.closed, drawn.closed);
    if (drawn.closed) {
      EXPECT_FALSE(t.cageValid) << "the crossing cage is a draft, not a cage to bind";
    }
  }
}

TEST(Recovery, APhonePhotoOpensUprightAndOlderFilesKeepThePictureAsTheyDrewOnIt) {
  // Stored 48x32, shown 32x48 (Exif orientation 8: turned 90 degrees anticlockwise).
  const auto dir = scratchDir("ui_exif");
  const std::string photo = (dir / "photo.jpg").string();
  writeBytes(photo, withSegment(app::encodeImage(quadrantPicture(48, 32), ".jpg"), exifSegment(orientationEntry(8, true), true)));
  ui::AppState s;
  s.worker.setSynchronous(true);
  s.recoveryPath = (dir / "recovery.kcw.json").string();
  ASSERT_TRUE(ui::openImage(s, photo));
  EXPECT_EQ(s.source.width, 32);
  EXPECT_EQ(quadrantLayout(s.source), "GWRB");
  EXPECT_TRUE(s.imageUpright);
  Points C(3, 2);
  C << 4, 4, 28, 6, 16, 40;  // inside the upright picture only
  const Cage before = s.cage;
  ui::setDraftCage(s, Cage::polygon(C));
  ui::commitCage(s, before, "draw");
  ASSERT_TRUE(ui::maybeAutosave(s, 100.0));
  EXPECT_TRUE(app::loadDraftCage(ui::recoveryCagePath(s)).imageUpright);

  // A cage copy written before kcwarp read the orientation (no image_upright): the picture as stored.
  Points D(3, 2);
  D << 4, 4, 44, 6, 20, 28;
  app::saveDraftCage(ui::recoveryCagePath(s), {Cage::polygon(D), photo, false});
  ui::AppState t;
  t.worker.setSynchronous(true);
  t.recoveryPath = s.recoveryPath;
  ASSERT_TRUE(ui::openRecoveryCopy(t));
  EXPECT_EQ(t.source.width, 48);
  EXPECT_EQ(quadrantLayout(t.source), "RGBW");
  EXPECT_FALSE(t.imageUpright);
  ui::discardRecoveryCopy(t);

  // A session bound on the picture as stored, written before kcwarp read the orientation: it opens
  // with its picture as stored (not the grey placeholder of a picture whose size differs).
  app::Session old = app::bind(Cage::polygon(D), 48, 32, app::BindParams{});
  old.image = photo;
  old.imageUpright = false;
  app::saveSession((dir / "old.kcw.json").string(), old);
  EXPECT_EQ(slurp(dir / "old.kcw.json").find("image_upright"), std::string::npos);
  ui::AppState u;
  u.worker.setSynchronous(true);
  ASSERT_TRUE(ui::openPath(u, (dir / "old.kcw.json").string()));
  u.worker.waitFinished();
  ui::pollWorker(u);
  ASSERT_TRUE(u.bound);
  EXPECT_EQ(u.source.width, 48);
  EXPECT_EQ(quadrantLayout(u.source), "RGBW");
  EXPECT_FALSE(u.imageUpright);
  EXPECT_FALSE(u.messages.back().error) << u.messages.back().text;
}

TEST(Recovery, ACorruptCageCopyIsRefusedAndNothingChanges) {
  const auto dir = scratchDir("ui_recovery_corrupt");
  const std::string image = (dir / "scene.png").string(), other = (dir / "other.png").string();
  app::saveImage(image, sceneImage(300, 200));
  app::saveImage(other, sceneImage(120, 90));
  const std::string head = R"({"version": 1, "image": ")" + image + R"(", )";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {head + R"("points": [[10, 10], [50, 20], [30, 40]], "closed": true, "edges": [[0, 1], [1, 7]]})", "edges[1][1]"},
      {head + R"("points": [[10, 10], [50, 20], [30, "x"]], "closed": true, "edges": []})", "points"},
      {head + R"("points": [[10, 10], [50, 20]], "closed": "yes", "edges": []})", "closed"},
      {R"({"version": 1, "image": 7, "points": [[10, 10], [50, 20]], "closed": false, "edges": [[0, 1]]})", "image"},
      {head + R"("points": [[10, 10], [50, 20]], "closed": false, "edges": [[0, 1])", "malformed JSON"},
      {head + R"("points": [[10, 10], [50, 20]], "closed": false, "edges": [[0, 1]], "image_upright": 1})", "image_upright"},
  };
  for (const auto& [text, problem] : cases) {
    SCOPED_TRACE(text);
    writeText(dir / "recovery.cage.json", text);
    ui::AppState t;
    t.worker.setSynchronous(true);
    t.recoveryPath = (dir / "recovery.kcw.json").string();
    ASSERT_TRUE(ui::openImage(t, other));
    EXPECT_FALSE(ui::openRecoveryCopy(t));
    ASSERT_FALSE(t.messages.empty());
    const std::string said = t.messages.back().text;
    EXPECT_TRUE(t.messages.back().error) << said;
    EXPECT_NE(said.find("recovery.cage.json"), std::string::npos) << said;
    EXPECT_NE(said.find(problem), std::string::npos) << said;
    EXPECT_EQ(t.imagePath, other) << "a failed recovery changed the document";
    EXPECT_EQ(t.cage.size(), 0);
  }
}

TEST(Files, DroppedPictureAndCageOpenTheOneAndBindTheOther) {
  const auto dir = scratchDir("ui_drop");
  const std::string picture = (dir / "scene.png").string(), other = (dir / "other.png").string();
  const std::string cage = (dir / "scene.cage.json").string(), broken = (dir / "broken.png").string();
  app::saveImage(picture, sceneImage(200, 150));
  app::saveImage(other, sceneImage(120, 90));
  writeText(dir / "broken.png", "not a picture");
  Points C(4, 2);
  C << 60, 40, 140, 40, 140, 110, 60, 110;
  app::saveCage(cage, Cage::polygon(C));

  ui::AppState s;
  s.worker.setSynchronous(true);
  s.autoSpacing = false;
  s.bindParams.spacing = 10.0;
  // The file manager may list the cage first: it still goes onto the dropped picture.
  s.droppedPaths = {cage, picture};
  ui::openDroppedFiles(s);
  ui::pollWorker(s);
  EXPECT_TRUE(s.droppedPaths.empty());
  EXPECT_EQ(s.source.width, 200);
  EXPECT_EQ(fs::path(s.imagePath).filename(), "scene.png");
  EXPECT_EQ(s.cage.C, C);
  ASSERT_TRUE(s.session) << "a dropped cage is bound";
  EXPECT_EQ(s.session->cage.C, C);

  // Unsaved work: a dropped picture asks first and leaves the document as it is until answered.
  s.unsaved = true;
  s.droppedPaths = {other};
  ui::openDroppedFiles(s);
  ASSERT_TRUE(s.unsavedPrompt.has_value());
  EXPECT_EQ(s.source.width, 200);
  EXPECT_TRUE(s.session);
  auto discard = std::move(s.unsavedPrompt->run);
  s.unsavedPrompt.reset();
  discard(s);
  EXPECT_EQ(s.source.width, 120);
  EXPECT_FALSE(s.session);

  // A file that is not a picture: an error naming it, and the open picture stays.
  s.unsaved = false;
  const size_t before = s.messages.size();
  s.droppedPaths = {broken};
  ui::openDroppedFiles(s);
  EXPECT_EQ(s.source.width, 120);
  ASSERT_GT(s.messages.size(), before);
  EXPECT_TRUE(s.messages.back().error);
  EXPECT_NE(s.messages.back().text.find("broken.png"), std::string::npos) << s.messages.back().text;

  // A path that is gone by the time it is handled: the same, without asking about unsaved work.
  s.unsaved = true;
  s.droppedPaths = {(dir / "gone.png").string()};
  ui::openDroppedFiles(s);
  EXPECT_FALSE(s.unsavedPrompt.has_value());
  EXPECT_EQ(s.source.width, 120);
  EXPECT_TRUE(s.messages.back().error);
  EXPECT_NE(s.messages.back().text.find("gone.png: no such file"), std::string::npos) << s.messages.back().text;
}

TEST(Files, RecentListKeepsNewestFirstWithoutDuplicates) {
  const auto dir = scratchDir("ui_recent");
  const std::string list = (dir / "cfg" / "recent.txt").string();
  std::vector<std::string> recent;
  for (const char* name : {"a.png", "b.png", "a.png"}) {
    writeText(dir / name, "x");
    ui::addRecentFile(recent, (dir / name).string(), list);
  }
  ASSERT_EQ(recent.size(), 2u);
  EXPECT_EQ(fs::path(recent[0]).filename(), "a.png");
  EXPECT_EQ(ui::loadRecentFiles(list), recent);
  fs::remove(dir / "b.png");  // files that are gone drop out of the menu
  EXPECT_EQ(ui::loadRecentFiles(list).size(), 1u);
}

TEST(Files, BrowserListsFoldersThenMatchingFiles) {
  const auto dir = scratchDir("ui_browser");
  fs::create_directories(dir / "pictures");
  fs::create_directories(dir / ".hidden");
  for (const char* name : {"b.png", "A.JPG", "s.kcw.json", "notes.txt"}) writeText(dir / name, "x");
  const auto entries = ui::listFolder(dir.string(), ui::PathPurpose::Open);
  ASSERT_EQ(entries.size(), 4u);
  EXPECT_TRUE(entries[0].directory);
  EXPECT_EQ(entries[0].name, "pictures");
  EXPECT_EQ(entries[1].name, "A.JPG");
  EXPECT_EQ(entries[2].name, "b.png");
  EXPECT_EQ(entries[3].name, "s.kcw.json");
  EXPECT_EQ(ui::listFolder(dir.string(), ui::PathPurpose::Export).size(), 2u);  // pictures/, b.png
}

/// Sets an environment variable (unsets it when `value` is null) until the end of the scope, then
/// puts back what it was.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : m_name(name) {
    if (const char* old = std::getenv(name)) m_old = old;
    if (value) setenv(name, value, 1);
    else unsetenv(name);
  }
  ~ScopedEnv() {
    if (m_old) setenv(m_name.c_str(), m_old->c_str(), 1);
    else unsetenv(m_name.c_str());
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  std::string m_name;
  std::optional<std::string> m_old;
};

TEST(Files, NativeDialogRunsZenityAndReadsTheChosenPath) {
  // A window test run earlier in the same process turns native dialogs off (GuiSession::SetUp).
  const ScopedEnv nativeDialogs("KCWARP_NO_NATIVE_DIALOG", nullptr);
  const auto dir = scratchDir("ui_zenity");
  // A stand-in zenity on PATH that records its arguments and answers with a path.
  writeText(dir / "zenity", "#!/bin/sh\nprintf '%s\\n' \"$@\" > \"" + (dir / "args.txt").string() +
                                "\"\necho /tmp/chosen.kcw.json\n");
  fs::permissions(dir / "zenity", fs::perms::owner_all);
  {
    const ScopedEnv path("PATH", (dir.string() + ":" + (std::getenv("PATH") ? std::getenv("PATH") : "")).c_str());
    EXPECT_EQ(ui::nativeDialogProgram(), "zenity");
    ui::NativeDialog dialog(ui::nativeDialogCommand("zenity", ui::PathPurpose::SaveSession, "/tmp/untitled.kcw.json"),
                            ui::PathPurpose::SaveSession, {});
    for (int k = 0; k < 200 && !dialog.done(); ++k) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    ASSERT_TRUE(dialog.done());
    EXPECT_EQ(dialog.result().value_or(""), "/tmp/chosen.kcw.json");
  }
  const std::string args = slurp(dir / "args.txt");
  EXPECT_NE(args.find("--save"), std::string::npos) << args;
  EXPECT_NE(args.find("--filename=/tmp/untitled.kcw.json"), std::string::npos) << args;
  // Cancel (exit code 1): no path.
  EXPECT_FALSE(ui::runForOutput({"sh", "-c", "echo /tmp/x; exit 1"}).has_value());
}


TEST(FileNames, SaveProposesThePicturesNameAndExportANewFile) {
  auto state = boundState();
  const auto dir = scratchDir("ui_file_names");
  state->imagePath = (dir / "portrait.png").string();
  EXPECT_EQ(ui::proposedSessionPath(*state), (dir / "portrait.kcw.json").string());
  EXPECT_EQ(ui::proposedExportPath(*state), (dir / "portrait-warped.png").string());
  std::ofstream(dir / "portrait.kcw.json") << "{}";
  std::ofstream(dir / "portrait-warped.png") << "x";
  std::ofstream(dir / "portrait-warped-2.png") << "x";
  EXPECT_EQ(ui::proposedSessionPath(*state), (dir / "portrait-2.kcw.json").string()) << "never a file that is there";
  EXPECT_EQ(ui::proposedExportPath(*state), (dir / "portrait-warped-3.png").string());
  state->exportPath = (dir / "portrait-warped.png").string();  // the last export's file exists: a new one
  EXPECT_EQ(ui::proposedExportPath(*state), (dir / "portrait-warped-3.png").string());
}

TEST(FileNames, AReturnAcceptsTheTypedPath) {
  // A Return down for one frame (the window holds a tapped Return down for a frame: feedKeys;
  // tests/ui/input_e2e_test.cpp taps it between slowed frames) accepts the path.
  HeadlessImGui gui;
  auto state = boundState();
  const auto dir = scratchDir("ui_return_tap");
  const fs::path target = dir / "tapped.png";
  ui::requestPath(*state, ui::PathPurpose::Export, target.string());
  auto draw = [&] {
    ui::handleShortcuts(*state);
    ui::drawDialogs(*state);
  };
  gui.frame(draw);
  gui.frame(draw);  // the path field has the keyboard
  ASSERT_EQ(state->pathDialog, ui::PathPurpose::Export);
  gui.frame(draw);
  EXPECT_EQ(state->pathDialog, ui::PathPurpose::Export) << "no key, no choice";
  ImGui::GetIO().KeysDown[GLFW_KEY_ENTER] = true;
  gui.frame(draw);
  ImGui::GetIO().KeysDown[GLFW_KEY_ENTER] = false;
  EXPECT_EQ(state->pathDialog, ui::PathPurpose::None);
  ui::pollWorker(*state);
  for (int k = 0; k < 200 && !fs::exists(target); ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    ui::pollWorker(*state);
  }
  EXPECT_TRUE(fs::exists(target)) << "the export ran";
}

TEST(FileNames, TheFileDialogAsksBeforeSavingOverAFile) {
  HeadlessImGui gui;
  auto state = boundState();
  const auto dir = scratchDir("ui_replace");
  const fs::path target = dir / "there.png";
  std::ofstream(target) << "keep me";
  ui::requestPath(*state, ui::PathPurpose::Export, target.string());
  auto draw = [&] { ui::drawDialogs(*state); };
  gui.frame(draw);
  gui.frame(draw);
  gui.clickLabel(*state, "Save", draw);
  EXPECT_EQ(state->replacePath, target.string()) << "asked, not written";
  EXPECT_EQ(state->pathDialog, ui::PathPurpose::Export);
  EXPECT_EQ(slurp(target), "keep me");
  gui.frame(draw);
  gui.clickLabel(*state, "Replace it", draw);
  ui::pollWorker(*state);
  EXPECT_EQ(state->pathDialog, ui::PathPurpose::None);
  EXPECT_NE(slurp(target), "keep me") << "replaced after the answer";
}

}  // namespace
}  // namespace kc::test
