// kcwarp-cli bench --lines: straight and parallel lines on a cage, by default the
// bundled star — random lines of 100–150 px inside it, random translations of every control by up
// to ±40 px; deviation from straight, parallel-group angle, folds of the warp inside the cage under
// the same poses, bind time; each with and without lines.
// kcwarp-cli bench --edges: the bundled examples bound with and without --linear-edges; linearity
// along the edges, negative lobes, Lagrange, bind time.

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "cli_common.h"
#include "kc/app/diagnostics.h"
#include "kc/app/file_io.h"
#include "kc/app/line_metrics.h"
#include "kc/app/pipeline.h"
#include "kc/app/structure.h"
#include "kc/core/structure/lines.h"

namespace kc::cli {

void benchLines(const std::string& cagePath, int sets, int repeats, bool crossing) {
  const Cage cage = app::loadCage(cagePath);
  const double x1 = cage.C.col(0).maxCoeff(), y1 = cage.C.col(1).maxCoeff();
  const int w = static_cast<int>(std::ceil(x1 + 20.0)), h = static_cast<int>(std::ceil(y1 + 20.0));
  app::BindParams p = app::frameBindParams();
  const RandomLineLayout layout = crossing ? RandomLineLayout::Crossing : RandomLineLayout::ParallelPair;
  std::printf("lines: %s, %d random sets of 3 lines (100-150 px, %s), 50 random translations of every\n"
              "control by up to +-40 px each; bind times median of %d runs\n",
              cagePath.c_str(), sets, crossing ? "each after the first crossing an earlier one; graded binds" : "one parallel pair",
              repeats);
  std::printf("  (ratio: bind wall time with lines / without; cpu: the same in process CPU time, steadier on a shared\n"
              "   machine; iterations: the blue-noise relaxation's, with / without lines; folds: of the warp inside the cage\n"
              "   (--outside fixed) under the same 50 poses, poses that fold / flipped triangles, with lines and without)\n");
  std::printf("  %4s %14s %14s %12s %12s %10s %10s %7s %7s %11s %10s %15s %15s\n", "set", "bend px", "without px", "angle deg", "without",
              "bind ms", "plain ms", "ratio", "cpu", "iterations", "unity", "folds", "without");
  double worstDev = 0.0, worstAngle = 0.0, worstRatio = 0.0, worstUnity = 0.0, worstRepro = 0.0;
  int worstSet = -1;
  std::string worstLines;
  Index sumFlipped = 0, sumPlainFlipped = 0;
  std::optional<app::FoldFigures> plainFolds;  // the plain bind is the same in every set: measured once
  double sumRatio = 0.0, sumCpu = 0.0, sumSamplingLines = 0.0, sumSamplingPlain = 0.0, sumTotalLines = 0.0, sumTotalPlain = 0.0;
  for (int set = 0; set < sets; ++set) {
    app::Structure st;
    st.lines = randomLines(cage, 3, 100.0, 150.0, p.spacing, 1000 + std::uint64_t(set), layout);
    if (!crossing) st.groups = {"pair"};
    std::vector<double> tLines, tPlain, cLines, cPlain;
    app::Session lined, plain;
    const auto cpu = [] { return double(std::clock()) / CLOCKS_PER_SEC; };
    for (int r = 0; r < repeats; ++r) {
      double c0 = cpu();
      plain = app::bind(cage, w, h, p);
      cPlain.push_back(cpu() - c0);
      tPlain.push_back(plain.report.timings.total);
      c0 = cpu();
      lined = app::bind(cage, st, w, h, p);
      cLines.push_back(cpu() - c0);
      tLines.push_back(lined.report.timings.total);
    }
    for (auto* v : {&tLines, &tPlain, &cLines, &cPlain}) std::sort(v->begin(), v->end());
    const double cpuRatio = cLines[cLines.size() / 2] / cPlain[cPlain.size() / 2];
    sumCpu += cpuRatio;
    sumSamplingLines += lined.report.timings.sampling, sumSamplingPlain += plain.report.timings.sampling;
    sumTotalLines += lined.report.timings.total, sumTotalPlain += plain.report.timings.total;
    const app::LineFigures with = app::measureLines(lined, st.lines, 50), without = app::measureLines(plain, st.lines, 50);
    const app::FoldFigures folds = app::measureFolds(lined, 50);
    if (!plainFolds) plainFolds = app::measureFolds(plain, 50);
    sumFlipped += folds.flipped;
    sumPlainFlipped += plainFolds->flipped;
    const double ratio = tLines[tLines.size() / 2] / tPlain[tPlain.size() / 2];
    sumRatio += ratio;
    char iterations[32];
    std::snprintf(iterations, sizeof iterations, "%d / %d", lined.report.sampling.iterations, plain.report.sampling.iterations);
    char foldText[2][32];
    std::snprintf(foldText[0], sizeof foldText[0], "%d / %ld", folds.foldedPoses, long(folds.flipped));
    std::snprintf(foldText[1], sizeof foldText[1], "%d / %ld", plainFolds->foldedPoses, long(plainFolds->flipped));
    std::printf("  %4d %14.3g %14.3g %12.3g %12.3g %10.1f %10.1f %7.2f %7.2f %11s %10.2g %15s %15s\n", set, with.deviation, without.deviation,
                with.angle, without.angle, 1e3 * tLines[tLines.size() / 2], 1e3 * tPlain[tPlain.size() / 2], ratio, cpuRatio,
                iterations, with.unity, foldText[0], foldText[1]);
    if (with.deviation > worstDev) {  // the worst set as a --structure file, to reproduce it with kcwarp-cli bind
      worstSet = set;
      worstLines = app::structureToJson(st);
    }
    worstDev = std::max(worstDev, with.deviation);
    worstAngle = std::max(worstAngle, with.angle);
    worstRatio = std::max(worstRatio, ratio);
    worstUnity = std::max(worstUnity, with.unity);
    worstRepro = std::max(worstRepro, with.reproduction);
  }
  std::printf("  worst: bend %.3g px (goal 0.1), parallel angle %.3g deg (goal 0.05), bind time x%.2f (goal 1.2),\n"
              "         partition of unity %.2g, reproduction %.2g px on the lines\n",
              worstDev, worstAngle, worstRatio, worstUnity, worstRepro);
  std::printf("  flipped triangles over all sets and poses: %ld with lines, %ld without\n", long(sumFlipped), long(sumPlainFlipped));
  if (worstSet >= 0) std::printf("  the most bent set, %d, as a --structure file: %s", worstSet, worstLines.c_str());
  std::printf("  mean over the sets: bind time x%.2f (wall), x%.2f (CPU); the last runs' sampling took %.0f%% of the lines'\n"
              "         extra wall time (sampling %.0f ms against %.0f ms, whole bind %.0f ms against %.0f ms, summed over the sets)\n",
              sumRatio / sets, sumCpu / sets,
              sumTotalLines > sumTotalPlain ? 100.0 * (sumSamplingLines - sumSamplingPlain) / (sumTotalLines - sumTotalPlain) : 0.0,
              1e3 * sumSamplingLines, 1e3 * sumSamplingPlain, 1e3 * sumTotalLines, 1e3 * sumTotalPlain);
}

void benchEdges(const std::string& folder, int repeats) {
  std::printf("linear edges: the bundled examples in %s, default bind with and without --linear-edges; bind times median\n"
              "of %d runs; linearity every h/8 along every edge (sticks: edges on no loop); min w inside the cage\n",
              folder.c_str(), repeats);
  std::printf("  %-8s %11s %11s %11s %11s %11s %11s %10s %10s %7s\n", "example", "edges", "plain", "sticks", "plain",
              "min w in", "plain", "bind ms", "plain ms", "ratio");
  for (const char* name : {"checker", "star", "figure", "stick"}) {
    const std::filesystem::path base = std::filesystem::path(folder) / name;
    if (!std::filesystem::exists(base.string() + ".cage.json")) continue;
    const Cage cage = app::loadCage(base.string() + ".cage.json");
    if (loopEdges(cage).size() != cageEdges(cage).size()) continue;  // --linear-edges refuses sticks
    const auto [w, h] = imageSize(base.string() + ".png");
    app::BindParams plainParams, edgeParams;
    edgeParams.kc.linearEdges = true;
    std::vector<double> tEdges, tPlain;
    app::Session lined, plain;
    for (int r = 0; r < repeats; ++r) {
      plain = app::bind(cage, w, h, plainParams);
      tPlain.push_back(plain.report.timings.total);
      lined = app::bind(cage, w, h, edgeParams);
      tEdges.push_back(lined.report.timings.total);
    }
    std::sort(tEdges.begin(), tEdges.end());
    std::sort(tPlain.begin(), tPlain.end());
    const app::Diagnostics dl = app::diagnose(lined), dp = app::diagnose(plain);
    const double ratio = tEdges[tEdges.size() / 2] / tPlain[tPlain.size() / 2];
    std::printf("  %-8s %11.3g %11.3g %11s %11s %11.3g %11.3g %10.1f %10.1f %7.2f\n", name, dl.edgeLinearity, dp.edgeLinearity,
                dl.sticks ? std::to_string(dl.stickLinearity).c_str() : "-", dp.sticks ? std::to_string(dp.stickLinearity).c_str() : "-",
                dl.inside.minWeight, dp.inside.minWeight, 1e3 * tEdges[tEdges.size() / 2], 1e3 * tPlain[tPlain.size() / 2], ratio);
    std::printf("  %-8s Lagrange %.2g, partition of unity %.2g, reproduction %.2g px (whole image, with linear edges)\n", "",
                dl.lagrange, dl.image.partitionOfUnity, dl.image.reproduction);
  }
}

}  // namespace kc::cli
