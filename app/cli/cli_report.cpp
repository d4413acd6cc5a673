// Text of the weight reports shared by `kcwarp-cli stats` and `kcwarp-cli demo`.

#include "cli_report.h"

#include <cmath>
#include <cstdio>

#include "kc/app/text.h"

namespace kc::cli {

using app::format;
using app::shortNumber;


std::string dragText(const app::Diagnostics& d, const char* indent) {
  const app::DragArea& a = d.drag;
  if (a.points == 0) return format("%sarea that moves under a drag: no grid point inside the cage\n", indent);
  return format("%sarea that moves >= %g px under a %g px drag of one control (w_i >= %g, every %d px): mean %.1f%%, max %.1f%% "
                "(control %ld) of the cage; deepest weight %.3g\n",
                indent, app::kVisibleShift, app::kDragPixels, app::kDragWeight, a.step, 100.0 * a.mean, 100.0 * a.max,
                static_cast<long>(a.maxControl), a.minWeight);
}

std::string localityText(const app::Diagnostics& d, const char* indent) {
  const LocalityStats& l = d.locality;
  std::string out;
  for (std::size_t i = 0; i < l.t.size(); ++i)
    out += format("%sP(%.0e) = %.3f   (mean fraction of the cage where |w_i| <= t)\n", indent, l.t[i], l.P[i]);
  out += format("%scontrol points influencing a point (w > 1e-3/m): mean %.2f, max %d\n", indent, l.meanInfluencing,
                l.maxInfluencing);
  out += indent;
  out += "Q(k), the fraction of the cage influenced by at least k control points:";
  for (std::size_t k = 1; k < l.Q.size() && k <= 8; ++k) out += format(" Q(%zu) %.3f", k, l.Q[k]);
  out += format("\n%scompact weights (w > 1e-3/m, CSR) take %.1f%% of dense storage (LBC paper Table 1)\n", indent,
                100.0 * d.compactFraction);
  out += dragText(d, indent);
  return out;
}

}  // namespace kc::cli
