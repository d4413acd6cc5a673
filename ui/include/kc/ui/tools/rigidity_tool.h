#pragma once
/// Rigidity brush (thesis 5.4, docs/rigidity.md): paints the per-sample rigidity ρ ∈ [0, 1] of a
/// bound kernel session — the parts of the picture that should keep their shape. A stroke works on
/// a copy of ρ (the tinted overlay shows it while painting); on release app::setRigidity re-solves
/// only around the painted region on the worker (startRigidity, rigidity_edits.h), one undo entry
/// per stroke. Erase (the panel's mode, or Ctrl) takes ρ away.

#include <vector>

#include "kc/core/types.h"
#include "kc/ui/tools/pointer.h"

namespace kc::ui {

struct AppState;

/// Falloff of the rigidity brush at `distance` from its centre, with `softness` s ∈ [0, 1]:
/// 1 inside the hard core d ≤ (1 − s)·r, then (1 − t²)² with t = (d − (1 − s)r) / (s·r) out to r,
/// 0 beyond. s = 1 is the weight brush's falloff (1 − (d/r)²)²; s = 0 a hard disc.
double rigidityFalloff(double distance, double radius, double softness);

/// One dab of a stroke: every paintable sample (interior or line — control, cage-edge and exterior
/// samples are not painted, a rigid region lies inside the cage) within `radius` of `centre`
/// raises its coverage c_s to max(c_s, f) (f = rigidityFalloff), and its ρ becomes, from its value
/// ρ0_s when the stroke began,
///     paint: ρ_s = max(ρ0_s, strength·c_s)        erase: ρ_s = ρ0_s·(1 − strength·c_s),
/// so a stroke paints a soft-edged band whose profile does not depend on how many dabs overlap.
/// Values below 1e-3 become 0 (an erased region ends, a faint rim does not widen the re-solved zone)
/// and a painted value below 1e-3 leaves ρ0. `rho0`, `cover`, `rho` have #S entries (cover and rho
/// are sized and filled from rho0 when empty). Returns the number of samples under the dab.
Index paintRigidityDab(const std::vector<double>& rho0, std::vector<double>& cover, std::vector<double>& rho,
                       const SampleSet& samples, const Vec2& centre, double radius, double softness, double strength,
                       bool erase);

class RigidityTool {
 public:
  void press(AppState& state, const PointerEvent& e);
  void drag(AppState& state, const PointerEvent& e);
  /// Ends the stroke and starts the re-solve around the painted region (when ρ changed).
  void release(AppState& state, const PointerEvent& e);
  /// Abandons a stroke (ρ stays as it was).
  void cancel(AppState& state);

  bool active() const { return m_active; }
  /// ρ while a stroke is painted (#S); empty otherwise (the overlay then shows the session's ρ).
  const std::vector<double>& stroke() const { return m_rho; }

 private:
  void dab(AppState& state, const Vec2& centre);
  void dabsTo(AppState& state, const Vec2& p);
  bool m_active = false;
  bool m_erase = false;
  Vec2 m_last = Vec2::Zero();
  std::vector<double> m_rho0, m_cover, m_rho;
};

}  // namespace kc::ui
