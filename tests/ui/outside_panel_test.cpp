// The outside-the-cage combo: choosing a mode rebuilds the display mesh on the worker; the view
// and the export follow it and the session remembers it.
#include <gtest/gtest.h>

#include "kc/ui/panels/panels.h"
#include "ui_fixture.h"

namespace kc::ui {
namespace {

void drawSide(AppState& s) {
  ImGui::SetNextWindowPos(ImVec2(1050, 20));
  ImGui::SetNextWindowSize(ImVec2(350, 860));
  ImGui::Begin("##side", nullptr, ImGuiWindowFlags_NoDecoration);
  if (ImGui::CollapsingHeader("Outside", ImGuiTreeNodeFlags_DefaultOpen)) drawOutsidePanel(s);
  ImGui::End();
}

/// A bound AppState on the checker picture with a square cage 50 px inside its border, bound
/// with `backend` and shown in `outside` mode.
/// `inset` moves the cage's sides inwards; `exterior` says how far outside it the bind samples.
std::unique_ptr<AppState> boundSquare(const std::string& backend = "kc", OutsideMode outside = OutsideMode::Pinned,
                                      double inset = 50.0,
                                      sampling::ExteriorExtent exterior = sampling::ExteriorExtent::Frame) {
  auto state = std::make_unique<AppState>();
  state->worker.setSynchronous(true);
  state->source = app::loadImage(std::string(KC_SOURCE_DIR) + "/images/checker.png");
  Points C(4, 2);
  C << inset, inset, 255 - inset, inset, 255 - inset, 255 - inset, inset, 255 - inset;
  app::BindParams p;
  p.backend = backend;
  p.spacing = 10.0;
  p.exterior = exterior;
  auto s = std::make_shared<app::Session>(app::bind(Cage::polygon(C), 256, 256, p));
  s->outside = outside;
  installSession(*state, s, buildDisplayMesh(*s, app::warpMeshOptionsFor(*s, outside)));
  return state;
}

/// Largest displacement of the display mesh's corner vertices after deforming with `pose`.
double cornerMove(AppState& s, const Pose& pose) {
  s.mesh.deform(pose);
  const Points& R = s.mesh.restVertices();
  const Points& F = s.mesh.deformedVertices();
  double worst = 0.0;
  for (Index v = 0; v < R.rows(); ++v)
    if ((R(v, 0) < 0 || R(v, 0) > s.source.width - 1) && (R(v, 1) < 0 || R(v, 1) > s.source.height - 1))
      worst = std::max(worst, (F.row(v) - R.row(v)).norm());
  return worst;
}

TEST(OutsidePanel, ChoosingAModeRebuildsTheMeshAndIsSaved) {
  test::HeadlessImGui gui;
  EXPECT_EQ(AppState().outside, OutsideMode::Pinned) << "pinned is the default for a new picture";
  auto s = boundSquare();
  EXPECT_EQ(s->outside, OutsideMode::Pinned);
  EXPECT_EQ(s->mesh.options().outside, OutsideMode::Pinned);
  Pose pose = restPose(4);
  pose[1].translate = Vec2(-30, 20);
  EXPECT_EQ(cornerMove(*s, pose), 0.0);

  gui.frame([&] { drawSide(*s); });
  ASSERT_TRUE(s->widgets.count("outside_mode"));
  gui.click(s->widgets["outside_mode"], [&] { drawSide(*s); });  // opens the combo
  gui.frame([&] { drawSide(*s); });  // a new popup is placed after its first frame
  ASSERT_TRUE(s->widgets.count("outside_deform"));
  const Version before = s->meshVersion;
  gui.click(s->widgets["outside_deform"], [&] { drawSide(*s); });
  pollWorker(*s);
  ASSERT_TRUE(s->session) << "the job handed the session back";
  EXPECT_EQ(s->outside, OutsideMode::Deform);
  EXPECT_EQ(s->mesh.options().outside, OutsideMode::Deform);
  EXPECT_NE(s->meshVersion, before);
  EXPECT_TRUE(s->unsaved);
  EXPECT_EQ(s->session->outside, OutsideMode::Deform);
  EXPECT_GT(cornerMove(*s, pose), 1.0) << "deform moves the picture's corners";

  // Back to pinned through the setter; a session opened later starts in the mode it saved.
  ASSERT_TRUE(setOutsideMode(*s, OutsideMode::Pinned));
  pollWorker(*s);
  EXPECT_EQ(s->mesh.options().outside, OutsideMode::Pinned);
  EXPECT_EQ(cornerMove(*s, pose), 0.0);
  app::Session& session = *s->session;
  session.outside = OutsideMode::Transparent;
  EXPECT_EQ(sessionOutsideMode(session), OutsideMode::Transparent);
  session.outside.reset();
  EXPECT_EQ(sessionOutsideMode(session), OutsideMode::Pinned);
}

TEST(OutsidePanel, MoveEverythingIsRefusedWithoutWeightsOutsideTheCage) {
  test::HeadlessImGui gui;
  auto s = boundSquare("lbc", OutsideMode::Fixed);
  ASSERT_FALSE(s->bound->capabilities.outsideCage);
  ASSERT_EQ(s->outside, OutsideMode::Fixed);

  gui.frame([&] { drawSide(*s); });
  gui.click(s->widgets["outside_mode"], [&] { drawSide(*s); });
  gui.frame([&] { drawSide(*s); });
  ASSERT_TRUE(s->widgets.count("outside_deform"));
  gui.click(s->widgets["outside_deform"], [&] { drawSide(*s); });  // greyed: the click does nothing
  pollWorker(*s);
  EXPECT_EQ(s->outside, OutsideMode::Fixed);
  EXPECT_FALSE(setOutsideMode(*s, OutsideMode::Deform)) << "the setter refuses it too, with a message";
  EXPECT_EQ(s->outside, OutsideMode::Fixed);
  ASSERT_TRUE(s->session) << "a refused change keeps the session";
}

TEST(OutsidePanel, MoveEverythingOnABandSessionBindsAgainOverThePicture) {
  // A small cage sampled in a band around it (the checker's corners are beyond the band):
  // choosing Move everything binds again with the whole picture sampled, keeping the pose.
  test::HeadlessImGui gui;
  auto s = boundSquare("kc", OutsideMode::Pinned, 100.0, sampling::ExteriorExtent::Band);
  ASSERT_EQ(s->session->params.exterior, sampling::ExteriorExtent::Band);
  ASSERT_FALSE(s->bound->capabilities.outsideCage);
  ASSERT_TRUE(bandNeedsFrameBind(*s));
  Pose pose = restPose(4);
  pose[1].translate = Vec2(-12, 9);
  setPose(*s, pose);

  gui.frame([&] { drawSide(*s); });
  gui.click(s->widgets["outside_mode"], [&] { drawSide(*s); });
  gui.frame([&] { drawSide(*s); });
  ASSERT_TRUE(s->widgets.count("outside_deform"));
  gui.click(s->widgets["outside_deform"], [&] { drawSide(*s); });  // offered, not greyed
  pollWorker(*s);
  ASSERT_TRUE(s->session);
  EXPECT_EQ(s->session->params.exterior, sampling::ExteriorExtent::Frame);
  EXPECT_TRUE(s->bound->capabilities.outsideCage);
  EXPECT_EQ(s->outside, OutsideMode::Deform);
  EXPECT_EQ(s->mesh.options().outside, OutsideMode::Deform);
  EXPECT_EQ(s->session->outside, OutsideMode::Deform);
  ASSERT_EQ(s->pose.size(), 4u);
  EXPECT_EQ(s->pose[1].translate, Vec2(-12, 9)) << "the pose is kept";
  EXPECT_GT(cornerMove(*s, s->pose), 0.5) << "deform moves the picture's corners";
  EXPECT_FALSE(bandNeedsFrameBind(*s));
}

TEST(OutsidePanel, MoveEverythingNamesThePaintABindLeavesBehindAndKeepsItOneUndoAway) {
  // On a band session with a paint stroke, Move everything binds again and computes the weights
  // anew: a question names the stroke first, and nothing changes until it is answered. The bind
  // is then one undo step: the stroke stays behind it.
  test::HeadlessImGui gui;
  auto s = boundSquare("kc", OutsideMode::Pinned, 100.0, sampling::ExteriorExtent::Band);
  s->unsaved = true;
  s->undo.push({"paint w1", WeightEdit{{0}, {0}, Weights(), Weights(), Weights(), Weights()}});
  const auto sessionBefore = s->session;

  gui.frame([&] { drawSide(*s); });
  gui.click(s->widgets["outside_mode"], [&] { drawSide(*s); });
  gui.frame([&] { drawSide(*s); });
  gui.click(s->widgets["outside_deform"], [&] { drawSide(*s); });
  pollWorker(*s);
  ASSERT_TRUE(s->unsavedPrompt.has_value());
  EXPECT_EQ(s->unsavedPrompt->what, "Bind again");
  EXPECT_NE(s->unsavedPrompt->question.find("paint w1"), std::string::npos) << s->unsavedPrompt->question;
  EXPECT_EQ(s->session, sessionBefore) << "no bind before the answer";
  EXPECT_EQ(s->outside, OutsideMode::Pinned);
  EXPECT_EQ(s->session->params.exterior, sampling::ExteriorExtent::Band);

  // "Bind again": the question's action binds over the whole picture.
  auto action = std::move(s->unsavedPrompt->run);
  s->unsavedPrompt.reset();
  action(*s);
  pollWorker(*s);
  ASSERT_TRUE(s->session);
  EXPECT_EQ(s->session->params.exterior, sampling::ExteriorExtent::Frame);
  EXPECT_EQ(s->outside, OutsideMode::Deform);
  ASSERT_EQ(s->undo.undoCount(), 2u) << "the stroke, then the bind";
  EXPECT_TRUE(std::holds_alternative<BindEdit>(s->undo.nextUndo()->edit));
  ASSERT_TRUE(undo(*s));
  EXPECT_EQ(s->session, sessionBefore) << "one undo: the band session again";
  EXPECT_EQ(s->outside, OutsideMode::Pinned);
}

}  // namespace
}  // namespace kc::ui
