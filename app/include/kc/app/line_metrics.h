#pragma once
/// How well a session keeps lines straight and parallel under random translations of its
/// controls (`kcwarp-cli bench --lines`, `stats` and tests/app/lines_test.cpp).

#include <cstdint>
#include <vector>

#include "kc/app/session.h"
#include "kc/core/structure/lines.h"

namespace kc::app {

struct LineFigures {
  double deviation = 0.0;     ///< px: largest distance of a deformed line point from its deformed chord
  double angle = 0.0;         ///< degrees: largest angle between deformed lines of one parallel group
  double unity = 0.0;         ///< max |Σ w − 1| at the evaluated line points
  double reproduction = 0.0;  ///< max |Σ w c − x| (px) there
};

/// Evaluates the session's field at 301 points along each line (rest), then for `trials` random
/// poses translating every control by up to ±maxTranslation px in x and y (seeded) measures
/// translatedLineDeviation per line and the angles within each parallel group (StructureLine::group).
LineFigures measureLines(const Session& session, const std::vector<StructureLine>& lines, int trials,
                         double maxTranslation = 40.0, std::uint64_t seed = 7);

}  // namespace kc::app
