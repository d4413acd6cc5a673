#pragma once
// Private to kc::app: the session file's `field` and `reports` blocks (ARCHITECTURE.md, Session).

#include "json_util.h"
#include "kc/app/session.h"

namespace kc::app::detail {

/// {"kind": "kernel", "nodes": "samples", "sigma", "spacing", "interp"} for a KernelField (rebuilt
/// from the samples and weights.optimized), {"kind": "mesh", "vertices", "triangles", "weights"}
/// for a MeshField (self-contained). Null json when the session has no field.
json fieldToJson(const Session& s);
/// Reads the field block into s: a mesh block builds s.field (returns true); a kernel block is
/// checked against s.params and σ (returns false: the backend rebuilds it). InputError naming the
/// bad entry otherwise.
bool fieldFromJson(const json& block, Session& s, const std::string& where);

json reportsToJson(const SolverReports& r);
/// Missing entries keep their defaults (older files have no reports block).
SolverReports reportsFromJson(const json& block);

/// One row per sample, one column per control point.
json weightsToJson(const Weights& W);
/// rows → n×m, InputError naming `field` (e.g. "weights.initial[3][1]") when malformed.
Weights parseWeights(const json& rows, Index n, Index m, const std::string& where, const std::string& field);

}  // namespace kc::app::detail
