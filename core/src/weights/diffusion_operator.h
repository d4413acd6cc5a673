#pragma once
// Private to kc::core's initial weights (heat_diffusion.cpp): the diffusion operator over the
// samples, which heat cannot use to cross the cage, and the samples it connects to fixed ones.

#include <cstdint>
#include <vector>

#include "kc/core/cage.h"
#include "kc/core/kernel/kernel_matrix.h"
#include "kc/core/types.h"

namespace kc::detail {

/// #S×#S: K without the pairs whose segment crosses the cage, directed so heat never goes from
/// the outside back in (inside and on-cage rows take heat only through segments inside or along
/// the cage; exterior rows from exterior and on-cage samples). See diffusion_operator.cpp.
SparseRowMatrix diffusionOperator(const SampleSet& S, const Cage& cage, const SparseMatrix& K);

/// Whether each sample in `unknown` reaches a known sample (isUnknown[j] == 0) through R's rows
/// (length #S, 1 = reachable).
std::vector<char> reachableFromKnown(const SparseRowMatrix& R, const std::vector<Index>& unknown,
                                     const std::vector<char>& isUnknown);

/// Where a sample kind lies relative to a closed cage (an open cage has one region, Inside): the
/// diffusion fills Inside and Boundary first, then Outside from the Boundary.
enum class Region : std::uint8_t { Inside, Boundary, Outside };
Region regionOf(SampleKind kind, bool closed);

}  // namespace kc::detail
