#pragma once
/// One background thread for long jobs (bind, re-optimization, loading, export). A job runs off
/// the main thread and returns a closure that the main thread applies to the AppState, so the
/// state is only ever written on the main thread (STYLE.md, Immediate-mode UI).

#include <atomic>
#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

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
};

class Worker {
 public:
  /// Applied on the main thread when the job is done.
  using Apply = std::function<void(AppState&)>;
  /// Runs on the worker thread; must not touch the AppState.
  using Job = std::function<Apply(JobContext&)>;

  Worker();
  ~Worker();
  Worker(const Worker&) = delete;
  Worker& operator=(const Worker&) = delete;

  /// Starts `job` named `name` (shown in the status bar). Returns false when a job is running.
  bool submit(std::string name, Job job);
  /// True from submit() until the job's result has been taken.
  bool busy() const { return m_busy.load(); }
  /// Asks the running job to stop (it sees JobContext::cancelled / progress() == false).
  void cancel();
  /// The finished job's closure (empty when none); the worker becomes idle.
  Apply takeResult();
  /// Blocks until the running job finished (its result still has to be taken).
  void waitFinished();

  /// Called on the worker thread when a job has finished (e.g. glfwPostEmptyEvent to wake the
  /// main loop, so results are applied without waiting for the next input event).
  void setWakeup(std::function<void()> wakeup) { m_wakeup = std::move(wakeup); }

  /// Runs jobs inline in submit() (tests without threads).
  void setSynchronous(bool on) { m_synchronous = on; }

  std::string name() const;
  std::string stage() const;
  double fraction() const;
  bool cancelRequested() const { return m_context.cancelled(); }

 private:
  void loop();

  mutable std::mutex m_mutex;
  std::condition_variable m_cv;
  Job m_job;
  Apply m_result;
  bool m_hasJob = false, m_hasResult = false, m_stop = false, m_synchronous = false;
  std::atomic<bool> m_busy{false};
  std::string m_name;
  std::function<void()> m_wakeup;
  JobContext m_context;
  std::thread m_thread;
};

}  // namespace kc::ui
