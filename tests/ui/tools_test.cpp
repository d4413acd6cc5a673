// Tool logic without a window: pose tool, brush strokes (subset re-optimization), undo, method
// switch, cage tool.
#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>

#include "kc/ui/heat_field.h"
#include "kc/ui/tools/brush_tool.h"
#include "ui_fixture.h"

namespace kc::ui {
namespace {

PointerEvent at(double x, double y, MouseButton b = MouseButton::Left) {
  PointerEvent e;
  e.position = Vec2(x, y);
  e.button = b;
  e.pickRadius = 6.0;
  return e;
}

/// A stroke from a to b with the brush tool.
void stroke(AppState& s, const Vec2& a, const Vec2& b) {
  s.brushTool.press(s, at(a.x(), a.y()));
  for (int k = 1; k <= 10; ++k) {
    const Vec2 p = a + (b - a) * (k / 10.0);
    s.brushTool.drag(s, at(p.x(), p.y()));
  }
  s.brushTool.release(s, at(b.x(), b.y()));
  s.worker.waitFinished();
  pollWorker(s);
}

/// Selects controls 0 and 1 (the top edge) with a rectangle.
void selectTopEdge(AppState& s) {
  s.poseTool.press(s, at(-20, -20));
  s.poseTool.release(s, at(300, 100));
  ASSERT_EQ(s.selection.size(), 2u);
}

TEST(PoseTool, LeftDragTranslatesAndUndoRestores) {
  auto s = test::boundState();
  const Vec2 c1 = s->bound->cage.C.row(1).transpose();
  s->poseTool.press(*s, at(c1.x(), c1.y()));
  s->poseTool.drag(*s, at(c1.x() - 20, c1.y() + 30));
  s->poseTool.release(*s, at(c1.x() - 20, c1.y() + 30));
  EXPECT_TRUE(s->pose[1].translate.isApprox(Vec2(-20, 30)));
  EXPECT_EQ(s->pose[0].translate, Vec2::Zero());
  ASSERT_EQ(s->undo.undoCount(), 1u);
  EXPECT_TRUE(updateDeformation(*s));
  EXPECT_TRUE(undo(*s));
  EXPECT_EQ(s->pose[1].translate, Vec2::Zero());
  EXPECT_TRUE(redo(*s));
  EXPECT_TRUE(s->pose[1].translate.isApprox(Vec2(-20, 30)));
}

TEST(PoseTool, ADragDeformsLiveAndTheReleaseDeformsInFull) {
  auto s = test::boundState();
  const Vec2 c1 = s->bound->cage.C.row(1).transpose();
  s->poseTool.press(*s, at(c1.x(), c1.y()));
  s->poseTool.drag(*s, at(c1.x() + 25, c1.y() - 10));
  EXPECT_TRUE(updateDeformation(*s));
  EXPECT_TRUE(s->deformed.key()->live) << "while dragging the repair starts from the previous picture";
  EXPECT_FALSE(updateDeformation(*s)) << "nothing changed";
  s->poseTool.release(*s, at(c1.x() + 25, c1.y() - 10));
  EXPECT_TRUE(updateDeformation(*s)) << "the release deforms again with the full repair";
  EXPECT_FALSE(s->deformed.key()->live);
  EXPECT_FALSE(updateDeformation(*s));
  WarpMesh fresh = s->mesh;  // the picture after the release is the export's
  fresh.deform(s->pose, DeformPass::Final);
  EXPECT_EQ(fresh.deformedVertices(), s->mesh.deformedVertices());
}

TEST(PoseTool, RightDragRotatesAboutTheRestPosition) {
  auto s = test::boundState();
  const Vec2 c = s->bound->cage.C.row(2).transpose();  // (255, 255)
  s->poseTool.press(*s, at(c.x(), c.y(), MouseButton::Right));
  s->poseTool.drag(*s, at(c.x() - 40, c.y(), MouseButton::Right));       // reference direction: left
  s->poseTool.release(*s, at(c.x(), c.y() + 40, MouseButton::Right));   // quarter turn to "down"
  EXPECT_NEAR(s->pose[2].rotate, std::numbers::pi / 2, 1e-9);           // counter-clockwise on screen
  EXPECT_EQ(s->pose[2].translate, Vec2::Zero());
}

TEST(PoseTool, RectangleSelectsAndMovesSeveral) {
  auto s = test::boundState();
  selectTopEdge(*s);
  s->poseTool.press(*s, at(0, 0));
  s->poseTool.release(*s, at(10, 15));
  EXPECT_TRUE(s->pose[0].translate.isApprox(Vec2(10, 15)));
  EXPECT_TRUE(s->pose[1].translate.isApprox(Vec2(10, 15)));
  EXPECT_EQ(s->pose[2].translate, Vec2::Zero());
}

TEST(PoseTool, RightDragTurnsASelectionAboutItsCentre) {
  auto s = test::boundState();
  selectTopEdge(*s);
  const Vec2 c0 = s->bound->cage.C.row(0).transpose(), c1 = s->bound->cage.C.row(1).transpose();
  const Vec2 centre = 0.5 * (c0 + c1);
  EXPECT_TRUE(selectionPivot(*s).isApprox(centre));
  // Half a turn about the centre (via a quarter turn): the two points swap places.
  const Vec2 quarter = centre + Vec2((c1 - centre).y(), -(c1 - centre).x());
  s->poseTool.press(*s, at(c1.x(), c1.y(), MouseButton::Right));
  s->poseTool.drag(*s, at(quarter.x(), quarter.y(), MouseButton::Right));
  s->poseTool.release(*s, at(c0.x(), c0.y(), MouseButton::Right));
  const Points P = posedControls(s->bound->cage.C, s->pose);
  EXPECT_LT((P.row(0).transpose() - c1).norm(), 1e-9) << P.row(0);
  EXPECT_LT((P.row(1).transpose() - c0).norm(), 1e-9) << P.row(1);
  EXPECT_NEAR(std::abs(s->pose[0].rotate), std::numbers::pi, 1e-9);
  EXPECT_EQ(s->pose[2].translate, Vec2::Zero());
  EXPECT_EQ(s->undo.undoCount(), 1u);
}

TEST(PoseTool, ThePivotCanBeMovedAndTheTurnFollowsIt) {
  auto s = test::boundState();
  selectTopEdge(*s);
  const Vec2 c0 = s->bound->cage.C.row(0).transpose(), c1 = s->bound->cage.C.row(1).transpose();
  const Vec2 centre = 0.5 * (c0 + c1), pivot = c0;  // drag the pivot marker onto point 0
  s->poseTool.press(*s, at(centre.x(), centre.y()));
  s->poseTool.drag(*s, at(pivot.x(), pivot.y()));
  s->poseTool.release(*s, at(pivot.x(), pivot.y()));
  ASSERT_TRUE(s->pivot.has_value());
  EXPECT_TRUE(s->pivot->isApprox(pivot));
  EXPECT_TRUE(isRestPose(s->pose)) << "moving the pivot moves no point";
  // A quarter turn about point 0: point 0 stays, point 1 swings a quarter circle.
  const Vec2 d = c1 - pivot, turned = pivot + Vec2(d.y(), -d.x());  // counter-clockwise on screen
  s->poseTool.press(*s, at(c1.x(), c1.y(), MouseButton::Right));
  s->poseTool.release(*s, at(turned.x(), turned.y(), MouseButton::Right));
  const Points P = posedControls(s->bound->cage.C, s->pose);
  EXPECT_LT((P.row(0).transpose() - c0).norm(), 1e-9) << P.row(0);
  EXPECT_LT((P.row(1).transpose() - turned).norm(), 1e-9) << P.row(1);
  EXPECT_NEAR(s->pose[1].rotate, std::numbers::pi / 2, 1e-9);
}

TEST(BrushTool, StrokeReoptimizesExactlyThePaintedSamples) {
  auto s = test::boundState();
  s->activeControl = 2;
  const Weights W0 = s->session->W0, W = s->session->W;
  stroke(*s, Vec2(150, 150), Vec2(200, 180));
  ASSERT_TRUE(s->session);
  ASSERT_EQ(s->undo.undoCount(), 1u);
  const auto& edit = std::get<WeightEdit>(s->undo.nextUndo()->edit);
  ASSERT_FALSE(edit.rows.empty());
  // The weights change at the painted samples and at those derived from them (the exterior rows
  // continued from the inside next to the cage), nowhere else; the undo entry holds exactly those.
  std::vector<char> painted(static_cast<std::size_t>(W.rows()), 0), derived(painted.size(), 0), recorded(painted.size(), 0);
  for (Index r : edit.rows) painted[static_cast<std::size_t>(r)] = 1;
  for (Index r : app::rederivedRows(*s->session, edit.rows)) derived[static_cast<std::size_t>(r)] = 1;
  for (Index r : edit.weightRows) recorded[static_cast<std::size_t>(r)] = 1;
  Index changed = 0;
  for (Index r = 0; r < W.rows(); ++r) {
    const bool differs = s->session->W.row(r) != W.row(r);
    ASSERT_EQ(differs, recorded[static_cast<std::size_t>(r)] != 0) << "sample " << r << ": the undo entry misses or invents a change";
    if (painted[static_cast<std::size_t>(r)]) {
      changed += differs;
      continue;
    }
    ASSERT_TRUE(!differs || derived[static_cast<std::size_t>(r)]) << "sample " << r << ", neither painted nor derived from them, changed";
    ASSERT_TRUE(s->session->W0.row(r) == W0.row(r));
  }
  EXPECT_GT(changed, Index(edit.rows.size() / 2));
  EXPECT_EQ(s->timings.reoptimizeSamples, Index(app::rederivedRows(*s->session, edit.rows).size()));
  // Painted targets moved towards control 2.
  EXPECT_GT(s->session->W0(edit.rows[0], 2), W0(edit.rows[0], 2));
}

TEST(BrushTool, UndoRestoresWeightsBitForBit) {
  auto s = test::boundState();
  s->activeControl = 1;
  const Weights W0 = s->session->W0, W = s->session->W;
  const RowMatrix coef = s->session->field->coefficients();
  stroke(*s, Vec2(100, 60), Vec2(180, 90));
  ASSERT_FALSE(s->session->W == W);
  ASSERT_TRUE(undo(*s));
  pollWorker(*s);
  ASSERT_TRUE(s->session);
  EXPECT_TRUE(s->session->W == W);
  EXPECT_TRUE(s->session->W0 == W0);
  EXPECT_TRUE(s->session->field->coefficients().isApprox(coef, 1e-12));
  ASSERT_TRUE(redo(*s));
  pollWorker(*s);
  EXPECT_FALSE(s->session->W == W);
}

TEST(BrushTool, DabKeepsRowsSummingToOne) {
  auto s = test::boundState();
  Weights W0 = s->session->W0;
  std::vector<char> painted;
  const Index n = paintDab(W0, s->session->samples, 0, Vec2(128, 128), 40.0, 0.5, painted);
  EXPECT_GT(n, 0);
  for (Index r = 0; r < W0.rows(); ++r) EXPECT_NEAR(W0.row(r).sum(), s->session->W0.row(r).sum(), 1e-9);
}

TEST(MethodSwitch, KeepsPaintedTargets) {
  auto s = test::boundState();
  s->activeControl = 3;
  stroke(*s, Vec2(60, 200), Vec2(120, 220));
  const Weights painted = s->session->W0, Wqp = s->session->W;
  ASSERT_TRUE(switchMethod(*s, Method::L1));
  pollWorker(*s);
  ASSERT_TRUE(s->session);
  EXPECT_EQ(s->bound->method, Method::L1);
  EXPECT_EQ(s->session->params.kc.method, Method::L1);
  EXPECT_TRUE(s->session->W0 == painted);
  EXPECT_FALSE(s->session->W == Wqp);
  // The undo entry holds the two methods, not four weight matrices.
  ASSERT_EQ(s->undo.undoCount(), 2u);
  const auto* edit = std::get_if<MethodEdit>(&s->undo.nextUndo()->edit);
  ASSERT_NE(edit, nullptr);
  EXPECT_EQ(edit->before, Method::QP);
  EXPECT_EQ(edit->after, Method::L1);
  EXPECT_EQ(edit->WBefore.size(), 0);  // the weights came from the optimizer: nothing stored
  const Weights Wl1 = s->session->W;
  ASSERT_TRUE(undo(*s));  // back to QP, bit for bit
  pollWorker(*s);
  ASSERT_TRUE(s->session);
  EXPECT_EQ(s->bound->method, Method::QP);
  EXPECT_TRUE(s->session->W == Wqp);
  EXPECT_TRUE(s->session->W0 == painted);
  ASSERT_TRUE(redo(*s));  // and forward again
  pollWorker(*s);
  ASSERT_TRUE(s->session);
  EXPECT_EQ(s->bound->method, Method::L1);
  EXPECT_TRUE(s->session->W == Wl1);
}

TEST(CageTool, ClicksBuildAndCloseAPolygon) {
  AppState s;
  Cage open;
  open.closed = false;
  setDraftCage(s, open);
  for (const Vec2& p : {Vec2(10, 10), Vec2(100, 10), Vec2(100, 100), Vec2(10, 100)}) {
    s.cageTool.press(s, at(p.x(), p.y()));
    s.cageTool.release(s, at(p.x(), p.y()));
  }
  EXPECT_EQ(s.cage.size(), 4);
  EXPECT_FALSE(s.cageValid);
  s.cageTool.press(s, at(11, 11));  // the first point closes it
  s.cageTool.release(s, at(11, 11));
  EXPECT_TRUE(s.cage.closed);
  EXPECT_TRUE(s.cageValid) << s.cageStatus;
  s.cageTool.press(s, at(100, 100, MouseButton::Right));  // delete a point: still a valid triangle
  EXPECT_EQ(s.cage.size(), 3);
  EXPECT_TRUE(s.cageValid);
  EXPECT_TRUE(undo(s));
  EXPECT_EQ(s.cage.size(), 4);
}

TEST(CageTool, AClickBesideAPointAcrossANarrowGapAddsAPoint) {
  // A cage drawn round two legs 3 px apart: the points of the second leg's inner side fall within
  // the pick radius (here 6 px) of the first leg's. Clicked, they are added; dragged, the point
  // under the press moves as before; a click on a point itself only selects it.
  AppState s;
  Cage open;
  open.closed = false;
  setDraftCage(s, open);
  auto click = [&](const Vec2& p) {
    s.cageTool.press(s, at(p.x(), p.y()));
    s.cageTool.release(s, at(p.x(), p.y()));
  };
  for (const Vec2& p : {Vec2(10, 10), Vec2(60, 10), Vec2(60, 100), Vec2(40, 100), Vec2(40, 30)}) click(p);
  ASSERT_EQ(s.cage.size(), 5);
  click(Vec2(37, 30));  // 3 px from point 4, across the gap
  click(Vec2(37, 100));
  ASSERT_EQ(s.cage.size(), 7) << "both sides of the gap are drawn";
  EXPECT_TRUE(s.cage.C.row(5).transpose().isApprox(Vec2(37, 30)));
  EXPECT_TRUE(s.cage.C.row(4).transpose().isApprox(Vec2(40, 30))) << "the point beside it did not move";
  click(Vec2(10, 100));
  click(Vec2(10.5, 10.5));  // the first point closes it
  EXPECT_TRUE(s.cage.closed);
  EXPECT_TRUE(s.cageValid) << s.cageStatus;
  EXPECT_EQ(s.cage.size(), 8);
  // Open again to check the other two cases.
  Cage again;
  again.closed = false;
  setDraftCage(s, again);
  for (const Vec2& p : {Vec2(10, 10), Vec2(60, 10), Vec2(60, 100)}) click(p);
  const std::size_t told = s.messages.size();
  click(Vec2(60.5, 10));  // on point 1 itself: selects it, adds nothing, and says how to add one beside it
  EXPECT_EQ(s.cage.size(), 3);
  ASSERT_EQ(s.messages.size(), told + 1);
  EXPECT_EQ(s.messages.back().text.rfind("Point 1 selected: ", 0), 0u) << s.messages.back().text;
  EXPECT_NE(s.messages.back().text.find("zoom in"), std::string::npos);
  s.cageTool.press(s, at(62, 10));  // beside point 1, then dragged: moves it, silently
  s.cageTool.drag(s, at(72, 20));
  s.cageTool.release(s, at(72, 20));
  EXPECT_EQ(s.cage.size(), 3);
  EXPECT_TRUE(s.cage.C.row(1).transpose().isApprox(Vec2(70, 20)));
  EXPECT_EQ(s.messages.size(), told + 1);
  s.cageTool.press(s, at(70, 20));  // on point 1 itself, then dragged: moves it, silently
  s.cageTool.drag(s, at(75, 25));
  s.cageTool.release(s, at(75, 25));
  EXPECT_EQ(s.messages.size(), told + 1);
}

TEST(CageTool, SelfIntersectingCageIsRejectedWithTheReason) {
  AppState s;
  Points C(4, 2);
  C << 0, 0, 100, 100, 100, 0, 0, 100;  // a bow tie
  setDraftCage(s, Cage::polygon(C));
  EXPECT_FALSE(s.cageValid);
  EXPECT_NE(s.cageStatus.find("intersect"), std::string::npos) << s.cageStatus;
  s.source = Image(128, 128, Rgba{1, 2, 3, 255});
  EXPECT_FALSE(startBind(s));
  EXPECT_FALSE(s.worker.busy());
}

TEST(CageTool, AStickFigureFromAFileBindsAndKeepsItsEdges) {
  // A cage file with an edge graph (a round head and open sticks, images/stick.cage.json) is a
  // finished cage: valid, bindable; its points move, but clicks do not add or remove any.
  AppState s;
  s.worker.setSynchronous(true);
  const std::string dir = std::string(KC_SOURCE_DIR) + "/images/";
  s.source = app::loadImage(dir + "stick.png");
  s.autoSpacing = false;
  s.bindParams.spacing = 10.0;
  const Cage stick = app::loadCage(dir + "stick.cage.json");
  ASSERT_FALSE(stick.closed);
  ASSERT_FALSE(stick.edges.empty());
  setDraftCage(s, stick);
  ASSERT_TRUE(s.cageValid) << s.cageStatus;
  s.cageTool.press(s, at(3, 3));  // empty space, far from every point
  s.cageTool.release(s, at(3, 3));
  const Vec2 p0 = stick.C.row(0).transpose();
  s.cageTool.press(s, at(p0.x(), p0.y(), MouseButton::Right));  // would delete a polygon's point
  EXPECT_EQ(s.cage.size(), stick.size());
  EXPECT_EQ(s.cage.edges, stick.edges);
  s.cageTool.press(s, at(p0.x(), p0.y()));  // drag a point by 3 px
  s.cageTool.release(s, at(p0.x() + 3, p0.y()));
  EXPECT_DOUBLE_EQ(s.cage.C(0, 0), p0.x() + 3);
  EXPECT_EQ(s.cage.edges, stick.edges);
  ASSERT_TRUE(s.cageValid) << s.cageStatus;
  ASSERT_TRUE(startBind(s));
  s.worker.waitFinished();
  pollWorker(s);
  ASSERT_TRUE(s.bound) << (s.messages.empty() ? "" : s.messages.back().text);
  ASSERT_TRUE(s.session);
  EXPECT_EQ(s.session->cage.edges, stick.edges);
  Index interior = 0;
  for (const auto kind : s.session->samples.kind) interior += kind == SampleKind::Interior;
  EXPECT_GT(interior, 0) << "the head's loop has an inside";
}

TEST(MethodSwitch, KeepsWeightsThatDidNotComeFromTheOptimizer) {
  auto s = test::boundState();
  // As after opening a session file written by another version: W is not optimize(W0, QP).
  s->weightsReproducible = false;
  s->session->W.row(40) = s->session->W.row(41);
  const Weights fromFile = s->session->W;
  ASSERT_TRUE(switchMethod(*s, Method::QEC));
  pollWorker(*s);
  const auto* edit = std::get_if<MethodEdit>(&s->undo.nextUndo()->edit);
  ASSERT_NE(edit, nullptr);
  EXPECT_EQ(edit->WBefore.rows(), fromFile.rows());
  EXPECT_TRUE(s->weightsReproducible);
  ASSERT_TRUE(undo(*s));
  pollWorker(*s);
  ASSERT_TRUE(s->session);
  EXPECT_TRUE(s->session->W == fromFile);
  EXPECT_EQ(s->bound->method, Method::QP);
}

TEST(Jobs, ReoptimizationBorrowsTheMeshWeightsLikeTheSession) {
  auto s = test::boundState();
  ASSERT_TRUE(s->meshSource);
  const Document::MeshSource* source = s->meshSource.get();
  ASSERT_TRUE(switchMethod(*s, Method::QEC));
  // While the job holds them, the main thread has neither the session nor the mesh's weights.
  EXPECT_EQ(s->session, nullptr);
  EXPECT_EQ(s->meshSource, nullptr);
  pollWorker(*s);
  ASSERT_TRUE(s->session);
  ASSERT_EQ(s->meshSource.get(), source);
  // The heatmap's numbers are the field's own at the mesh vertices.
  const Weights direct = s->session->field->weightsAt(s->mesh.restVertices());
  EXPECT_LT((s->meshSource->W - direct).cwiseAbs().maxCoeff(), 1e-12);
  const std::vector<double> w = controlWeights(s->meshSource->W, 2);
  ASSERT_EQ(static_cast<Index>(w.size()), direct.rows());
  for (Index v = 0; v < direct.rows(); v += 97) EXPECT_EQ(w[static_cast<std::size_t>(v)], s->meshSource->W(v, 2));
}


TEST(PoseTool, RightDragOffThePointsTurnsTheSelectionAndShowsTheAngle) {
  auto s = test::boundState();
  selectTopEdge(*s);
  const Vec2 c0 = s->bound->cage.C.row(0).transpose(), c1 = s->bound->cage.C.row(1).transpose();
  const Vec2 centre = 0.5 * (c0 + c1);
  // From a point of the picture below the centre (no control point there) a quarter turn.
  const Vec2 start = centre + Vec2(0, 60), quarter = centre + Vec2(60, 0);  // counter-clockwise on screen
  s->poseTool.press(*s, at(start.x(), start.y(), MouseButton::Right));
  ASSERT_TRUE(s->poseTool.rotating()) << "a right-drag off the points turns the selection";
  s->poseTool.drag(*s, at(quarter.x(), quarter.y(), MouseButton::Right));
  EXPECT_NEAR(s->poseTool.angle(), std::numbers::pi / 2, 1e-9) << "the angle shown while turning";
  s->poseTool.release(*s, at(quarter.x(), quarter.y(), MouseButton::Right));
  EXPECT_NEAR(s->pose[0].rotate, std::numbers::pi / 2, 1e-9);
  EXPECT_NEAR(s->pose[1].rotate, std::numbers::pi / 2, 1e-9);
  EXPECT_EQ(s->pose[2].translate, Vec2::Zero());
  EXPECT_EQ(s->selection.size(), 2u) << "the selection stays";
}

TEST(PoseTool, TurningOnePointReportsItsAngle) {
  auto s = test::boundState();
  const Vec2 c2 = s->bound->cage.C.row(2).transpose();
  s->poseTool.press(*s, at(c2.x(), c2.y(), MouseButton::Right));
  s->poseTool.drag(*s, at(c2.x() + 30, c2.y(), MouseButton::Right));  // the reference direction
  s->poseTool.drag(*s, at(c2.x(), c2.y() - 30, MouseButton::Right));  // a quarter turn, counter-clockwise on screen
  ASSERT_TRUE(s->poseTool.rotating());
  EXPECT_NEAR(s->poseTool.angle(), std::numbers::pi / 2, 1e-9);
  s->poseTool.release(*s, at(c2.x(), c2.y() - 30, MouseButton::Right));
  EXPECT_FALSE(s->poseTool.rotating());
}

TEST(StatusBar, UndoRedoStrokeAndMethodSwitchSayWhatHappened) {
  auto s = test::boundState();
  s->activeControl = 1;
  stroke(*s, Vec2(100, 60), Vec2(180, 90));
  ASSERT_FALSE(s->messages.empty());
  EXPECT_EQ(s->messages.back().text.rfind("Stroke (paint w1): ", 0), 0u) << s->messages.back().text;
  ASSERT_TRUE(switchMethod(*s, Method::QEC));
  pollWorker(*s);
  EXPECT_EQ(s->messages.back().text.rfind("Method QEC: ", 0), 0u) << s->messages.back().text;
  ASSERT_TRUE(undo(*s));
  EXPECT_EQ(s->messages.back().text, "Undone: method qec.");
  pollWorker(*s);
  ASSERT_TRUE(redo(*s));
  EXPECT_EQ(s->messages.back().text, "Redone: method qec.");
  pollWorker(*s);
}

TEST(Folds, AFoldIsToldWithItsFixAndItsEnd) {
  auto s = test::boundState();
  ASSERT_TRUE(updateDeformation(*s));
  ASSERT_EQ(s->deformReport.flippedTriangles, 0);
  const std::size_t messages = s->messages.size();
  // Control 0 pulled past the opposite corner: the picture folds over itself.
  const Pose before = s->pose;
  Pose pose = before;
  pose[0].translate = 1.3 * (s->bound->cage.C.row(2) - s->bound->cage.C.row(0)).transpose();
  setPose(*s, pose);
  commitPose(*s, before, "move control");
  ASSERT_TRUE(updateDeformation(*s));
  ASSERT_GT(s->deformReport.flippedTriangles, 0);
  ASSERT_GT(s->messages.size(), messages);
  const Message& m = s->messages.back();
  EXPECT_NE(m.text.find("folds over itself"), std::string::npos) << m.text;
  EXPECT_NE(m.text.find("Undo the move (Ctrl+Z)"), std::string::npos) << m.text;
  EXPECT_TRUE(m.offersUndo);
  ASSERT_TRUE(undo(*s));
  ASSERT_TRUE(updateDeformation(*s));
  EXPECT_EQ(s->deformReport.flippedTriangles, 0);
  EXPECT_EQ(s->messages.back().text, "The picture no longer folds over itself.");
}

TEST(Folds, AStrokeThatFoldsOffersToUndoTheStroke) {
  // The fold's fix names the change that made it: a stroke's is "Undo the stroke".
  auto s = test::boundState();
  ASSERT_TRUE(updateDeformation(*s));
  s->undo.push({"paint w1", WeightEdit{{0}, {0}, Weights(), Weights(), Weights(), Weights()}});
  Pose pose = s->pose;
  pose[0].translate = 1.3 * (s->bound->cage.C.row(2) - s->bound->cage.C.row(0)).transpose();
  setPose(*s, pose);  // (a stroke that folds needs a pose near the edge; the message depends only on the last edit)
  ASSERT_TRUE(updateDeformation(*s));
  ASSERT_GT(s->deformReport.flippedTriangles, 0);
  EXPECT_NE(s->messages.back().text.find("Undo the stroke (Ctrl+Z), or paint with a lower Strength"), std::string::npos)
      << s->messages.back().text;
}

}  // namespace
}  // namespace kc::ui
