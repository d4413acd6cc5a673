// Progress and Cancel of a bind: for each stage, the longest time between two progress
// calls (a Cancel is noticed at the next call, so this bounds the time Cancel takes in app::bind)
// and the measured time from a cancel request in the middle of the stage until bind() returns.
// With the GUI built, also "ui cancel s": the same request made through the GUI's worker (the
// status bar's Cancel) until the window is idle with its previous session back — the worker
// abandons the bind, so this stays short even in the stages that are one solver call. Pictures:
// 800×600 (a person's drawing) and 1920×1440, a character-sized cage, default parameters (h = 6).
#include <benchmark/benchmark.h>

#include <atomic>
#include <chrono>
#include <map>
#include <optional>
#include <string>
#include <thread>

#include "kc/app/pipeline.h"
#ifdef KC_BENCH_UI
#include "kc/ui/app_state.h"
#include "kc/ui/edits.h"
#include "kc/ui/jobs.h"
#endif

namespace {

using namespace kc;
using Clock = std::chrono::steady_clock;

double secondsBetween(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

/// A 10-point cage around the middle of a width×height picture (a figure with raised arms).
Cage figureCage(int width, int height) {
  const double sx = width / 800.0, sy = height / 600.0;
  const double pts[10][2] = {{340, 120}, {460, 120}, {470, 230}, {600, 200}, {610, 260},
                             {470, 300}, {480, 480}, {320, 480}, {330, 300}, {200, 260}};
  Points C(10, 2);
  for (int i = 0; i < 10; ++i) C.row(i) << pts[i][0] * sx, pts[i][1] * sy;
  return Cage::polygon(C);
}

struct StageTimes {
  std::map<std::string, double> start, end, longestGap;
  std::vector<std::string> order;
};

/// One uncancelled bind: when each stage starts and ends, and its longest gap between progress calls.
StageTimes profile(const Cage& cage, int w, int h) {
  StageTimes t;
  const auto t0 = Clock::now();
  std::string stage;
  double last = 0.0;
  app::bind(cage, w, h, app::frameBindParams(), [&](const char* s, double) {
    const double now = secondsBetween(t0, Clock::now());
    if (stage != s) {
      if (!stage.empty()) t.end[stage] = now;
      stage = s;
      t.order.push_back(stage);
      t.start[stage] = now;
    } else {
      t.longestGap[stage] = std::max(t.longestGap[stage], now - last);
    }
    last = now;
    return true;
  });
  return t;
}

/// Seconds from a cancel request at `at` seconds after the start of a bind until it returns.
double cancelLatency(const Cage& cage, int w, int h, double at) {
  std::atomic<bool> cancel{false};
  Clock::time_point requested;
  std::thread canceller([&] {
    std::this_thread::sleep_for(std::chrono::duration<double>(at));
    requested = Clock::now();
    cancel = true;
  });
  bool cancelled = false;
  try {
    app::bind(cage, w, h, app::frameBindParams(), [&](const char*, double) { return !cancel.load(); });
  } catch (const Cancelled&) {
    cancelled = true;
  }
  const auto returned = Clock::now();
  canceller.join();
  return cancelled ? secondsBetween(requested, returned) : -1.0;  // −1: finished before the request
}

#ifdef KC_BENCH_UI
/// Seconds from a Cancel made `delay` seconds into stage `stage` of the GUI's Bind (as the
/// worker reports it) until the window is idle again with its previous state: the main thread
/// polls the worker every millisecond, as frames would (the window adds at most one frame).
/// −1: the stage was missed or ended before the delay. The abandoned bind is
/// waited for afterwards, outside the measured time, so it does not slow the next measurement.
double uiCancelLatency(const Cage& cage, int w, int h, const std::string& stage, double delay) {
  ui::AppState st;
  st.source = Image(w, h);
  ui::setDraftCage(st, cage);
  if (!ui::startBind(st)) return -1.0;
  std::optional<Clock::time_point> entered, requested;
  bool asked = false;
  while (st.worker.busy()) {
    if (!asked && st.worker.stage() == stage) {
      if (!entered) entered = Clock::now();
      if (secondsBetween(*entered, Clock::now()) >= delay) {
        requested = Clock::now();
        st.worker.cancel();
        asked = true;
      }
    } else if (!asked && entered) {
      asked = true;  // the stage ended before the delay: not measured
      st.worker.cancel();
    }
    ui::pollWorker(st);
    if (st.worker.busy()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  const auto idle = Clock::now();
  st.worker.waitAbandoned();
  return requested && !st.bound ? secondsBetween(*requested, idle) : -1.0;
}
#endif

void BM_BindCancel(benchmark::State& state) {
  const int w = static_cast<int>(state.range(0)), h = w * 3 / 4;
  const Cage cage = figureCage(w, h);
  for (auto _ : state) {
    const StageTimes t = profile(cage, w, h);
    for (const std::string& s : t.order) {
      if (s == "done") continue;
      const double mid = 0.5 * (t.start.at(s) + (t.end.count(s) ? t.end.at(s) : t.start.at(s)));
      const double seconds = (t.end.count(s) ? t.end.at(s) : t.start.at(s)) - t.start.at(s);
      state.counters[s + " s"] = seconds;
      state.counters[s + " gap s"] = t.longestGap.count(s) ? t.longestGap.at(s) : 0.0;
      state.counters[s + " cancel s"] = cancelLatency(cage, w, h, mid);
#ifdef KC_BENCH_UI
      state.counters[s + " ui cancel s"] = uiCancelLatency(cage, w, h, s, 0.5 * seconds);
#endif
    }
  }
}

BENCHMARK(BM_BindCancel)->Arg(800)->Arg(1920)->Iterations(1)->Unit(benchmark::kSecond);

}  // namespace

BENCHMARK_MAIN();
