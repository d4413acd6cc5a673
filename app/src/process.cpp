#include "kc/app/process.h"

#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <new>

namespace kc::app {

void preferPassiveOpenMpWaiting(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") != nullptr) return;
  if (::setenv("OMP_WAIT_POLICY", "PASSIVE", 1) != 0) return;
  ::execv("/proc/self/exe", argv);  // returns only on failure: carry on with the default policy
}

namespace {

std::atomic<char*> g_reserve{nullptr};

void releaseReserve() {
  delete[] g_reserve.exchange(nullptr);
  std::set_new_handler(nullptr);
  throw std::bad_alloc();
}

}  // namespace

void keepMemoryReserve() {
  if (g_reserve.load() != nullptr) return;
  char* reserve = new (std::nothrow) char[kMemoryReserveBytes];
  if (reserve == nullptr) return;
  char* none = nullptr;
  if (!g_reserve.compare_exchange_strong(none, reserve)) delete[] reserve;  // another thread set one aside
  std::set_new_handler(releaseReserve);
}

}  // namespace kc::app
