#include "kc/ui/worker.h"

#include <exception>
#include <thread>

namespace kc::ui {

/// One job on its own thread. `finished`, `abandoned` and `result` are guarded by Worker::m_mutex.
struct Worker::Run {
  JobContext context;
  Job job;
  Apply onAbandon;
  Apply result;
  bool finished = false, abandoned = false;
  std::thread thread;
};

bool JobContext::progress(const char* stage, double fraction) {
  bool entered = false;
  {
    std::lock_guard lock(m_mutex);
    entered = m_stage != stage;
    if (entered) m_stage = stage;
  }
  m_fraction = fraction;
  if (entered && m_stageHook) m_stageHook(stage);
  return !m_cancel.load();
}

Worker::Worker() = default;

Worker::~Worker() {
  std::vector<std::shared_ptr<Run>> runs;
  {
    std::lock_guard lock(m_mutex);
    runs = std::move(m_abandoned);
    if (m_current) runs.push_back(std::move(m_current));
  }
  for (const auto& run : runs) {
    run->context.m_cancel = true;
    if (run->thread.joinable()) run->thread.join();
  }
}

bool Worker::submit(std::string name, Job job, Apply onAbandon) {
  std::vector<std::shared_ptr<Run>> ended;
  std::unique_lock lock(m_mutex);
  reapLocked(ended);
  if (m_busy.load() || (onAbandon && m_abandoned.size() >= kMaxAbandoned)) return false;
  auto run = std::make_shared<Run>();
  run->context.m_stageHook = m_stageHook;
  run->job = std::move(job);
  run->onAbandon = std::move(onAbandon);
  m_busy = true;
  m_name = std::move(name);
  m_current = run;
  if (m_synchronous) {
    lock.unlock();
    runOn(run);
    return true;
  }
  run->thread = std::thread([this, run] { runOn(run); });
  lock.unlock();
  for (const auto& r : ended) r->thread.join();
  return true;
}

void Worker::runOn(const std::shared_ptr<Run>& run) {
  Apply result;
  {
    Job job = std::move(run->job);
    try {
      result = job(run->context);
    } catch (...) {
      // Jobs catch their own errors (they must hand back what they borrowed); this is a last resort.
      std::exception_ptr e = std::current_exception();
      result = [e](AppState&) { std::rethrow_exception(e); };
    }
  }  // the job's captures are released here, on this thread
  bool abandoned = false;
  {
    std::lock_guard lock(m_mutex);
    abandoned = run->abandoned;
    if (!abandoned) {
      run->result = std::move(result);
      run->finished = true;
    }
  }
  if (abandoned) {
    result = nullptr;  // the discarded result (a whole session, say) is freed off the main thread
    std::lock_guard lock(m_mutex);
    run->finished = true;
  }
  m_cv.notify_all();
  if (!abandoned && m_wakeup) m_wakeup();
}

void Worker::reapLocked(std::vector<std::shared_ptr<Run>>& ended) {
  for (std::size_t k = 0; k < m_abandoned.size();) {
    if (m_abandoned[k]->finished) {
      ended.push_back(std::move(m_abandoned[k]));
      m_abandoned.erase(m_abandoned.begin() + static_cast<long>(k));
    } else {
      ++k;
    }
  }
}

void Worker::cancel() {
  std::lock_guard lock(m_mutex);
  if (!m_current) return;
  m_current->context.m_cancel = true;
  if (m_synchronous || m_current->finished || !m_current->onAbandon) return;
  m_current->abandoned = true;
  m_result = std::move(m_current->onAbandon);
  m_hasResult = true;
  m_abandoned.push_back(std::move(m_current));
}

Worker::Apply Worker::takeResult() {
  std::vector<std::shared_ptr<Run>> ended;
  Apply result;
  {
    std::lock_guard lock(m_mutex);
    reapLocked(ended);
    if (m_hasResult) {
      result = std::move(m_result);
      m_hasResult = false;
    } else if (m_current && m_current->finished) {
      result = std::move(m_current->result);
      ended.push_back(std::move(m_current));
    } else {
      return {};
    }
    m_busy = false;
  }
  for (const auto& r : ended)
    if (r->thread.joinable()) r->thread.join();  // ended: returns at once
  return result;
}

void Worker::waitFinished() {
  std::unique_lock lock(m_mutex);
  m_cv.wait(lock, [this] { return !m_current || m_current->finished; });
}

std::size_t Worker::abandonedRunning() const {
  std::lock_guard lock(m_mutex);
  std::size_t n = 0;
  for (const auto& r : m_abandoned) n += !r->finished;
  return n;
}

void Worker::waitAbandoned() {
  std::vector<std::shared_ptr<Run>> ended;
  {
    std::unique_lock lock(m_mutex);
    m_cv.wait(lock, [this] {
      for (const auto& r : m_abandoned)
        if (!r->finished) return false;
      return true;
    });
    reapLocked(ended);
  }
  for (const auto& r : ended) r->thread.join();
}

std::string Worker::name() const {
  std::lock_guard lock(m_mutex);
  return m_name;
}

std::string Worker::stage() const {
  std::lock_guard lock(m_mutex);
  if (!m_current) return {};
  std::lock_guard stageLock(m_current->context.m_mutex);
  return m_current->context.m_stage;
}

double Worker::fraction() const {
  std::lock_guard lock(m_mutex);
  return m_current ? m_current->context.m_fraction.load() : 0.0;
}

bool Worker::cancelRequested() const {
  std::lock_guard lock(m_mutex);
  return m_current && m_current->context.cancelled();
}

}  // namespace kc::ui
