#include "kc/ui/worker.h"

#include <exception>

namespace kc::ui {

bool JobContext::progress(const char* stage, double fraction) {
  {
    std::lock_guard lock(m_mutex);
    m_stage = stage;
  }
  m_fraction = fraction;
  return !m_cancel.load();
}

Worker::Worker() : m_thread([this] { loop(); }) {}

Worker::~Worker() {
  {
    std::lock_guard lock(m_mutex);
    m_stop = true;
    m_context.m_cancel = true;
  }
  m_cv.notify_all();
  m_thread.join();
}

bool Worker::submit(std::string name, Job job) {
  std::unique_lock lock(m_mutex);
  if (m_busy.load()) return false;
  m_busy = true;
  m_name = std::move(name);
  m_context.m_cancel = false;
  m_context.m_fraction = 0.0;
  {
    std::lock_guard stageLock(m_context.m_mutex);
    m_context.m_stage.clear();
  }
  if (m_synchronous) {
    lock.unlock();
    Apply result = job(m_context);
    lock.lock();
    m_result = std::move(result);
    m_hasResult = true;
    return true;
  }
  m_job = std::move(job);
  m_hasJob = true;
  m_cv.notify_all();
  return true;
}

void Worker::cancel() { m_context.m_cancel = true; }

Worker::Apply Worker::takeResult() {
  std::lock_guard lock(m_mutex);
  if (!m_hasResult) return {};
  m_hasResult = false;
  m_busy = false;
  return std::move(m_result);
}

void Worker::waitFinished() {
  std::unique_lock lock(m_mutex);
  m_cv.wait(lock, [this] { return !m_hasJob || m_stop; });
}

std::string Worker::name() const {
  std::lock_guard lock(m_mutex);
  return m_name;
}

std::string Worker::stage() const {
  std::lock_guard lock(m_context.m_mutex);
  return m_context.m_stage;
}

double Worker::fraction() const { return m_context.m_fraction.load(); }

void Worker::loop() {
  std::unique_lock lock(m_mutex);
  while (true) {
    m_cv.wait(lock, [this] { return m_stop || m_hasJob; });
    if (m_stop) return;
    Job job = std::move(m_job);
    lock.unlock();
    Apply result;
    try {
      result = job(m_context);
    } catch (...) {
      // Jobs catch their own errors (they must hand back what they borrowed); this is a last resort.
      std::exception_ptr e = std::current_exception();
      result = [e](AppState&) { std::rethrow_exception(e); };
    }
    lock.lock();
    m_result = std::move(result);
    m_hasResult = true;
    m_hasJob = false;
    m_cv.notify_all();
    if (m_wakeup) m_wakeup();
  }
}

}  // namespace kc::ui
