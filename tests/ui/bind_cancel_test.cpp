// Cancel of a bind in the window: the status bar's Cancel gives the previous session back at once
// in every stage, also while the worker is inside a solver call that cannot stop (held here in
// the stage by a stage hook, so no timing is asserted); the abandoned bind never writes the state.
#include <gtest/gtest.h>

#include <string>

#include "kc/ui/frame.h"
#include "stage_gate.h"
#include "ui_fixture.h"

namespace kc::ui {
namespace {

using test::StageGate;

/// The bound checker example with a threaded worker whose jobs pass through `gate`.
std::unique_ptr<AppState> threadedState(StageGate& gate) {
  auto s = test::boundState();
  s->worker.setSynchronous(false);
  s->worker.setStageHook([&gate](const std::string& stage) { gate(stage); });
  return s;
}

TEST(BindCancel, DuringTheFactorizationTheWindowIsIdleBeforeTheWorkerHasFinished) {
  test::HeadlessImGui gui;
  StageGate gate("factorization");  // the kernel matrix's factorization, one CHOLMOD call
  auto s = threadedState(gate);
  auto draw = [&] { drawFrame(*s); };
  const app::Session* before = s->session.get();
  const Pose pose = s->pose;
  s->tool = Tool::Cage;
  gui.frame(draw);
  gui.clickLabel(*s, "Bind", draw);
  gate.waitInside();
  ASSERT_TRUE(s->worker.busy());
  EXPECT_EQ(s->session, nullptr) << "the bind holds the session while it runs";
  EXPECT_EQ(s->worker.stage(), "factorization");

  gui.frame(draw);
  gui.clickLabel(*s, "Cancel", draw);  // the status bar's Cancel
  pollWorker(*s);                      // the window's next frame
  // The worker is still inside the stage (held by the gate), yet the window is back.
  EXPECT_EQ(s->worker.abandonedRunning(), 1u);
  EXPECT_FALSE(s->worker.busy());
  EXPECT_EQ(s->session.get(), before);
  EXPECT_EQ(s->tool, Tool::Cage) << "the tool did not change";
  EXPECT_TRUE(s->pose.size() == pose.size() && s->pose[0].translate == pose[0].translate);
  ASSERT_FALSE(s->messages.empty());
  EXPECT_EQ(s->messages.back().text, "Bind cancelled.");

  // The controls work: a new bind starts and finishes while the abandoned one is still held.
  gui.frame(draw);
  gui.clickLabel(*s, "Bind", draw);
  EXPECT_TRUE(s->worker.busy()) << (s->messages.empty() ? "" : s->messages.back().text);
  s->worker.waitFinished();
  pollWorker(*s);
  ASSERT_TRUE(s->session);
  const app::Session* rebound = s->session.get();
  EXPECT_NE(rebound, before);
  EXPECT_EQ(s->tool, Tool::Pose);
  EXPECT_EQ(s->worker.abandonedRunning(), 1u);

  // The abandoned bind ends; its result is dropped, the session stays the new one.
  const std::size_t messages = s->messages.size();
  gate.release();
  s->worker.waitAbandoned();
  pollWorker(*s);
  EXPECT_EQ(s->session.get(), rebound);
  EXPECT_EQ(s->messages.size(), messages);
  EXPECT_FALSE(s->worker.busy());
}

TEST(BindCancel, EveryStageGivesTheSessionBackAtOnce) {
  auto s = test::boundState(20.0);
  test::expectCancelInEveryStage(*s, {"sampling", "kernel", "initial weights", "factorization", "optimization", "interpolation", "warp mesh"});
}

}  // namespace
}  // namespace kc::ui
