// kcwarp-cli bench --lines: straight and parallel lines (issue 13's goals) on a cage, by default the
// bundled star — random lines of 100–150 px inside it, random translations of every control by up
// to ±40 px; deviation from straight, parallel-group angle, bind time with and without lines.

#include <algorithm>
#include <cstdio>
#include <vector>

#include "cli_common.h"
#include "kc/app/file_io.h"
#include "kc/app/line_metrics.h"
#include "kc/app/pipeline.h"
#include "kc/core/structure/lines.h"

namespace kc::cli {

void benchLines(const std::string& cagePath, int sets, int repeats) {
  const Cage cage = app::loadCage(cagePath);
  const double x1 = cage.C.col(0).maxCoeff(), y1 = cage.C.col(1).maxCoeff();
  const int w = static_cast<int>(std::ceil(x1 + 20.0)), h = static_cast<int>(std::ceil(y1 + 20.0));
  app::BindParams p;
  std::printf("lines: %s, %d random sets of 3 lines (100-150 px, one parallel pair), 50 random translations of every\n"
              "control by up to +-40 px each; bind times median of %d runs\n",
              cagePath.c_str(), sets, repeats);
  std::printf("  %4s %14s %14s %12s %12s %10s %10s %7s %10s\n", "set", "bend px", "without px", "angle deg", "without",
              "bind ms", "plain ms", "ratio", "unity");
  double worstDev = 0.0, worstAngle = 0.0, worstRatio = 0.0, worstUnity = 0.0, worstRepro = 0.0;
  for (int set = 0; set < sets; ++set) {
    app::Structure st;
    st.lines = randomLines(cage, 3, 100.0, 150.0, p.spacing, 1000 + std::uint64_t(set), true);
    st.groups = {"pair"};
    std::vector<double> tLines, tPlain;
    app::Session lined, plain;
    for (int r = 0; r < repeats; ++r) {
      plain = app::bind(cage, w, h, p);
      tPlain.push_back(plain.timings.total);
      lined = app::bind(cage, st, w, h, p);
      tLines.push_back(lined.timings.total);
    }
    std::sort(tLines.begin(), tLines.end());
    std::sort(tPlain.begin(), tPlain.end());
    const app::LineFigures with = app::measureLines(lined, st.lines, 50), without = app::measureLines(plain, st.lines, 50);
    const double ratio = tLines[tLines.size() / 2] / tPlain[tPlain.size() / 2];
    std::printf("  %4d %14.3g %14.3g %12.3g %12.3g %10.1f %10.1f %7.2f %10.2g\n", set, with.deviation, without.deviation, with.angle,
                without.angle, 1e3 * tLines[tLines.size() / 2], 1e3 * tPlain[tPlain.size() / 2], ratio, with.unity);
    worstDev = std::max(worstDev, with.deviation);
    worstAngle = std::max(worstAngle, with.angle);
    worstRatio = std::max(worstRatio, ratio);
    worstUnity = std::max(worstUnity, with.unity);
    worstRepro = std::max(worstRepro, with.reproduction);
  }
  std::printf("  worst: bend %.3g px (goal 0.1), parallel angle %.3g deg (goal 0.05), bind time x%.2f (goal 1.2),\n"
              "         partition of unity %.2g, reproduction %.2g px on the lines\n",
              worstDev, worstAngle, worstRatio, worstUnity, worstRepro);
}

}  // namespace kc::cli
