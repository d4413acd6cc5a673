// The LBC backend in the window: the Bind panel's KC | LBC switch and its parameters, binding
// with progress and Cancel, what LBC cannot do greyed with the reason, and posing, heatmap
// weights, diagnostics, export and session save/open working on an LBC session. Driven through
// ui::drawFrame on Dear ImGui's null backend, clicking widgets by their visible labels.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cli_run.h"
#include "kc/app/diagnostics.h"
#include "kc/ui/document.h"
#include "kc/ui/frame.h"
#include "scene_image.h"
#include "stage_gate.h"
#include "ui_fixture.h"

namespace kc::ui {
namespace {

namespace fs = std::filesystem;

/// The generated 400×300 scene opened from a PNG in `dir`, with a closed, unbound hexagon around
/// the character (image pixels), in the cage tool; jobs run inline.
std::unique_ptr<AppState> sceneWithCage(const fs::path& dir) {
  const std::string image = (dir / "scene.png").string();
  app::saveImage(image, test::sceneImage(400, 300));
  auto s = std::make_unique<AppState>();
  s->worker.setSynchronous(true);
  EXPECT_TRUE(openImage(*s, image));
  Points C(6, 2);
  C << 160, 90, 240, 90, 270, 160, 240, 240, 160, 240, 130, 160;
  setDraftCage(*s, Cage::polygon(C));
  s->tool = Tool::Cage;
  s->bindParams.spacing = 10.0;
  return s;
}

/// Clicks the Bind panel's LBC switch and Bind; returns with the bound LBC session installed.
void bindLbc(test::HeadlessImGui& gui, AppState& s) {
  auto draw = [&] { drawFrame(s); };
  gui.frame(draw);
  gui.clickLabel(s, "LBC", draw);
  ASSERT_EQ(s.bindParams.backend, "lbc");
  gui.frame(draw);  // the panel shows LBC's parameters now: let it report where Bind is
  gui.clickLabel(s, "Bind", draw);
  pollWorker(s);
  ASSERT_TRUE(s.bound) << (s.messages.empty() ? "" : s.messages.back().text);
  ASSERT_TRUE(s.session && s.session->hasField());
}

TEST(LbcGui, TheBindPanelSwitchesBackendAndShowsItsParameters) {
  test::HeadlessImGui gui;
  auto s = sceneWithCage(test::scratchDir("ui_lbc_panel"));
  auto draw = [&] { drawFrame(*s); };
  gui.frame(draw);
  EXPECT_EQ(s->bindParams.backend, "kc") << "KC is the default";
  EXPECT_TRUE(s->widgets.count("Auto sigma"));
  EXPECT_FALSE(s->widgets.count("LBC tolerance")) << "LBC's parameters only when they are used";

  gui.clickLabel(*s, "LBC", draw);
  gui.frame(draw);
  EXPECT_EQ(s->bindParams.backend, "lbc");
  EXPECT_FALSE(s->widgets.count("Auto sigma")) << "KC's sigma means nothing to LBC";
  for (const char* label : {"LBC locality", "LBC tolerance", "Max iterations"}) EXPECT_TRUE(s->widgets.count(label)) << label;

  // Before the bind, what LBC cannot do is already greyed: method buttons do nothing, the brush
  // and "Move everything" are refused with the reason.
  gui.clickLabel(*s, "QEC", draw);
  EXPECT_EQ(s->bindParams.kc.method, Method::QP);
  selectTool(*s, Tool::Brush);
  EXPECT_EQ(s->tool, Tool::Cage);
  ASSERT_FALSE(s->messages.empty());
  EXPECT_NE(s->messages.back().text.find("mesh of the cage interior"), std::string::npos) << s->messages.back().text;
  EXPECT_FALSE(setOutsideMode(*s, OutsideMode::Deform));
  EXPECT_EQ(s->outside, OutsideMode::Pinned);

  // Back to KC: Initialization = lbc shows the LBC parameters under it.
  gui.clickLabel(*s, "KC", draw);
  s->bindParams.kc.init.method = InitMethod::Lbc;
  gui.frame(draw);
  EXPECT_TRUE(s->widgets.count("Auto sigma"));
  EXPECT_TRUE(s->widgets.count("LBC tolerance"));
}

TEST(LbcGui, BindPoseHeatmapDiagnosticsExportSaveAndOpen) {
  test::HeadlessImGui gui;
  const fs::path dir = test::scratchDir("ui_lbc_session");
  auto s = sceneWithCage(dir);
  s->bindParams.lbc.tolerance = 1e-3;
  bindLbc(gui, *s);
  auto draw = [&] { drawFrame(*s); };
  const app::Session& bound = *s->session;
  EXPECT_EQ(bound.params.backend, "lbc");
  EXPECT_GT(bound.report.meshVertices(), 6);
  EXPECT_EQ(s->tool, Tool::Pose);
  EXPECT_FALSE(s->bound->capabilities.painting || s->bound->capabilities.methods || s->bound->capabilities.outsideCage);
  EXPECT_NE(s->messages.back().text.find("with LBC"), std::string::npos) << s->messages.back().text;
  EXPECT_EQ(boundSigmaText(*s), "") << "LBC weights have no kernel width to show";

  // Greyed after the bind too: method buttons, brush (panel and key), Move everything.
  gui.frame(draw);
  const Weights W = s->session->W;
  gui.clickLabel(*s, "QEC", draw);
  pollWorker(*s);
  ASSERT_TRUE(s->session);
  EXPECT_TRUE(s->session->W == W) << "a greyed method button must not re-optimize";
  gui.clickLabel(*s, "Brush (B)", draw);
  EXPECT_EQ(s->tool, Tool::Pose);
  EXPECT_FALSE(setOutsideMode(*s, OutsideMode::Deform));

  // The heatmap colours the field's own weights at the display mesh's vertices: inside the cage
  // they are the LBC mesh field's (a partition of unity, w >= 0, 1 at the active point).
  ASSERT_TRUE(s->meshSource);
  const Weights& Wv = s->meshSource->W;
  const Points& R = s->mesh.restVertices();
  ASSERT_EQ(Wv.rows(), R.rows());
  std::vector<Index> inside;
  for (Index v = 0; v < R.rows(); ++v)
    if (insideCage(bound.cage, R.row(v).transpose())) inside.push_back(v);
  ASSERT_GT(inside.size(), 100u);
  Points P(Index(inside.size()), 2);
  for (std::size_t k = 0; k < inside.size(); ++k) P.row(Index(k)) = R.row(inside[k]);
  const Weights field = bound.field->weightsAt(P);
  double largest = 0.0;
  for (std::size_t k = 0; k < inside.size(); ++k) {
    const Index v = inside[k];
    EXPECT_LT((Wv.row(v) - field.row(Index(k))).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_NEAR(Wv.row(v).sum(), 1.0, 1e-9);
    EXPECT_GE(Wv.row(v).minCoeff(), -1e-12);
    largest = std::max(largest, Wv(v, 0));
  }
  EXPECT_GT(largest, 0.8) << "near point 0 its weight approaches 1";

  // Dragging point 1 deforms the picture.
  gui.frame(draw);
  const Vec2 c1 = bound.cage.C.row(1).transpose();
  gui.drag(s->view.toScreen(c1), s->view.toScreen(c1 + Vec2(20, -15)), draw);
  EXPECT_TRUE(s->pose[1].translate.isApprox(Vec2(20, -15), 1.0)) << s->pose[1].translate.transpose();
  EXPECT_GT(s->deformReport.seconds, 0.0);

  // Diagnostics: exact inside the cage (partition of unity, reproduction, w ≥ 0).
  refreshDiagnostics(*s);
  ASSERT_TRUE(s->diagnostics);
  EXPECT_LT(s->diagnostics->inside.partitionOfUnity, 1e-9);
  EXPECT_LT(s->diagnostics->inside.reproduction, 1e-7);
  EXPECT_GE(s->diagnostics->inside.minWeight, -1e-12);
  EXPECT_FALSE(s->diagnostics->outsideWeights);
  EXPECT_EQ(s->diagnostics->image.points, 0) << "no whole-picture row: LBC has no weights outside the cage";
  gui.frame(draw);
  EXPECT_TRUE(s->widgets.count("outside") && s->widgets.count("LBC mesh"));
  EXPECT_FALSE(s->widgets.count("image"));
  {
    // Every control of an LBC session says what it does — or, greyed, why it cannot.
    ImGui::GetIO().DisplaySize = ImVec2(1400, 2000);  // tall enough that every panel is on screen
    gui.frame(draw);
    for (const char* label : {"LBC locality", "LBC tolerance", "Max iterations", "outside", "LBC mesh", "QEC", "Brush (B)"})
      EXPECT_TRUE(s->widgets.count(label)) << label;
    const std::string missing = gui.widgetsWithoutTooltip(*s, draw);
    EXPECT_TRUE(missing.empty()) << "no tooltip on" << missing;
    ImGui::GetIO().DisplaySize = ImVec2(1400, 900);
    ImGui::GetIO().MousePos = ImVec2(-1, -1);
    gui.frame(draw);
  }

  // Export: the warped picture, the outside untouched (LBC keeps or pins it).
  const std::string png = (dir / "out.png").string();
  ASSERT_TRUE(startExport(*s, png));
  pollWorker(*s);
  ASSERT_TRUE(fs::exists(png)) << s->messages.back().text;
  const Image out = app::loadImage(png);
  ASSERT_EQ(out.width, 400);
  ASSERT_EQ(out.height, 300);
  EXPECT_TRUE(out.at(2, 2) == s->source.at(2, 2)) << "the picture's corner stays";

  // Save and open again: the same LBC session, weights bit for bit, pose and capabilities kept.
  const std::string file = (dir / "lbc.kcw.json").string();
  ASSERT_TRUE(startSaveSession(*s, file));
  pollWorker(*s);
  ASSERT_TRUE(fs::exists(file));
  const Weights saved = s->session->W;
  const Pose pose = s->pose;
  ASSERT_TRUE(startOpenSession(*s, file));
  pollWorker(*s);
  ASSERT_TRUE(s->session);
  EXPECT_EQ(s->session->params.backend, "lbc");
  EXPECT_TRUE(s->session->W == saved);
  EXPECT_TRUE(s->pose[1].translate == pose[1].translate);
  EXPECT_FALSE(s->bound->capabilities.painting);
  EXPECT_EQ(s->bindParams.backend, "lbc") << "the panel shows the opened session's backend";
}

TEST(LbcGui, NoConvergenceIsAMessageWithAdviceAndKeepsTheSession) {
  test::HeadlessImGui gui;
  auto s = sceneWithCage(test::scratchDir("ui_lbc_cap"));
  bindLbc(gui, *s);
  const app::Session* before = s->session.get();
  s->bindParams.lbc.maxIterations = 2;
  ASSERT_TRUE(startBind(*s));
  pollWorker(*s);
  EXPECT_EQ(s->session.get(), before) << "a failed bind leaves the session untouched";
  ASSERT_FALSE(s->messages.empty());
  const Message& m = s->messages.back();
  EXPECT_TRUE(m.error);
  EXPECT_NE(m.text.find("did not converge"), std::string::npos) << m.text;
  EXPECT_NE(m.text.find("Max iterations"), std::string::npos) << "advice in the panel's words: " << m.text;
}

TEST(LbcGui, PinnedBorderReplacesMoveEverythingAtAnLbcBind) {
  test::HeadlessImGui gui;
  auto s = sceneWithCage(test::scratchDir("ui_lbc_outside"));
  ASSERT_TRUE(setOutsideMode(*s, OutsideMode::Deform)) << "KC before the bind: allowed";
  bindLbc(gui, *s);
  EXPECT_EQ(s->outside, OutsideMode::Pinned);
  EXPECT_EQ(s->mesh.options().outside, OutsideMode::Pinned);
  EXPECT_EQ(s->session->outside, OutsideMode::Pinned);
}

TEST(LbcGui, KcOnLbcTargetsIsMoreLocalAndStillPaintable) {
  auto s = sceneWithCage(test::scratchDir("ui_lbc_init"));
  ASSERT_TRUE(startBind(*s));
  pollWorker(*s);
  ASSERT_TRUE(s->bound);
  const double kcInfluencing = app::diagnose(*s->session, 20000).locality.meanInfluencing;
  s->bindParams.kc.init.method = InitMethod::Lbc;
  ASSERT_TRUE(startBind(*s));
  pollWorker(*s);
  ASSERT_TRUE(s->session);
  EXPECT_EQ(s->session->params.kc.init.method, InitMethod::Lbc);
  EXPECT_TRUE(s->bound->capabilities.painting && s->bound->capabilities.methods) << "KC on LBC targets is KC: paintable";
  const double onLbc = app::diagnose(*s->session, 20000).locality.meanInfluencing;
  EXPECT_LT(onLbc, kcInfluencing) << "controls influencing a point: KC " << kcInfluencing << ", KC on LBC " << onLbc;
}

TEST(LbcGui, CancelGivesTheSessionBackInEveryStageAndStopsTheBind) {
  test::HeadlessImGui gui;
  auto s = sceneWithCage(test::scratchDir("ui_lbc_cancel"));
  bindLbc(gui, *s);
  test::expectCancelInEveryStage(*s, {"mesh", "geodesics", "LBC iterations", "warp mesh"});
}

}  // namespace
}  // namespace kc::ui
