// The worker: results reach the main thread only through takeResult(); an abandoned job hands its
// onAbandon closure back at once and its own result is dropped when it ends.
#include <gtest/gtest.h>

#include <future>
#include <memory>

#include "kc/ui/app_state.h"
#include "kc/ui/worker.h"

namespace kc::ui {
namespace {

/// A job that blocks until `release` is set, then returns a closure that appends `tag` to the
/// state's messages. `started` is set when it runs; the closure holds `payload`.
Worker::Job blockingJob(std::shared_future<void> release, std::promise<void>& started, std::string tag,
                        std::shared_ptr<int> payload) {
  return [release, &started, tag, payload](JobContext& ctx) -> Worker::Apply {
    started.set_value();
    release.wait();
    ctx.progress("after release", 1.0);
    return [tag](AppState& st) { st.messages.push_back({tag, false}); };
  };
}

TEST(Worker, AbandonedJobGivesBackAtOnceAndItsResultIsDropped) {
  AppState state;
  std::promise<void> release, started;
  auto payload = std::make_shared<int>(7);
  std::weak_ptr<int> watch = payload;
  ASSERT_TRUE(state.worker.submit("job", blockingJob(release.get_future().share(), started, "finished", payload),
                                  [](AppState& st) { st.messages.push_back({"abandoned", false}); }));
  payload.reset();
  started.get_future().wait();
  EXPECT_TRUE(state.worker.busy());
  state.worker.cancel();
  Worker::Apply apply = state.worker.takeResult();
  ASSERT_TRUE(apply);
  apply(state);
  EXPECT_FALSE(state.worker.busy());  // idle while the job is still blocked inside
  EXPECT_EQ(state.worker.abandonedRunning(), 1u);
  ASSERT_EQ(state.messages.size(), 1u);
  EXPECT_EQ(state.messages[0].text, "abandoned");
  EXPECT_FALSE(watch.expired());  // the running job still holds its data

  release.set_value();
  state.worker.waitAbandoned();
  EXPECT_EQ(state.worker.abandonedRunning(), 0u);
  EXPECT_FALSE(state.worker.takeResult());  // the finished job's closure never reaches the state
  EXPECT_EQ(state.messages.size(), 1u);
  EXPECT_TRUE(watch.expired());  // and what it held is released
}

TEST(Worker, NewJobRunsWhileAnAbandonedOneFinishesAndTheCapHolds) {
  AppState state;
  std::promise<void> release, started1, started2, started3;
  std::shared_future<void> gate = release.get_future().share();
  auto onAbandon = [](AppState& st) { st.messages.push_back({"abandoned", false}); };
  ASSERT_TRUE(state.worker.submit("one", blockingJob(gate, started1, "one", nullptr), onAbandon));
  started1.get_future().wait();
  state.worker.cancel();
  state.worker.takeResult()(state);
  ASSERT_TRUE(state.worker.submit("two", blockingJob(gate, started2, "two", nullptr), onAbandon));
  started2.get_future().wait();
  state.worker.cancel();
  state.worker.takeResult()(state);
  EXPECT_EQ(state.worker.abandonedRunning(), 2u);
  EXPECT_FALSE(state.worker.canAbandonMore());
  // A third abandonable job waits for one of them; a job that is not abandonable may start.
  EXPECT_FALSE(state.worker.submit("three", blockingJob(gate, started3, "three", nullptr), onAbandon));
  EXPECT_TRUE(state.worker.submit("plain", [](JobContext&) -> Worker::Apply {
    return [](AppState& st) { st.messages.push_back({"plain", false}); };
  }));
  state.worker.waitFinished();
  state.worker.takeResult()(state);
  release.set_value();
  state.worker.waitAbandoned();
  EXPECT_FALSE(state.worker.takeResult());
  ASSERT_EQ(state.messages.size(), 3u);
  EXPECT_EQ(state.messages[2].text, "plain");
  EXPECT_TRUE(state.worker.canAbandonMore());
}

TEST(Worker, CancelWithoutOnAbandonWaitsForTheJobsOwnAnswer) {
  AppState state;
  std::promise<void> release, started;
  ASSERT_TRUE(state.worker.submit("job", [gate = release.get_future().share(), &started](JobContext& ctx) -> Worker::Apply {
    started.set_value();
    gate.wait();
    const bool going = ctx.progress("stage", 0.5);
    return [going](AppState& st) { st.messages.push_back({going ? "ran on" : "stopped", false}); };
  }));
  started.get_future().wait();
  state.worker.cancel();
  EXPECT_FALSE(state.worker.takeResult());  // not abandonable: still running
  EXPECT_TRUE(state.worker.busy());
  release.set_value();
  state.worker.waitFinished();
  state.worker.takeResult()(state);
  ASSERT_EQ(state.messages.size(), 1u);
  EXPECT_EQ(state.messages[0].text, "stopped");
  EXPECT_EQ(state.worker.abandonedRunning(), 0u);
}

}  // namespace
}  // namespace kc::ui
