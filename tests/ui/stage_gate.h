#pragma once
// Test support: holds a worker job inside one bind stage (a stand-in for a long solver call), so
// Cancel can be pressed while the job is there, and remembers every stage the jobs entered.

#include <gtest/gtest.h>

#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "kc/ui/jobs.h"

namespace kc::test {

/// Holds the first job that enters `stage` until release(). Install as the worker's stage hook.
class StageGate {
 public:
  explicit StageGate(std::string stage) : m_stage(std::move(stage)) {}
  void operator()(const std::string& stage) {
    {
      std::lock_guard lock(m_mutex);
      m_seen.insert(stage);
    }
    if (stage != m_stage || m_used.exchange(true)) return;
    std::unique_lock lock(m_mutex);
    m_inside = true;
    m_cv.notify_all();
    m_cv.wait(lock, [this] { return m_released; });
  }
  /// Blocks until a job is held in the stage.
  void waitInside() {
    std::unique_lock lock(m_mutex);
    m_cv.wait(lock, [this] { return m_inside; });
  }
  void release() {
    std::lock_guard lock(m_mutex);
    m_released = true;
    m_cv.notify_all();
  }
  /// True when some job entered `stage` (held or not).
  bool seen(const std::string& stage) {
    std::lock_guard lock(m_mutex);
    return m_seen.count(stage) > 0;
  }

 private:
  std::string m_stage;
  std::atomic<bool> m_used{false};
  std::mutex m_mutex;
  std::condition_variable m_cv;
  std::set<std::string> m_seen;
  bool m_inside = false, m_released = false;
};

/// Binds `state` (its bound session, draft cage and Bind panel) on a threaded worker once per
/// stage of `stages` (in the order a bind passes them), cancelling while the bind is held inside
/// that stage: the window must have its session back at once and keep it when the abandoned bind
/// ends, and the bind must stop at its next report — no stage two places further is entered.
inline void expectCancelInEveryStage(ui::AppState& state, const std::vector<std::string>& stages) {
  state.worker.setSynchronous(false);
  std::unique_ptr<StageGate> gate;  // replaced per stage, only while no job runs
  state.worker.setStageHook([&gate](const std::string& stage) { (*gate)(stage); });
  const app::Session* before = state.session.get();
  for (std::size_t k = 0; k < stages.size(); ++k) {
    SCOPED_TRACE(stages[k]);
    gate = std::make_unique<StageGate>(stages[k]);
    ASSERT_TRUE(ui::startBind(state));
    gate->waitInside();
    EXPECT_EQ(state.worker.stage(), stages[k]);
    state.worker.cancel();
    ui::pollWorker(state);
    EXPECT_FALSE(state.worker.busy());
    EXPECT_EQ(state.session.get(), before);
    gate->release();
    state.worker.waitAbandoned();
    ui::pollWorker(state);
    EXPECT_EQ(state.session.get(), before);
    ASSERT_FALSE(state.messages.empty());
    EXPECT_EQ(state.messages.back().text, "Bind cancelled.");
    for (std::size_t later = k + 2; later < stages.size(); ++later) EXPECT_FALSE(gate->seen(stages[later])) << stages[later];
  }
  state.worker.setStageHook(nullptr);
}

}  // namespace kc::test
