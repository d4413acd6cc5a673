#pragma once
/// Regular-grid sampling of a cage and its domain (thesis 3.3.1, 6.2.1 "grid sampling").

#include "kc/core/cage.h"
#include "kc/core/types.h"
#include "kc/sampling/boundary.h"

namespace kc::sampling {

/// Controls and edge samples (boundarySamples), then the grid points {(i h, j h)} that lie in
/// `domain`, each labelled Interior or Exterior (insideCage) and dropped when closer than h/2 to
/// the cage. The grid is anchored at the image origin so it does not depend on the margin.
/// Structure `lines` get their samples (appendLineSamples) after the edge samples, and grid
/// points closer than h/2 to a line are dropped too. No input checks: `sample` validates.
SampleSet gridSample(const Cage& cage, const Rect& domain, double h, std::span<const StructureLine> lines = {});

/// Number of grid points of `domain` at spacing h (before dropping those near the cage).
double gridPointCount(const Rect& domain, double h);

}  // namespace kc::sampling
