#pragma once
/// Shared value types of kcwarp's numerics. Matrices hold one row per element.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "kc/core/names.h"

namespace kc {

using Index = Eigen::Index;
using Vec2 = Eigen::Vector2d;

/// #P×2 points, one (x, y) row per point, pixel coordinates (x right, y down).
using Points = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;

/// Triangles of a mesh: three vertex indices per triangle.
using Triangles = std::vector<std::array<int, 3>>;

/// Dense row-major matrix: one row per sample / point. Weights W are #S×m.
using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using Weights = RowMatrix;

/// 2×3 affine map [A | t] acting on (x, y, 1).
using Affine2 = Eigen::Matrix<double, 2, 3>;

/// What a sample is (ARCHITECTURE.md, file formats). Controls are samples 0..m-1 (thesis 3.18).
enum class SampleKind : std::uint8_t { Control, Edge, Line, Interior, Exterior };

template <>
struct EnumNames<SampleKind> {
  static constexpr std::array<std::pair<SampleKind, std::string_view>, 5> table{
      {{SampleKind::Control, "control"},
       {SampleKind::Edge, "edge"},
       {SampleKind::Line, "line"},
       {SampleKind::Interior, "interior"},
       {SampleKind::Exterior, "exterior"}}};
};

/// The sample set handed to core: positions, kinds, and for edge samples the cage edge they lie on.
struct SampleSet {
  Points X;                       ///< #S×2 positions; rows 0..m-1 are the control points.
  std::vector<SampleKind> kind;   ///< #S kinds.
  /// #S×2: for Edge samples the control indices (k, l) of the edge's ends; (-1, -1) otherwise.
  Eigen::Matrix<int, Eigen::Dynamic, 2, Eigen::RowMajor> edge;
  /// Structure lines (5.3): each line's samples from a to b (kind Line, an end on the cage its edge
  /// sample; lines that meet share one), empty without lines.
  std::vector<std::vector<Index>> lines;

  Index size() const { return X.rows(); }
  /// Throws std::invalid_argument when shapes disagree, kinds/edges are inconsistent or X is not finite.
  void validate(Index m) const;
};

}  // namespace kc
