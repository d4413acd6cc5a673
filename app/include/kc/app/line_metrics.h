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

/// Folds of the session's warp inside the cage (the mesh of `kcwarp-cli warp --outside fixed`) over the same
/// random poses as measureLines with the same trials, maxTranslation and seed.
struct FoldFigures {
  int foldedPoses = 0;       ///< poses with at least one flipped triangle (DeformReport::flippedTriangles > 0)
  Index flipped = 0;         ///< flipped triangles, summed over the poses
  double minJacobian = 0.0;  ///< smallest det J over the poses (DeformReport::minJacobian)
};

/// `trials` poses translating every control of an m-point cage by up to ±maxTranslation px in x
/// and y (seeded): m×2 translations each. measureLines and measureFolds draw them.
std::vector<Points> randomTranslations(Index m, int trials, double maxTranslation, std::uint64_t seed);

/// FoldFigures over `trials` poses of randomTranslations; throws std::invalid_argument when the
/// session has no field.
FoldFigures measureFolds(const Session& session, int trials, double maxTranslation = 40.0, std::uint64_t seed = 7);

/// Evaluates the session's field at 301 points along each line (rest), then for `trials` random
/// poses translating every control by up to ±maxTranslation px in x and y (seeded) measures
/// translatedLineDeviation per line and the angles within each parallel group (StructureLine::group).
LineFigures measureLines(const Session& session, const std::vector<StructureLine>& lines, int trials,
                         double maxTranslation = 40.0, std::uint64_t seed = 7);

}  // namespace kc::app
