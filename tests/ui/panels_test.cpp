// Panels driven through Dear ImGui's null backend (no window): clicks land on the widgets the
// panels report in AppState::widgets.
#include <gtest/gtest.h>

#include "kc/ui/panels/panels.h"
#include "ui_fixture.h"

namespace kc::ui {
namespace {

/// The side panel as the window lays it out.
void drawSide(AppState& s) {
  ImGui::SetNextWindowPos(ImVec2(1050, 20));
  ImGui::SetNextWindowSize(ImVec2(350, 860));
  ImGui::Begin("##side", nullptr, ImGuiWindowFlags_NoDecoration);
  drawToolsPanel(s);
  drawWeightsPanel(s);
  drawBindPanel(s);
  drawDiagnosticsPanel(s);
  ImGui::End();
}

TEST(BindPanel, InvalidCageDisablesBindAndShowsTheReason) {
  test::HeadlessImGui gui;
  AppState s;
  s.worker.setSynchronous(true);
  s.source = Image(200, 200, Rgba{90, 90, 90, 255});
  Points C(4, 2);
  C << 20, 20, 180, 180, 180, 20, 20, 180;  // self-intersecting
  setDraftCage(s, Cage::polygon(C));
  gui.frame([&] { drawSide(s); });
  ASSERT_TRUE(s.widgets.count("bind"));
  gui.click(s.widgets["bind"], [&] { drawSide(s); });
  pollWorker(s);
  EXPECT_FALSE(s.bound) << "Bind must be disabled for an invalid cage";
  EXPECT_FALSE(s.cageStatus.empty());

  C << 20, 20, 180, 20, 180, 180, 20, 180;  // now a square
  setDraftCage(s, Cage::polygon(C));
  gui.frame([&] { drawSide(s); });  // the layout changed: let the panel report where Bind is now
  gui.click(s.widgets["bind"], [&] { drawSide(s); });
  pollWorker(s);
  EXPECT_TRUE(s.bound) << (s.messages.empty() ? "" : s.messages.back().text);
  EXPECT_TRUE(s.session && s.session->hasField());
  EXPECT_TRUE(s.mesh.hasWeights());
}

TEST(WeightsPanel, MethodRadioSwitchesAndKeepsTargets) {
  test::HeadlessImGui gui;
  auto s = test::boundState();
  gui.frame([&] { drawSide(*s); });
  ASSERT_TRUE(s->widgets.count("method_qec"));
  const Weights W0 = s->session->W0, W = s->session->W;
  gui.click(s->widgets["method_qec"], [&] { drawSide(*s); });
  pollWorker(*s);
  ASSERT_TRUE(s->session);
  EXPECT_EQ(s->method, Method::QEC);
  EXPECT_TRUE(s->session->W0 == W0);
  EXPECT_FALSE(s->session->W == W);
  EXPECT_EQ(s->undo.undoCount(), 1u);
}

TEST(ToolsPanel, RadioButtonsSelectTools) {
  test::HeadlessImGui gui;
  auto s = test::boundState();
  gui.frame([&] { drawSide(*s); });
  gui.click(s->widgets["tool_brush"], [&] { drawSide(*s); });
  EXPECT_EQ(s->tool, Tool::Brush);
  gui.click(s->widgets["tool_cage"], [&] { drawSide(*s); });
  EXPECT_EQ(s->tool, Tool::Cage);
}

TEST(DiagnosticsPanel, MeasuresTheBoundSession) {
  test::HeadlessImGui gui;
  auto s = test::boundState();
  refreshDiagnostics(*s);
  ASSERT_TRUE(s->diagnostics.has_value());
  EXPECT_LT(s->diagnostics->samples.partitionOfUnity, 1e-6);
  gui.frame([&] { drawSide(*s); });  // draws the table without asserting inside ImGui
}

}  // namespace
}  // namespace kc::ui

namespace kc::ui {
namespace {

TEST(QuitDialog, AsksBeforeDiscardingUnsavedWork) {
  test::HeadlessImGui gui;
  auto s = test::boundState();
  // Nothing unsaved: quitting needs no confirmation.
  s->unsaved = false;
  s->quitRequested = true;
  gui.frame([&] { drawDialogs(*s); });
  EXPECT_TRUE(s->quitConfirmed);

  // Unsaved work: the dialog opens and the program keeps running until the user chooses.
  s->quitConfirmed = false;
  s->unsaved = true;
  s->quitRequested = true;
  for (int i = 0; i < 3; ++i) gui.frame([&] { drawDialogs(*s); });
  EXPECT_FALSE(s->quitConfirmed);
  ASSERT_TRUE(s->widgets.count("quit_discard"));
  gui.click(s->widgets["quit_discard"], [&] { drawDialogs(*s); });
  EXPECT_TRUE(s->quitConfirmed);
}

}  // namespace
}  // namespace kc::ui
