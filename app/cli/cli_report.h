#pragma once
// Text of the weight reports that `stats` and `demo` share: locality (LBC paper eq. 19–21, Table 1)
// and the LBC solver's report.

#include <string>

#include "kc/app/diagnostics.h"
#include "kc/app/session.h"

namespace kc::cli {

/// One line per item, each starting with `indent`: P(t) for every tabulated t, the mean and
/// largest number of controls above 10⁻³/m per point, Q(1..8), and the compact weights' memory
/// over dense storage — all measured inside the cage (Diagnostics::locality, compactFraction).
std::string localityText(const app::Diagnostics& d, const char* indent);

/// One line starting with `indent`: the area that moves ≥ kVisibleShift px under a kDragPixels
/// drag of one control (Diagnostics::drag), mean and largest over the controls, and the deepest
/// weight at those points. localityText ends with it.
std::string dragText(const app::Diagnostics& d, const char* indent);

}  // namespace kc::cli
