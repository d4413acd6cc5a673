// The window's real user interface (menu bar, side panel with its collapsing headers, status bar,
// canvas, dialogs: ui::drawFrame, the function the window calls) driven through Dear ImGui's null
// backend. Clicks land on widgets found by their visible label, as a person finds them.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <thread>

#include <GLFW/glfw3.h>
#include <imgui_internal.h>

#include "cli_run.h"
#include "kc/ui/document.h"
#include "kc/ui/frame.h"
#include "kc/ui/jobs.h"
#include "kc/app/pipeline.h"
#include "kc/ui/panels/panels.h"
#include "scene_image.h"
#include "ui_fixture.h"

namespace kc::ui {
namespace {

using test::newPicture;

TEST(Window, NewcomerDrawsACageClicksBindAndPoses) {
  test::HeadlessImGui gui;
  auto s = newPicture();
  auto draw = [&] { drawFrame(*s); };
  gui.frame(draw);  // lays out the canvas and fits the picture
  // Click a cage around the character (image pixels), then the first point again to close it.
  const Vec2 corners[] = {{150, 60}, {250, 60}, {260, 240}, {140, 240}};
  for (const Vec2& p : corners) gui.click(s->view.toScreen(p), draw);
  gui.click(s->view.toScreen(corners[0]), draw);
  ASSERT_TRUE(s->cage.closed);
  ASSERT_TRUE(s->cageValid) << s->cageStatus;
  EXPECT_FALSE(s->bound) << "closing a cage does not bind by itself";

  gui.clickLabel(*s, "Bind", draw);
  pollWorker(*s);
  ASSERT_TRUE(s->bound) << "the Bind button did not bind" << (s->messages.empty() ? "" : ": " + s->messages.back().text);
  EXPECT_TRUE(s->session && s->session->hasField());
  EXPECT_EQ(s->tool, Tool::Pose) << "after a bind the pose tool is active";

  // The next drag on a point deforms.
  gui.frame(draw);
  const Vec2 from = s->view.toScreen(corners[1]), to = s->view.toScreen(corners[1] + Vec2(30, -20));
  gui.drag(from, to, draw);
  ASSERT_EQ(s->pose.size(), 4u);
  EXPECT_TRUE(s->pose[1].translate.isApprox(Vec2(30, -20), 1.0)) << s->pose[1].translate.transpose();
  EXPECT_EQ(s->undo.undoCount(), 1u);
  EXPECT_GT(s->deformReport.seconds, 0.0) << "the picture was not re-deformed";
}

TEST(BindPanel, TheBindButtonStaysInPlaceWhicheverParametersAreShown) {
  // Switching KC -> LBC to compare, then clicking Bind where it was, must hit Bind.
  test::HeadlessImGui gui;
  auto s = test::boundState();
  auto draw = [&] { drawFrame(*s); };
  for (int k = 0; k < 2; ++k) gui.frame(draw);
  ASSERT_TRUE(s->widgets.count("Bind"));
  const Vec2 kc = s->widgets.at("Bind");
  s->bindParams.backend = "lbc";
  for (int k = 0; k < 2; ++k) gui.frame(draw);
  EXPECT_TRUE(s->widgets.at("Bind").isApprox(kc)) << s->widgets.at("Bind").transpose() << " against " << kc.transpose();
  s->bindParams.backend = "kc";
  s->bindParams.kc.init.method = InitMethod::Lbc;  // more rows of parameters
  for (int k = 0; k < 2; ++k) gui.frame(draw);
  EXPECT_TRUE(s->widgets.at("Bind").isApprox(kc)) << s->widgets.at("Bind").transpose() << " against " << kc.transpose();
}

TEST(FileMenu, ExportPngDoesWhatCtrlEDoesAndExportPngAsAsksForANewFile) {
  test::HeadlessImGui gui;
  auto s = test::boundState();
  const std::filesystem::path dir = test::scratchDir("ui_file_menu_export");
  s->imagePath = (dir / "shot.png").string();
  auto draw = [&] { drawFrame(*s); };
  gui.frame(draw);
  auto choose = [&](const char* item) {
    gui.frame(draw);
    gui.clickLabel(*s, "File", draw);
    gui.frame(draw);  // the menu opens and lays out its items
    gui.clickLabel(*s, item, draw);
  };
  // Nothing exported yet: Export PNG asks where, as Ctrl+E does.
  choose("Export PNG");
  ASSERT_EQ(s->pathDialog, PathPurpose::Export);
  EXPECT_EQ(s->pathDialogText, (dir / "shot-warped.png").string());
  gui.frame(draw);
  gui.clickLabel(*s, "Cancel", draw);
  ASSERT_EQ(s->pathDialog, PathPurpose::None);
  // After an export: Export PNG writes the same file again without a question (Ctrl+E)...
  const std::filesystem::path last = dir / "shot-warped.png";
  std::ofstream(last) << "the earlier export";
  s->exportPath = last.string();
  choose("Export PNG");
  EXPECT_EQ(s->pathDialog, PathPurpose::None) << "no dialog: the last export's file is written again";
  for (int k = 0; k < 300 && (s->worker.busy() || test::slurp(last) == "the earlier export"); ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    pollWorker(*s);
  }
  EXPECT_EQ(test::slurp(last).substr(1, 3), "PNG") << "the export ran";
  // ... and Export PNG as... proposes a new file (Ctrl+Shift+E).
  choose("Export PNG as...");
  ASSERT_EQ(s->pathDialog, PathPurpose::Export);
  EXPECT_EQ(s->pathDialogText, (dir / "shot-warped-2.png").string());
}

TEST(Window, EveryPanelControlHasItsVisibleLabel) {
  test::HeadlessImGui gui;
  auto s = test::boundState();
  gui.frame([&] { drawFrame(*s); });
  for (const char* label : {"Pose (P)", "Brush (B)", "Cage (C)", "Reset pose", "QP", "QEC", "L1", "Heatmap", "Bind",
                            "Load cage...", "Save cage...", "Auto sigma"})
    EXPECT_TRUE(s->widgets.count(label)) << label;
}

TEST(Window, EveryMarkedControlShowsATooltipWhenHovered) {
  test::HeadlessImGui gui;
  auto s = test::boundState();
  refreshDiagnostics(*s);
  ImGui::GetIO().DisplaySize = ImVec2(1400, 2000);  // tall enough that every panel is on screen
  auto draw = [&] { drawFrame(*s); };
  gui.frame(draw);
  const std::map<std::string, Vec2> widgets = s->widgets;
  // The diagnostics panel: its button, table headers, row names and every line.
  for (const char* label : {"Refresh properties", "|sum-1|", "repro px", "min w", "neg", "samples", "inside", "image",
                            "Lagrange", "grid step", "Solver", "Flipped triangles", "Size change", "Mesh", "Samples", "Bind:",
                            "Re-optimization", "Mesh weights", "Release -> picture", "Frame"})
    EXPECT_TRUE(widgets.count(label)) << label;
  const std::string missing = gui.widgetsWithoutTooltip(*s, draw);
  EXPECT_TRUE(missing.empty()) << "no tooltip on" << missing;
}

TEST(Window, DiagnosticsSayWhatTheLobeLiftDid) {
  test::HeadlessImGui gui;
  auto s = test::unboundChecker(10.0);
  s->bindParams.kc.liftLobes = true;
  ImGui::GetIO().DisplaySize = ImVec2(1400, 2000);
  auto draw = [&] { drawFrame(*s); };
  gui.frame(draw);
  gui.clickLabel(*s, "Bind", draw);
  pollWorker(*s);
  ASSERT_TRUE(s->bound);
  EXPECT_LT(s->bound->report.lift.deepestBefore, 0.0) << "the lift ran and probed the field";
  refreshDiagnostics(*s);
  s->widgets.clear();
  gui.frame(draw);
  EXPECT_TRUE(s->widgets.count("Lobes lifted"));
  const std::string missing = gui.widgetsWithoutTooltip(*s, draw);
  EXPECT_TRUE(missing.empty()) << "no tooltip on" << missing;
  // Without the option the line is not shown.
  auto plain = test::boundState();
  refreshDiagnostics(*plain);
  gui.frame([&] { drawFrame(*plain); });
  EXPECT_FALSE(plain->widgets.count("Lobes lifted"));
}

TEST(BindPanel, InvalidCageDisablesBindAndShowsTheReason) {
  test::HeadlessImGui gui;
  auto s = newPicture();
  auto draw = [&] { drawFrame(*s); };
  Points C(4, 2);
  C << 120, 60, 280, 240, 280, 60, 120, 240;  // self-intersecting
  setDraftCage(*s, Cage::polygon(C));
  gui.frame(draw);
  gui.clickLabel(*s, "Bind", draw);
  pollWorker(*s);
  EXPECT_FALSE(s->bound) << "Bind must be disabled for an invalid cage";
  EXPECT_FALSE(s->cageStatus.empty());

  C << 120, 60, 280, 60, 280, 240, 120, 240;  // now a rectangle
  setDraftCage(*s, Cage::polygon(C));
  gui.frame(draw);  // the layout changed: let the panel report where Bind is now
  gui.clickLabel(*s, "Bind", draw);
  pollWorker(*s);
  EXPECT_TRUE(s->bound) << (s->messages.empty() ? "" : s->messages.back().text);
  EXPECT_TRUE(s->session && s->session->hasField());
  EXPECT_TRUE(s->mesh.hasWeights());
}

TEST(WeightsPanel, OneMethodControlSwitchesAndKeepsTargets) {
  test::HeadlessImGui gui;
  auto s = test::boundState();
  auto draw = [&] { drawFrame(*s); };
  gui.frame(draw);
  const Weights W0 = s->session->W0, W = s->session->W;
  gui.clickLabel(*s, "QEC", draw);
  pollWorker(*s);
  ASSERT_TRUE(s->session);
  EXPECT_EQ(s->bound->method, Method::QEC);
  EXPECT_EQ(s->bindParams.kc.method, Method::QEC) << "the next bind uses the method shown";
  EXPECT_TRUE(s->session->W0 == W0);
  EXPECT_FALSE(s->session->W == W);
  EXPECT_EQ(s->undo.undoCount(), 1u);
}

TEST(ToolsPanel, RadioButtonsSelectTools) {
  test::HeadlessImGui gui;
  auto s = test::boundState();
  auto draw = [&] { drawFrame(*s); };
  gui.frame(draw);
  gui.clickLabel(*s, "Brush (B)", draw);
  EXPECT_EQ(s->tool, Tool::Brush);
  gui.clickLabel(*s, "Cage (C)", draw);
  EXPECT_EQ(s->tool, Tool::Cage);
}

TEST(WeightsPanel, HeatmapBoxIsTickedOnlyWhereThePictureShowsTheHeatmap) {
  test::HeadlessImGui gui;
  auto s = test::boundState();
  auto draw = [&] { drawFrame(*s); };
  s->heat.show = true;  // the Brush tool's heatmap is on by default
  gui.frame(draw);
  gui.clickLabel(*s, "Rigid (R)", draw);
  ASSERT_EQ(s->tool, Tool::Rigid);
  gui.frame(draw);
  gui.clickLabel(*s, "Heatmap", draw);  // disabled here: the rigidity tint is drawn, not the heatmap
  EXPECT_TRUE(s->heat.show) << "a click on the disabled box changed the Brush tool's heatmap";
  gui.clickLabel(*s, "Pose (P)", draw);
  gui.frame(draw);
  const bool before = s->heat.showInPose;
  gui.clickLabel(*s, "Heatmap", draw);
  EXPECT_NE(s->heat.showInPose, before) << "in the Pose tool the box switches the heatmap";
}

TEST(DiagnosticsPanel, MeasuresTheBoundSession) {
  test::HeadlessImGui gui;
  auto s = test::boundState();
  refreshDiagnostics(*s);
  ASSERT_TRUE(s->diagnostics.has_value());
  EXPECT_LT(s->diagnostics->samples.partitionOfUnity, 1e-6);
  gui.frame([&] { drawFrame(*s); });  // draws the table without asserting inside ImGui
}

TEST(FileDialog, ThePathFieldSelectsItsTextSoTypingReplacesIt) {
  test::HeadlessImGui gui;
  auto s = test::boundState();
  auto draw = [&] { drawFrame(*s); };
  const auto dir = std::filesystem::temp_directory_path() / "kcwarp_test_ui_pathfield";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string typed = (dir / "mine.png").string();
  requestPath(*s, PathPurpose::Export, "warped.png");
  for (int k = 0; k < 3; ++k) gui.frame(draw);  // opens, focuses the field
  for (char c : typed) ImGui::GetIO().AddInputCharacter(static_cast<unsigned>(c));
  gui.frame(draw);
  gui.frame(draw);
  gui.clickLabel(*s, "Save", draw);
  pollWorker(*s);
  EXPECT_EQ(s->exportPath, typed) << "typing must replace the suggested name, not append to it";
  EXPECT_TRUE(std::filesystem::exists(typed));
}

TEST(UnsavedPrompt, OpenAsksFirstAndCancelKeepsTheWork) {
  test::HeadlessImGui gui;
  auto s = test::boundState();
  auto draw = [&] { drawFrame(*s); };
  s->unsaved = true;
  const std::string other = std::string(KC_SOURCE_DIR) + "/images/figure.png";
  const int width = s->source.width;
  openAnyFile(*s, other);
  for (int k = 0; k < 3; ++k) gui.frame(draw);
  ASSERT_TRUE(s->unsavedPrompt.has_value()) << "opening over unsaved work must ask";
  EXPECT_EQ(s->source.width, width);
  gui.clickLabel(*s, "Cancel", draw);
  EXPECT_FALSE(s->unsavedPrompt.has_value());
  EXPECT_TRUE(s->bound);
  EXPECT_TRUE(s->unsaved);

  openAnyFile(*s, other);
  for (int k = 0; k < 3; ++k) gui.frame(draw);
  gui.clickLabel(*s, "Open without saving", draw);
  EXPECT_FALSE(s->bound);
  EXPECT_NE(s->imagePath.find("figure.png"), std::string::npos);
  EXPECT_EQ(s->tool, Tool::Cage);
}

TEST(UnsavedPrompt, EscapeCancelsTheQuestionsAndTheFileDialog) {
  // Escape down for one frame (the window holds a tapped Escape down for a frame: feedKeys;
  // tests/ui/input_e2e_test.cpp taps it between slowed frames).
  test::HeadlessImGui gui;
  auto s = test::boundState();
  auto draw = [&] { drawFrame(*s); };
  ImGuiIO& io = ImGui::GetIO();
  s->unsaved = true;
  const std::string other = std::string(KC_SOURCE_DIR) + "/images/figure.png";
  const int width = s->source.width;
  const auto escape = [&] {
    io.KeysDown[GLFW_KEY_ESCAPE] = true;
    gui.frame(draw);
    io.KeysDown[GLFW_KEY_ESCAPE] = false;
    gui.frame(draw);
  };
  // Opening over unsaved work asks; Escape goes back to the work, as Cancel does.
  openAnyFile(*s, other);
  for (int k = 0; k < 3; ++k) gui.frame(draw);
  ASSERT_TRUE(s->unsavedPrompt.has_value());
  escape();
  EXPECT_FALSE(s->unsavedPrompt.has_value());
  EXPECT_TRUE(s->bound);
  EXPECT_TRUE(s->unsaved);
  EXPECT_EQ(s->source.width, width);
  // The question before a bind that would drop something.
  s->unsavedPrompt = PendingAction{"Bind again", [](AppState& st) { st.bound.reset(); }, "It drops a stroke."};
  for (int k = 0; k < 3; ++k) gui.frame(draw);
  ASSERT_TRUE(s->widgets.count("Bind again")) << "the question is shown";
  escape();
  EXPECT_FALSE(s->unsavedPrompt.has_value());
  EXPECT_TRUE(s->bound) << "Escape must not go on";
  // The file dialog.
  requestPath(*s, PathPurpose::Open, other);
  for (int k = 0; k < 3; ++k) gui.frame(draw);
  ASSERT_EQ(s->pathDialog, PathPurpose::Open);
  escape();
  EXPECT_EQ(s->pathDialog, PathPurpose::None);
  EXPECT_EQ(s->source.width, width) << "nothing was opened";
}

TEST(Shortcuts, ACtrlKeyTappedRightAfterTheFileDialogClosesIsAnswered) {
  // ImGui reports the closed dialog's path field as taking text for one more frame; a Ctrl+O
  // tapped in that frame opens the dialog again (a tapped Ctrl shortcut waits one frame for it).
  test::HeadlessImGui gui;
  auto s = test::boundState();
  auto draw = [&] { drawFrame(*s); };
  ImGuiIO& io = ImGui::GetIO();
  requestPath(*s, PathPurpose::Open, s->imagePath);
  for (int k = 0; k < 3; ++k) gui.frame(draw);
  ASSERT_EQ(s->pathDialog, PathPurpose::Open);
  io.KeysDown[GLFW_KEY_ESCAPE] = true;
  gui.frame(draw);
  io.KeysDown[GLFW_KEY_ESCAPE] = false;
  ASSERT_EQ(s->pathDialog, PathPurpose::None);
  s->tappedKeys.emplace_back(GLFW_KEY_O, GLFW_MOD_CONTROL);
  for (int k = 0; k < 3; ++k) gui.frame(draw);
  EXPECT_EQ(s->pathDialog, PathPurpose::Open) << "the tapped Ctrl+O was lost";
  // While a field takes text, a tapped shortcut belongs to the field, also in the frame after.
  io.KeysDown[GLFW_KEY_ESCAPE] = true;
  gui.frame(draw);
  io.KeysDown[GLFW_KEY_ESCAPE] = false;
  ASSERT_EQ(s->pathDialog, PathPurpose::None);
  char text[32] = "";
  bool focus = true;
  auto drawWithField = [&] {
    drawFrame(*s);
    ImGui::Begin("field");
    if (std::exchange(focus, false)) ImGui::SetKeyboardFocusHere();
    ImGui::InputText("##text", text, sizeof text);
    ImGui::End();
  };
  for (int k = 0; k < 3; ++k) gui.frame(drawWithField);
  ASSERT_TRUE(io.WantTextInput);
  s->tappedKeys.emplace_back(GLFW_KEY_O, GLFW_MOD_CONTROL);
  for (int k = 0; k < 3; ++k) gui.frame(drawWithField);
  EXPECT_EQ(s->pathDialog, PathPurpose::None) << "Ctrl+O typed into a field must not open the file dialog";
  EXPECT_TRUE(s->heldTaps.empty());
}

TEST(UnsavedPrompt, AnUnboundCageCountsAsWork) {
  test::HeadlessImGui gui;
  auto s = newPicture();
  auto draw = [&] { drawFrame(*s); };
  gui.frame(draw);
  for (const Vec2& p : {Vec2(150, 60), Vec2(250, 60), Vec2(200, 200)}) gui.click(s->view.toScreen(p), draw);
  ASSERT_TRUE(s->unsaved);
  unlessUnsaved(*s, "New", newDocument);
  for (int k = 0; k < 3; ++k) gui.frame(draw);
  EXPECT_TRUE(s->widgets.count("Save cage and new")) << "an unbound cage can be saved before it is dropped";
  gui.clickLabel(*s, "New without saving", draw);
  EXPECT_TRUE(s->source.empty());
  EXPECT_EQ(s->cage.size(), 0);
}

TEST(View, RefitsOnResizeUntilTheUserZooms) {
  test::HeadlessImGui gui;
  auto s = test::boundState();
  auto draw = [&] { drawFrame(*s); };
  gui.frame(draw);
  const double zoom = s->view.zoom;
  ImGui::GetIO().DisplaySize = ImVec2(900, 700);
  gui.frame(draw);
  EXPECT_LT(s->view.zoom, zoom) << "a smaller window shows the whole picture again";
  s->view.zoomTo(1.0);
  EXPECT_EQ(s->view.zoom, 1.0);
  ImGui::GetIO().DisplaySize = ImVec2(1400, 900);
  gui.frame(draw);
  EXPECT_EQ(s->view.zoom, 1.0) << "a zoom the user chose is kept";
}

TEST(QuitDialog, AsksBeforeDiscardingUnsavedWork) {
  test::HeadlessImGui gui;
  auto s = test::boundState();
  auto draw = [&] { drawFrame(*s); };
  // Nothing unsaved: quitting needs no confirmation.
  s->unsaved = false;
  s->quitRequested = true;
  gui.frame(draw);
  EXPECT_TRUE(s->quitConfirmed);

  // Unsaved work: the dialog opens and the program keeps running until the user chooses.
  s->quitConfirmed = false;
  s->unsaved = true;
  s->quitRequested = true;
  for (int i = 0; i < 3; ++i) gui.frame(draw);
  EXPECT_FALSE(s->quitConfirmed);
  gui.clickLabel(*s, "Quit without saving", draw);
  EXPECT_TRUE(s->quitConfirmed);
}

TEST(BindPanel, AutoSpacingFollowsThePictureAndTheSliderWinsWhenOff) {
  // A 34-point-like cage over half of the picture: 6 px on a small picture, wider on a 12 MP one
  // (the CLI's app::automaticSpacing), and the slider's value once Auto spacing is off.
  AppState state;
  auto cageOver = [](int w, int h) {
    Points C(4, 2);
    C << 0.25 * w, 0.25 * h, 0.75 * w, 0.25 * h, 0.75 * w, 0.75 * h, 0.25 * w, 0.75 * h;
    return Cage::polygon(C);
  };
  ASSERT_TRUE(state.autoSpacing);
  EXPECT_DOUBLE_EQ(bindParamsFor(state, cageOver(400, 300), 400, 300).spacing, 6.0);
  app::BindParams defaults;
  const double big = bindParamsFor(state, cageOver(4000, 3000), 4000, 3000).spacing;
  defaults.exterior = sampling::ExteriorExtent::Band;  // the GUI samples a band unless the outside mode is Move everything
  EXPECT_DOUBLE_EQ(big, app::automaticSpacing(cageOver(4000, 3000), 4000, 3000, defaults));
  EXPECT_GT(big, 15.0);
  state.bindParams.spacing = big;  // what a bind leaves in the panel: the next small picture is 6 px again
  EXPECT_DOUBLE_EQ(bindParamsFor(state, cageOver(400, 300), 400, 300).spacing, 6.0);
  state.autoSpacing = false;
  state.bindParams.spacing = 3.5;
  EXPECT_DOUBLE_EQ(bindParamsFor(state, cageOver(4000, 3000), 4000, 3000).spacing, 3.5);
}

/// The locality length shown next to "Local targets" is the one Bind's screened targets will use:
/// app::locality at the automatic spacing, not at the slider's (greyed) value.
TEST(BindPanel, LocalityShownIsTheBindsUnderAutoSpacing) {
  AppState state;
  state.worker.setSynchronous(true);
  state.source = test::sceneImage(2000, 1500);
  Points C(4, 2);  // a long, thin strip: 1.5 spacings, not its depth, sets the length
  C << 200, 700, 1800, 700, 1800, 740, 200, 740;
  const Cage cage = Cage::polygon(C);
  setDraftCage(state, cage);
  ASSERT_TRUE(state.autoSpacing && state.cageValid);
  ASSERT_EQ(state.bindParams.spacing, 6.0);
  const double h = bindParamsFor(state, cage, 2000, 1500).spacing;
  ASSERT_GT(h, 7.0) << "the automatic spacing must differ from the slider's for this test to mean anything";
  const double used = app::localityLength(cage, h, app::kLocalitySpacings);
  EXPECT_NE(used, app::localityLength(cage, 6.0, app::kLocalitySpacings));
  EXPECT_DOUBLE_EQ(spacingPlan(state).locality, used);
  state.bindParams.kc.locality.value = 3.0;  // a change of the setting is seen at once
  EXPECT_DOUBLE_EQ(spacingPlan(state).locality, app::localityLength(cage, h, 3.0));
  state.bindParams.kc.locality = {app::Locality::Rule::Pixels, 17.0};
  EXPECT_DOUBLE_EQ(spacingPlan(state).locality, 17.0);
  state.bindParams.kc.locality = {app::Locality::Rule::Automatic, 0.0};
  EXPECT_DOUBLE_EQ(spacingPlan(state).locality, automaticLocality(cage.C));
}

/// A backend registered by a file of its own (tests/support/mvc_backend.cpp, linked into this test)
/// gets its radio button beside KC and LBC, and its described parameter as the panel's widget.
TEST(BindPanel, ARegisteredBackendShowsItsSwitchAndItsParameters) {
  test::HeadlessImGui gui;
  auto s = test::boundState();
  auto draw = [&] { drawFrame(*s); };
  for (int k = 0; k < 2; ++k) gui.frame(draw);
  for (const char* label : {"KC", "LBC", "MVC", "Auto sigma"}) EXPECT_TRUE(s->widgets.count(label)) << label;
  EXPECT_FALSE(s->widgets.count("MVC snap"));
  gui.clickLabel(*s, "MVC", draw);
  EXPECT_EQ(s->bindParams.backend, "mvc");
  for (int k = 0; k < 2; ++k) gui.frame(draw);
  EXPECT_TRUE(s->widgets.count("MVC snap"));
  EXPECT_FALSE(s->widgets.count("Auto sigma"));  // the kc backend's own parameters are gone
}

/// Under Initialization = lbc the kc panel shows the LBC solver's parameters (the kc backend names
/// the backend its targets come from); under heat-linear it does not.
TEST(BindPanel, LbcInitializationShowsTheLbcSolversParameters) {
  EXPECT_EQ(app::backendFor("kc").targetsBackend(app::BindParams{}), nullptr);
  EXPECT_EQ(app::backendFor("lbc").targetsBackend(app::BindParams{}), nullptr);
  test::HeadlessImGui gui;
  auto s = test::boundState();
  auto draw = [&] { drawFrame(*s); };
  s->bindParams.kc.init.method = InitMethod::HeatLinear;
  for (int k = 0; k < 2; ++k) gui.frame(draw);
  EXPECT_FALSE(s->widgets.count("LBC locality"));
  s->bindParams.kc.init.method = InitMethod::Lbc;
  EXPECT_EQ(app::backendFor("kc").targetsBackend(s->bindParams), &app::backendFor("lbc"));
  for (int k = 0; k < 2; ++k) gui.frame(draw);
  EXPECT_TRUE(s->widgets.count("LBC locality"));
}

/// "Local targets" switches the screening and the targets' floor together: off binds the smooth,
/// far-reaching targets, on again the local default.
TEST(BindPanel, LocalTargetsSwitchesTheScreeningAndTheFloor) {
  test::HeadlessImGui gui;
  auto s = test::boundState();
  auto draw = [&] { drawFrame(*s); };
  for (int k = 0; k < 2; ++k) gui.frame(draw);
  ASSERT_EQ(s->bindParams.kc.targetFloor, app::kTargetFloor);
  gui.clickLabel(*s, "Local targets", draw);
  EXPECT_EQ(s->bindParams.kc.locality.rule, app::Locality::Rule::Off);
  EXPECT_EQ(s->bindParams.kc.targetFloor, 0.0);
  gui.clickLabel(*s, "Local targets", draw);
  EXPECT_EQ(s->bindParams.kc.locality, app::Locality{});
  EXPECT_EQ(s->bindParams.kc.targetFloor, app::kTargetFloor);
}

/// The kc backend's Advanced parameters come from its description: closed until opened, then each
/// a widget of its type that sets the next bind's parameter.
TEST(BindPanel, AdvancedShowsTheDescribedParametersAndSetsThem) {
  test::HeadlessImGui gui;
  auto s = test::boundState();
  auto draw = [&] { drawFrame(*s); };
  for (int k = 0; k < 2; ++k) gui.frame(draw);
  ASSERT_TRUE(s->widgets.count("Advanced"));
  EXPECT_FALSE(s->widgets.count("Guard lobes"));
  gui.clickLabel(*s, "Advanced", draw);
  for (int k = 0; k < 2; ++k) gui.frame(draw);
  for (const char* label : {"Heat iterations", "Target floor", "Guard lobes", "Near correction", "Linear edges", "Exact lines"})
    EXPECT_TRUE(s->widgets.count(label)) << label;
  ASSERT_TRUE(s->bindParams.kc.guardLobes);
  gui.clickLabel(*s, "Guard lobes", draw);
  EXPECT_FALSE(s->bindParams.kc.guardLobes);
  s->bindParams.kc.init.method = InitMethod::InverseDistance;  // no diffusion: its iterations are not shown
  for (int k = 0; k < 2; ++k) gui.frame(draw);
  EXPECT_FALSE(s->widgets.count("Heat iterations"));
}

/// The spacing shown next to "Auto spacing" is the one Bind will use: switching Initialization to
/// LBC (whose kernel samples lie at half a plain bind's spacing) changes it at once.
TEST(BindPanel, AutoSpacingShownFollowsTheInitialization) {
  auto s = test::boundState();
  s->autoSpacing = true;
  s->bindParams.kc.init.method = InitMethod::HeatLinear;
  const double plain = autoSpacingShown(*s);
  s->bindParams.kc.init.method = InitMethod::Lbc;
  const double lbc = autoSpacingShown(*s);
  EXPECT_EQ(lbc, bindParamsFor(*s, s->cage, s->source.width, s->source.height).spacing);
  EXPECT_LT(lbc, 0.75 * plain) << "plain " << plain << ", lbc " << lbc;
}

}  // namespace
}  // namespace kc::ui
