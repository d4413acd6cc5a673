#pragma once
/// Background jobs for long work (bind, re-optimization, loading, export). A job runs off the main
/// thread and returns a closure that the main thread applies to the AppState, so the state is only
/// ever written on the main thread (STYLE.md, Immediate-mode UI).
///
/// Cancel. A job sees Cancel at its next JobContext::progress() call; most stages call it often.
/// Some stages are one library call that cannot be interrupted (the kernel factorization, the
/// steady-state heat solve: seconds on a large picture). A job submitted with an `onAbandon`
/// closure is therefore *abandoned* on Cancel: the worker hands `onAbandon` (which gives back what
/// the job borrowed) to the next takeResult() at once, becomes idle, and the job runs on to its end
/// on its own thread, where its result is destroyed unapplied (it never reaches the AppState).
/// A new job may start meanwhile; while kMaxAbandoned abandoned jobs are still running, submit()
/// refuses further abandonable jobs until one has ended (bounds the memory and CPU they hold).

#include <atomic>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace kc::ui {

struct AppState;

/// What a running job sees: report progress, check for Cancel.
class JobContext {
 public:
  /// Stage name and fraction in [0, 1]; returns false when the user asked to cancel.
  bool progress(const char* stage, double fraction);
  bool cancelled() const { return m_cancel.load(); }

 private:
  friend class Worker;
  std::atomic<bool> m_cancel{false};
  std::atomic<double> m_fraction{0.0};
  mutable std::mutex m_mutex;
  std::string m_stage;
  std::function<void(const std::string&)> m_stageHook;
};

class Worker {
 public:
  /// Applied on the main thread when the job is done.
  using Apply = std::function<void(AppState&)>;
  /// Runs on a worker thread; must not touch the AppState.
  using Job = std::function<Apply(JobContext&)>;
  /// Abandoned jobs that may still be running before submit() refuses new ones.
  static constexpr std::size_t kMaxAbandoned = 2;

  Worker();
  /// Cancels every job and waits for all of them, abandoned ones included.
  ~Worker();
  Worker(const Worker&) = delete;
  Worker& operator=(const Worker&) = delete;

  /// Starts `job` named `name` (shown in the status bar). With `onAbandon`, Cancel abandons the job
  /// (see the file comment) and `onAbandon` is the result. Returns false when a job is running, or
  /// for a job with `onAbandon` when canAbandonMore() is false.
  bool submit(std::string name, Job job, Apply onAbandon = {});
  /// True from submit() until the job's result (or its onAbandon) has been taken.
  bool busy() const { return m_busy.load(); }
  /// Asks the running job to stop (it sees JobContext::cancelled / progress() == false); a job
  /// with an onAbandon closure is abandoned at once.
  void cancel();
  /// The finished (or abandoned) job's closure (empty when none); the worker becomes idle.
  Apply takeResult();
  /// Blocks until the running job finished (its result still has to be taken).
  void waitFinished();
  /// False while kMaxAbandoned abandoned jobs are still running (no further abandonable job may start).
  bool canAbandonMore() const { return abandonedRunning() < kMaxAbandoned; }
  /// Abandoned jobs still running.
  std::size_t abandonedRunning() const;
  /// Blocks until every abandoned job has ended.
  void waitAbandoned();

  /// Called on a worker thread when a (not abandoned) job has finished (e.g. glfwPostEmptyEvent to
  /// wake the main loop, so results are applied without waiting for the next input event).
  void setWakeup(std::function<void()> wakeup) { m_wakeup = std::move(wakeup); }
  /// Called on the worker thread whenever a job enters a new progress stage, with the stage name
  /// (tests hold a job inside a stage with it). Set while no job runs.
  void setStageHook(std::function<void(const std::string&)> hook) { m_stageHook = std::move(hook); }

  /// Runs jobs inline in submit() (tests without threads; Cancel cannot abandon then).
  void setSynchronous(bool on) { m_synchronous = on; }

  std::string name() const;
  std::string stage() const;
  double fraction() const;
  bool cancelRequested() const;

 private:
  struct Run;
  void runOn(const std::shared_ptr<Run>& run);
  /// Moves the abandoned jobs that have ended to `ended` (joined by the caller, unlocked).
  void reapLocked(std::vector<std::shared_ptr<Run>>& ended);

  mutable std::mutex m_mutex;
  std::condition_variable m_cv;
  std::shared_ptr<Run> m_current;                 ///< The running (or finished, untaken) job.
  std::vector<std::shared_ptr<Run>> m_abandoned;  ///< Abandoned jobs, joined when they have ended.
  Apply m_result;
  bool m_hasResult = false, m_synchronous = false;
  std::atomic<bool> m_busy{false};
  std::string m_name;
  std::function<void()> m_wakeup;
  std::function<void(const std::string&)> m_stageHook;
};

}  // namespace kc::ui
