#pragma once
/// Private: cage edges bucketed in a uniform grid, so "how far is the cage from this point" and
/// "does this short move come too close to the cage" cost O(1) per query instead of O(m).

#include <array>
#include <vector>

#include "kc/core/cage.h"
#include "kc/core/types.h"

namespace kc::sampling::detail {

class CageLocator {
 public:
  /// cell: bucket size, about the query radius (e.g. the spacing h).
  CageLocator(const Cage& cage, double cell);

  /// Distance from x to the nearest cage edge when it is below maxDistance, else maxDistance.
  double distance(const Vec2& x, double maxDistance) const;
  /// True when every point of segment a–b is at least `clearance` away from every cage edge.
  bool segmentClear(const Vec2& a, const Vec2& b, double clearance) const;

 private:
  template <class F>
  void forEachEdgeNear(double xmin, double ymin, double xmax, double ymax, F&& f) const;
  int cellX(double x) const;
  int cellY(double y) const;

  std::vector<std::array<Vec2, 2>> m_seg;  // edge end points
  double m_cell = 1.0, m_x0 = 0.0, m_y0 = 0.0;
  int m_nx = 0, m_ny = 0;
  std::vector<int> m_start;  // cell → first slot in m_items (size cells + 1)
  std::vector<int> m_items;  // edge indices per cell
};

}  // namespace kc::sampling::detail
