#pragma once
// Private to kc::app: the session file's `field` and `reports` blocks (ARCHITECTURE.md, Session).

#include "json_util.h"
#include "kc/app/file_io.h"
#include "kc/app/backend.h"
#include "kc/app/session.h"

namespace kc::app::detail {

/// {"kind": "kernel", "nodes": "samples", "sigma", "spacing", "interp", "coefficients_b64"} for a
/// KernelField (coefficients [B; U], (3+#S)×m, in the compact form only; without them rebuilt from
/// the samples and weights.optimized), {"kind": "mesh", "vertices", "triangles", "weights"} for a
/// MeshField (self-contained), a registered codec's block for other kinds (registerFieldCodec).
/// Null json when the session has no field or its kind has no codec.
json fieldToJson(const Session& s, WeightsForm form);
/// Reads the field block into s: a mesh block builds s.field (returns true); a kernel block is
/// checked against s.params and σ, and its coefficients, when stored, restore s.field without a
/// factorization (returns false: the backend checks them against the weights or rebuilds the
/// field). Needs s.samples, s.W and s.params read. InputError naming the bad entry otherwise.
bool fieldFromJson(const json& block, Session& s, const std::string& where);
/// The registered field codecs (the built-in "mesh" and "kernel" first), and the one of `kind` (null: none).
std::vector<FieldCodec>& fieldCodecs();
const FieldCodec* codecFor(std::string_view kind);

/// Partition of unity and linear reproduction of the weights W (#S×m) of samples X (#S×2) over
/// control points C (m×2), row by row: |Σ_k W(i,k) − 1| ≤ kUnityTolerance and
/// ‖Σ_k W(i,k)·C_k − X_i‖ ≤ kReproductionTolerance·(1 + max ‖C_k‖∞) (docs/ARCHITECTURE.md,
/// "File formats"). InputError naming `field`, the row and the check otherwise.
void checkWeightRows(const Weights& W, const Points& X, const Points& C, const std::string& where, const std::string& field);
/// Sessions kcwarp writes stay below 5e-13 in both (every backend, method, init and structure of
/// the bundled examples); the tolerances leave three orders of magnitude.
inline constexpr double kUnityTolerance = 1e-9;
inline constexpr double kReproductionTolerance = 1e-9;

/// The session's `reports` block: the stages a user must see, and the backend's own report under
/// reports.<its parameter block>.
json reportsToJson(const BindReport& r, const Backend& backend);
/// Missing entries keep their defaults (older files have no reports block); the backend reads its own.
BindReport reportsFromJson(const json& block, const Backend& backend);

/// One row per sample, one column per control point (the JSON form older files use).
json weightsToJson(const Weights& W);
/// rows → n×m, InputError naming `field` (e.g. "weights.initial[3][1]") when malformed.
Weights parseWeights(const json& rows, Index n, Index m, const std::string& where, const std::string& field);

/// The compact form of an n×m weight matrix: {"shape": [n, m], "dtype": "f64le", "base64": B}
/// where B is the base64 of the n·m doubles row by row (W(0,0), W(0,1), …), each 8 bytes of
/// little-endian IEEE 754. Reading it back gives the same bits.
json weightsToCompactJson(const Weights& W);
/// Writes W into `block`: under `key` + "_b64" in the compact form, or under `key` as rows.
void putWeights(json& block, const std::string& key, const Weights& W, WeightsForm form);
/// The n×m weights in `block` under `key` + "_b64" (compact) or `key` (rows); exactly one must be
/// there. `field` names the key in messages (e.g. "weights.optimized"). InputError naming the file
/// and key on a shape other than [n, m], base64 that is not canonical or has the wrong length
/// (truncated), or a value that is not finite or exceeds kMaxWeight in magnitude.
Weights getWeights(const json& block, const std::string& key, Index n, Index m, const std::string& where,
                   const std::string& field);

}  // namespace kc::app::detail
