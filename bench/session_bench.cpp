// Session files: save (to text) and load (text → validated session with its field
// rebuilt) of the bundled figure bound at its size with default parameters, with the weights in
// the compact form (base64 of little-endian doubles, the default) and as JSON rows (older files).
// Counter "MB": the file's size.
#include <benchmark/benchmark.h>

#include <string>

#include "kc/app/file_io.h"
#include "kc/app/image_io.h"
#include "kc/app/pipeline.h"

#ifndef KC_SOURCE_DIR
#define KC_SOURCE_DIR "."
#endif

namespace {

using namespace kc;

const app::Session& figureSession() {
  static const app::Session s = [] {
    const std::string base = std::string(KC_SOURCE_DIR) + "/images/figure";
    const Image picture = app::loadImage(base + ".png");
    return app::bind(app::loadCage(base + ".cage.json"), picture.width, picture.height, app::frameBindParams());
  }();
  return s;
}

app::WeightsForm formOf(const benchmark::State& state) {
  return state.range(0) == 0 ? app::WeightsForm::Compact : app::WeightsForm::Rows;
}

void BM_SessionSave(benchmark::State& state) {
  const app::Session& s = figureSession();
  std::size_t bytes = 0;
  for (auto _ : state) {
    const std::string text = app::sessionToJson(s, formOf(state));
    bytes = text.size();
    benchmark::DoNotOptimize(text.data());
  }
  state.counters["MB"] = double(bytes) / 1e6;
  state.SetLabel(state.range(0) == 0 ? "compact" : "rows");
}

void BM_SessionLoad(benchmark::State& state) {
  const app::Session& s = figureSession();
  const std::string text = app::sessionToJson(s, formOf(state));
  for (auto _ : state) {
    const app::Session t = app::sessionFromJson(text, "figure.kcw.json");
    benchmark::DoNotOptimize(t.W.data());
  }
  state.counters["MB"] = double(text.size()) / 1e6;
  state.counters["samples"] = double(s.samples.size());
  state.SetLabel(state.range(0) == 0 ? "compact" : "rows");
}

}  // namespace

BENCHMARK(BM_SessionSave)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SessionLoad)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
