#pragma once
/// Fixed samples of a sampling: control points, cage edges at a common spacing, and the regular
/// frame of fixed points on the boundary of the sampled domain (thesis 6.2.1, Figs 6.6, 6.9).

#include <array>
#include <vector>

#include <span>

#include "kc/core/cage.h"
#include "kc/core/sizing.h"
#include "kc/core/structure/lines.h"
#include "kc/core/types.h"

namespace kc::sampling {

/// Axis-aligned rectangle [x0, x1] × [y0, y1] (pixels).
struct Rect {
  double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;

  double width() const { return x1 - x0; }
  double height() const { return y1 - y0; }
  double area() const { return width() * height(); }
  bool contains(const Vec2& p) const { return p.x() >= x0 && p.x() <= x1 && p.y() >= y0 && p.y() <= y1; }
  /// Distance from p (inside) to the nearest side; negative outside.
  double insideDistance(const Vec2& p) const;
};

/// Number of equal pieces an edge of length `length` is split into for spacing h:
/// max(1, round(length / h)), so the period on every edge is within a factor ~1.5 of h.
Index edgePieces(double length, double h);

/// Control points (samples 0..m−1, thesis 3.18) followed by every cage edge sampled at a
/// common spacing ≈ h (kind Edge, `edge` row = the edge's control indices). The edge's ends are
/// the controls themselves and are not repeated.
SampleSet boundarySamples(const Cage& cage, double h);
/// The same at the local spacing of `sizing` (segmentDivision of every edge).
SampleSet boundarySamples(const Cage& cage, const SizingField& sizing);

/// Regular points on the boundary of `domain`, spacing ≈ h on each side, corners included,
/// counter-clockwise from (x0, y0). #F×2.
Points framePoints(const Rect& domain, double h);
/// The same at the local spacing of `sizing` along each side.
Points framePoints(const Rect& domain, const SizingField& sizing);

/// Appends the rows of P to S with kind `kind` and edge (−1, −1).
void appendSamples(SampleSet& S, const Points& P, SampleKind kind);

/// Appends the samples of every structure line (kind Line, lineSamplePoints at spacing h, ends
/// included) and records their indices in S.lines (thesis 5.3.3).
void appendLineSamples(SampleSet& S, std::span<const StructureLine> lines, double h);
/// The same at the local spacing of `sizing`. Lines that meet (lineContacts: crossing, one ending
/// on another, sharing an end) share one sample there, which both lines' index lists hold; a line
/// end on the cage is the boundary sample there (a control, or the nearest edge sample of that edge
/// moved along it to the end: its weights stay the edge's linear ones).
void appendLineSamples(SampleSet& S, std::span<const StructureLine> lines, const SizingField& sizing);
/// What free samples keep their distance from: the cage's edges and the structure lines, as one
/// edge list (a Cage whose points are the cage's then the lines' ends; for distance queries only,
/// not for inside tests).
Cage obstacleEdges(const Cage& cage, std::span<const StructureLine> lines);
/// Keeps the rows of P whose distance to the cage is at least `minDistance`.
Points dropNearCage(const Cage& cage, const Points& P, double minDistance);
/// Keeps the rows p of P at least fraction · h(p) from the cage (h = `sizing`).
Points dropNearCage(const Cage& cage, const Points& P, const SizingField& sizing, double fraction);

}  // namespace kc::sampling
