// The rigidity brush without a window (thesis 5.4, docs/rigidity.md): a stroke paints ρ with a soft
// falloff and strength; release re-solves around it through app::setRigidity (weights farther than
// (reach + 5)σ from the painted samples keep their bits); undo and redo restore ρ and W exactly;
// erase takes ρ away; Cancel during the solve puts the session back; sessions keep ρ; the tool is
// greyed with the reason for LBC and before a bind; the panel's widgets say what they do; the tint
// covers the painted samples only.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "cli_run.h"
#include "kc/ui/frame.h"
#include "kc/ui/line_edits.h"
#include "kc/ui/rigidity_edits.h"
#include "kc/ui/tools/brush_tool.h"
#include "kc/ui/tools/rigidity_tool.h"
#include "stage_gate.h"
#include "ui_fixture.h"

namespace kc::ui {
namespace {

PointerEvent pointerAt(const Vec2& p, bool ctrl = false) {
  PointerEvent e;
  e.position = p;
  e.ctrl = ctrl;
  return e;
}

void finish(AppState& s) {
  s.worker.waitFinished();
  pollWorker(s);
}

/// A stroke from a to b with the rigidity tool, then the job's result applied.
void rigidityStroke(AppState& s, const Vec2& a, const Vec2& b, bool ctrl = false) {
  s.rigidTool.press(s, pointerAt(a, ctrl));
  for (int k = 1; k <= 8; ++k) s.rigidTool.drag(s, pointerAt(a + (b - a) * (k / 8.0), ctrl));
  s.rigidTool.release(s, pointerAt(b, ctrl));
  finish(s);
}

Index rigidCount(const std::vector<double>& rho) { return std::count_if(rho.begin(), rho.end(), [](double r) { return r > 0.0; }); }

std::string lastMessage(const AppState& s) { return s.messages.empty() ? "" : s.messages.back().text; }

/// Distance from p to the segment ab.
double segmentDistance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
  return (p - (a + t * (b - a))).norm();
}

/// The bound checker (256×256, 4 corner controls, h = 10 px) with the rigidity tool active.
std::unique_ptr<AppState> rigidState() {
  auto s = test::boundState(10.0);
  selectTool(*s, Tool::Rigid);
  EXPECT_EQ(s->tool, Tool::Rigid) << lastMessage(*s);
  return s;
}

const Vec2 kA(90, 110), kB(150, 130);

TEST(RigidityDab, FalloffSoftnessAndStrength) {
  EXPECT_EQ(rigidityFalloff(0.0, 10.0, 0.0), 1.0);
  EXPECT_EQ(rigidityFalloff(9.9, 10.0, 0.0), 1.0);  // hard disc
  EXPECT_EQ(rigidityFalloff(10.0, 10.0, 0.0), 0.0);
  for (double d : {0.0, 3.0, 7.5, 9.9}) EXPECT_DOUBLE_EQ(rigidityFalloff(d, 10.0, 1.0), brushFalloff(d, 10.0));
  EXPECT_EQ(rigidityFalloff(4.0, 10.0, 0.5), 1.0);  // inside the hard core (1 − 0.5)·10
  EXPECT_NEAR(rigidityFalloff(7.5, 10.0, 0.5), 0.75 * 0.75, 1e-15);  // t = 0.5: (1 − 0.25)²

  SampleSet S;
  S.X.resize(5, 2);
  S.X << 0, 0, 5, 0, 2, 0, 30, 0, 1, 1;
  S.edge = decltype(S.edge)::Constant(5, 2, -1);
  S.kind = {SampleKind::Interior, SampleKind::Interior, SampleKind::Edge, SampleKind::Interior, SampleKind::Control};
  const std::vector<double> rho0(5, 0.0);
  std::vector<double> cover, rho;
  EXPECT_EQ(paintRigidityDab(rho0, cover, rho, S, Vec2(0, 0), 10.0, 1.0, 0.8, false), 2);  // edge, control and far samples are not painted
  EXPECT_DOUBLE_EQ(rho[0], 0.8);
  EXPECT_NEAR(rho[1], 0.8 * 0.75 * 0.75, 1e-15);
  EXPECT_EQ(rho[2], 0.0);
  EXPECT_EQ(rho[3], 0.0);
  EXPECT_EQ(rho[4], 0.0);
  const double once = rho[1];
  paintRigidityDab(rho0, cover, rho, S, Vec2(0, 0), 10.0, 1.0, 0.8, false);  // the same dab again: the profile does not build up
  EXPECT_EQ(rho[1], once);
  // Erasing a stroke's start values: ρ0 · (1 − strength · coverage).
  const std::vector<double> full(5, 1.0);
  std::vector<double> cover2, rho2;
  paintRigidityDab(full, cover2, rho2, S, Vec2(0, 0), 10.0, 1.0, 1.0, true);
  EXPECT_EQ(rho2[0], 0.0);
  EXPECT_NEAR(rho2[1], 1.0 - 0.75 * 0.75, 1e-15);
  EXPECT_EQ(rho2[3], 1.0);
}

TEST(RigidityBrush, AStrokePaintsRhoAndReSolvesOnlyNearIt) {
  auto s = rigidState();
  s->rigidBrush.radius = 20.0;
  s->rigidBrush.softness = 0.5;
  s->rigidBrush.strength = 1.0;
  const Weights W = s->session->W, W0 = s->session->W0;
  ASSERT_EQ(rigidCount(s->session->rigidity), 0);
  rigidityStroke(*s, kA, kB);
  ASSERT_TRUE(s->session) << lastMessage(*s);
  // The status line in plain words; the solver's own (method, rounds) in the diagnostics' details.
  EXPECT_EQ(lastMessage(*s).rfind("Rigidity: ", 0), 0u) << lastMessage(*s);
  EXPECT_NE(lastMessage(*s).find("held rigid"), std::string::npos) << lastMessage(*s);
  for (const char* solverWord : {"active set", "ADMM", "rounds", "iterations"})
    EXPECT_EQ(lastMessage(*s).find(solverWord), std::string::npos) << lastMessage(*s);
  EXPECT_NE(s->rigidityDetails.find("rigidity: "), std::string::npos) << s->rigidityDetails;
  const std::vector<double>& rho = s->session->rigidity;
  ASSERT_EQ(rho.size(), static_cast<std::size_t>(s->bound->samples.size()));
  EXPECT_EQ(boundRigidity(*s), rho) << "the ρ shown follows the session";
  EXPECT_GT(rigidCount(rho), 15);
  const SampleSet& S = s->bound->samples;
  std::vector<Vec2> painted;
  Index core = 0;
  for (Index i = 0; i < S.size(); ++i) {
    const double d = segmentDistance(S.X.row(i).transpose(), kA, kB), r = rho[static_cast<std::size_t>(i)];
    if (d >= 20.0) {
      EXPECT_EQ(r, 0.0) << "sample " << i << " outside the brush is rigid";
    }
    if (d <= 8.0 && S.kind[static_cast<std::size_t>(i)] == SampleKind::Interior) {  // the hard core (10 px) of the dabs every 5 px
      EXPECT_EQ(r, 1.0) << "sample " << i;
      ++core;
    }
    if (r > 0.0) painted.push_back(S.X.row(i).transpose());
  }
  EXPECT_GT(core, 5);
  // Weights change near the stroke and nowhere farther than (reach + 5)σ from a painted sample; W0 does not change.
  const double reach = (RigidityOptions{}.reach + 5.0) * s->session->sigma;
  double nearChange = 0.0;
  Index far = 0;
  for (Index i = 0; i < S.size(); ++i) {
    double d = 1e300;
    for (const Vec2& p : painted) d = std::min(d, (S.X.row(i).transpose() - p).norm());
    const double change = (s->session->W.row(i) - W.row(i)).cwiseAbs().maxCoeff();
    if (d > reach + 1e-9) {
      ++far;
      EXPECT_TRUE(s->session->W.row(i) == W.row(i)) << "sample " << i << " at " << d << " px from the region changed by " << change;
    } else {
      nearChange = std::max(nearChange, change);
    }
  }
  EXPECT_GT(far, S.size() / 3) << "the test needs samples far from the stroke";
  EXPECT_GT(nearChange, 1e-4) << "the stroke changed no weights";
  EXPECT_TRUE(s->session->W0 == W0);
  // One undo entry holding the changed rows only (not whole matrices).
  ASSERT_EQ(s->undo.undoCount(), 1u);
  const auto& edit = std::get<RigidityEdit>(s->undo.nextUndo()->edit);
  EXPECT_GT(edit.rows.size(), 0u);
  EXPECT_LT(edit.rows.size(), static_cast<std::size_t>(S.size()) / 2);
  EXPECT_EQ(edit.WAfter.rows(), static_cast<Index>(edit.rows.size()));
  EXPECT_EQ(s->undo.nextUndo()->label, "paint rigidity");
  EXPECT_GT(s->timings.releaseToPictureMs, 0.0);
  EXPECT_TRUE(s->unsaved);
  // The display mesh's weights are the field's at its vertices.
  EXPECT_LE((s->meshSource->W - s->meshSource->sampler.evaluate(*s->session->field)).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(RigidityBrush, UndoAndRedoRestoreRhoAndWeightsExactly) {
  auto s = rigidState();
  const Weights W = s->session->W;
  const RowMatrix coef = s->session->field->coefficients();
  const Weights meshW = s->meshSource->W;
  rigidityStroke(*s, kA, kB);
  const std::vector<double> rho = s->session->rigidity;
  const Weights Wafter = s->session->W;
  const RowMatrix coefAfter = s->session->field->coefficients();
  ASSERT_FALSE(Wafter == W);
  ASSERT_TRUE(undo(*s));
  finish(*s);
  ASSERT_TRUE(s->session);
  EXPECT_EQ(rigidCount(s->session->rigidity), 0);
  EXPECT_EQ(rigidCount(boundRigidity(*s)), 0);
  EXPECT_TRUE(s->session->W == W) << "undo gives the weights back bit for bit";
  EXPECT_LE((s->session->field->coefficients() - coef).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LE((s->meshSource->W - meshW).cwiseAbs().maxCoeff(), 1e-12);
  ASSERT_TRUE(redo(*s));
  finish(*s);
  EXPECT_EQ(s->session->rigidity, rho);
  EXPECT_TRUE(s->session->W == Wafter);
  EXPECT_LE((s->session->field->coefficients() - coefAfter).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(RigidityBrush, EraseAndClearTakeRhoAway) {
  auto s = rigidState();
  const Weights W = s->session->W;
  rigidityStroke(*s, kA, kB);
  const Index painted = rigidCount(s->session->rigidity);
  rigidityStroke(*s, kA, 0.5 * (kA + kB), /*ctrl=*/true);  // Ctrl erases half the stroke
  const Index left = rigidCount(s->session->rigidity);
  EXPECT_LT(left, painted);
  EXPECT_GT(left, 0);
  EXPECT_EQ(s->undo.nextUndo()->label, "erase rigidity");
  ASSERT_TRUE(clearRigidity(*s));
  finish(*s);
  EXPECT_EQ(rigidCount(s->session->rigidity), 0);
  // No rigidity left: the weights are the unconstrained ones again (the per-sample optimization of W0).
  EXPECT_LE((s->session->W - W).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_EQ(s->undo.undoCount(), 3u);
  EXPECT_FALSE(clearRigidity(*s)) << "nothing to clear";
}

TEST(RigidityBrush, CancelDuringTheSolvePutsTheSessionBack) {
  auto s = rigidState();
  s->worker.setSynchronous(false);
  test::StageGate gate("warp mesh");  // entered when the QP has finished
  s->worker.setStageHook([&gate](const std::string& stage) { gate(stage); });
  const Weights W = s->session->W;
  const RowMatrix coef = s->session->field->coefficients();
  s->rigidTool.press(*s, pointerAt(kA));
  s->rigidTool.drag(*s, pointerAt(kB));
  s->rigidTool.release(*s, pointerAt(kB));
  EXPECT_TRUE(s->worker.busy());
  EXPECT_GT(rigidCount(boundRigidity(*s)), 0) << "the tint shows the stroke while it is solved";
  gate.waitInside();
  s->worker.cancel();
  gate.release();
  finish(*s);
  s->worker.setStageHook(nullptr);
  ASSERT_TRUE(s->session);
  EXPECT_EQ(rigidCount(s->session->rigidity), 0);
  EXPECT_EQ(rigidCount(boundRigidity(*s)), 0);
  EXPECT_TRUE(s->session->W == W);
  EXPECT_LE((s->session->field->coefficients() - coef).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(s->undo.undoCount(), 0u);
  EXPECT_NE(lastMessage(*s).find("cancelled"), std::string::npos) << lastMessage(*s);
}

TEST(RigidityBrush, SessionsKeepTheRigidity) {
  auto s = rigidState();
  rigidityStroke(*s, kA, kB);
  const std::filesystem::path dir = test::scratchDir("rigidity_brush_session");
  const std::string path = (dir / "rigid.kcw.json").string();
  ASSERT_TRUE(startSaveSession(*s, path));
  finish(*s);
  auto t = test::boundState(10.0);
  ASSERT_TRUE(startOpenSession(*t, path));
  finish(*t);
  ASSERT_TRUE(t->session) << lastMessage(*t);
  EXPECT_EQ(t->session->rigidity, s->session->rigidity);
  EXPECT_EQ(boundRigidity(*t), s->session->rigidity);
  EXPECT_LE((t->session->W - s->session->W).cwiseAbs().maxCoeff(), 1e-15);
  // The reopened session takes further strokes, and undo of one gives the reopened weights back.
  const Weights reopened = t->session->W;
  selectTool(*t, Tool::Rigid);
  rigidityStroke(*t, Vec2(60, 200), Vec2(100, 200));
  EXPECT_GT(rigidCount(t->session->rigidity), rigidCount(s->session->rigidity));
  ASSERT_TRUE(undo(*t));
  finish(*t);
  EXPECT_TRUE(t->session->W == reopened);
  EXPECT_EQ(t->session->rigidity, s->session->rigidity);
}

TEST(RigidityBrush, APaintedRegionSurvivesTheReBindOfALineEdit) {
  auto s = rigidState();
  s->autoSpacing = false;
  rigidityStroke(*s, kA, kB);
  const std::vector<double> before = s->session->rigidity;
  const SampleSet oldSamples = s->bound->samples;
  app::Structure lines = s->lines;
  StructureLine l;
  l.a = Vec2(40, 200);
  l.b = Vec2(200, 215);
  lines.lines.push_back(l);
  ASSERT_TRUE(editLines(*s, lines, "add line")) << lastMessage(*s);
  finish(*s);  // the re-bind; its result starts the rigidity's re-solve on the new samples
  finish(*s);
  ASSERT_TRUE(s->session) << lastMessage(*s);
  ASSERT_EQ(s->session->structure.lines.size(), 1u);
  const std::vector<double>& after = s->session->rigidity;
  ASSERT_EQ(after.size(), static_cast<std::size_t>(s->bound->samples.size()));
  EXPECT_EQ(boundRigidity(*s), after);
  // Every new rigid sample has an old rigid sample nearby and the painted area keeps its size.
  for (Index i = 0; i < s->bound->samples.size(); ++i) {
    if (after[static_cast<std::size_t>(i)] <= 0.0) continue;
    double d = 1e300;
    for (Index j = 0; j < oldSamples.size(); ++j)
      if (before[static_cast<std::size_t>(j)] > 0.0) d = std::min(d, (s->bound->samples.X.row(i) - oldSamples.X.row(j)).norm());
    EXPECT_LE(d, 15.0) << "sample " << i;
  }
  EXPECT_GE(rigidCount(after), 8 * rigidCount(before) / 10);
  EXPECT_LE(rigidCount(after), 12 * rigidCount(before) / 10);
  // Undo takes the line away (it re-binds); no rigidity stroke is left in the history.
  ASSERT_EQ(s->undo.undoCount(), 1u);
  EXPECT_TRUE(std::holds_alternative<LinesEdit>(s->undo.nextUndo()->edit));
}

TEST(RigidityOverlay, ARigidPolygonFromAStructureIsTintedAndOutlined) {
  auto s = std::make_unique<AppState>();
  s->worker.setSynchronous(true);
  const std::string dir = std::string(KC_SOURCE_DIR) + "/images/";
  s->source = app::loadImage(dir + "checker.png");
  app::Structure structure;
  RigidRegion r;
  r.polygon.resize(4, 2);
  r.polygon << 100, 100, 160, 100, 160, 150, 100, 150;
  structure.rigid.push_back(r);
  app::BindParams p;
  p.spacing = 10.0;
  auto session = std::make_shared<app::Session>(app::bind(app::loadCage(dir + "checker.cage.json"), structure, s->source.width,
                                                          s->source.height, p));
  installSession(*s, session, buildDisplayMesh(*session, app::warpMeshOptionsFor(*session, OutsideMode::Pinned)), true);
  ASSERT_EQ(s->lines.rigid.size(), 1u);
  ASSERT_EQ(s->bound->rigidOutlines.size(), 1u);
  EXPECT_EQ(s->bound->rigidOutlines[0].X.rows(), 4 * 16 + 1);
  EXPECT_EQ(s->bound->rigidOutlines[0].W.rows(), 4 * 16 + 1);
  EXPECT_GT(rigidCount(boundRigidity(*s)), 15);
  test::HeadlessImGui gui;
  auto draw = [&] { drawFrame(*s); };
  gui.frame(draw);
  const std::vector<float>& tint = s->rigidTint.value();
  const Points& V = s->mesh.restVertices();
  ASSERT_EQ(tint.size(), static_cast<std::size_t>(V.rows()));
  float inside = 1.0f, outside = 0.0f;
  for (Index v = 0; v < V.rows(); ++v) {
    const double x = V(v, 0), y = V(v, 1);
    if (x > 115 && x < 145 && y > 115 && y < 135) inside = std::min(inside, tint[static_cast<std::size_t>(v)]);
    if (x < 70 || x > 190 || y < 70 || y > 180) outside = std::max(outside, tint[static_cast<std::size_t>(v)]);
  }
  EXPECT_GT(inside, 0.9f);
  EXPECT_EQ(outside, 0.0f);
  // View > Rigid regions off: the pose tool draws no tint.
  s->show.rigid = false;
  const auto key = s->rigidTint.key();
  s->rigidityVersion.bump();
  gui.frame(draw);
  EXPECT_EQ(s->rigidTint.key(), key) << "the tint was recomputed while hidden";
}

TEST(RigidityBrush, GreyedForLbcAndBeforeABind) {
  auto s = std::make_unique<AppState>();
  selectTool(*s, Tool::Rigid);
  EXPECT_NE(s->tool, Tool::Rigid);
  EXPECT_NE(lastMessage(*s).find("bind a cage first"), std::string::npos) << lastMessage(*s);
  s->bindParams.backend = "lbc";
  selectTool(*s, Tool::Rigid);
  EXPECT_NE(s->tool, Tool::Rigid);
  EXPECT_NE(lastMessage(*s).find("KC weights only"), std::string::npos) << lastMessage(*s);
  // The greyed radio button says why in its tooltip.
  test::HeadlessImGui gui;
  auto draw = [&] { drawFrame(*s); };
  gui.frame(draw);
  ASSERT_TRUE(s->widgets.count("Rigid (R)"));
  std::erase_if(s->widgets, [](const auto& w) { return w.first != "Rigid (R)"; });
  EXPECT_EQ(gui.widgetsWithoutTooltip(*s, draw), "");
}

TEST(RigidityPanel, WidgetsSayWhatTheyDoAndTheTintCoversThePaintedPart) {
  test::HeadlessImGui gui;
  auto s = rigidState();
  rigidityStroke(*s, kA, kB);
  auto draw = [&] { drawFrame(*s); };
  gui.frame(draw);
  gui.frame(draw);  // the side panel gets its scroll bar in the second frame: the layout settles
  const std::vector<std::string> labels = {"Rigid (R)", "Radius", "Softness", "Strength", "Paint", "Erase", "Clear rigidity", "Rigid samples"};
  for (const std::string& label : labels) EXPECT_TRUE(s->widgets.count(label)) << label;
  std::erase_if(s->widgets, [&](const auto& w) { return std::find(labels.begin(), labels.end(), w.first) == labels.end(); });
  EXPECT_EQ(gui.widgetsWithoutTooltip(*s, draw), "");
  // The tint: ρ at the display mesh's vertices, positive on the stroke, 0 far from it.
  const std::vector<float>& tint = s->rigidTint.value();
  const Points& V = s->mesh.restVertices();
  ASSERT_EQ(tint.size(), static_cast<std::size_t>(V.rows()));
  float onStroke = 0.0f, away = 0.0f;
  for (Index v = 0; v < V.rows(); ++v) {
    const double d = segmentDistance(V.row(v).transpose(), kA, kB);
    if (d < 5.0) onStroke = std::max(onStroke, tint[static_cast<std::size_t>(v)]);
    if (d > s->rigidBrush.radius + 2.0 * s->bound->spacing) away = std::max(away, tint[static_cast<std::size_t>(v)]);
  }
  EXPECT_GT(onStroke, 0.8f);
  EXPECT_EQ(away, 0.0f);
  // Clear rigidity from the panel: the tint goes away.
  gui.clickLabel(*s, "Clear rigidity", draw);
  finish(*s);
  gui.frame(draw);
  EXPECT_EQ(rigidCount(s->session->rigidity), 0);
  EXPECT_TRUE(s->rigidTint.value().empty());
}

}  // namespace
}  // namespace kc::ui
