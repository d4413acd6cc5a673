#include "kc/ui/tools/rigidity_tool.h"

#include <algorithm>
#include <cmath>

#include "kc/ui/app_state.h"
#include "kc/ui/edits.h"
#include "kc/ui/rigidity_edits.h"
#include "kc/ui/tools/brush_tool.h"

namespace kc::ui {
namespace {

/// Below this a ρ is 0 (an erased region ends; a faint painted rim does not widen the re-solved zone).
constexpr double kRhoFloor = 1e-3;

}  // namespace

double rigidityFalloff(double distance, double radius, double softness) {
  if (!(radius > 0.0) || !(distance < radius)) return 0.0;
  const double s = std::clamp(softness, 0.0, 1.0);
  const double core = (1.0 - s) * radius;
  if (distance <= core) return 1.0;
  const double t = (distance - core) / (s * radius);
  const double q = 1.0 - t * t;
  return q * q;
}

Index paintRigidityDab(const std::vector<double>& rho0, std::vector<double>& cover, std::vector<double>& rho,
                       const SampleSet& samples, const Vec2& centre, double radius, double softness, double strength,
                       bool erase) {
  const std::size_t n = static_cast<std::size_t>(samples.size());
  if (rho0.size() != n) return 0;
  if (cover.size() != n) cover.assign(n, 0.0);
  if (rho.size() != n) rho = rho0;
  strength = std::clamp(strength, 0.0, 1.0);
  Index touched = 0;
  for (std::size_t s = 0; s < n; ++s) {
    const SampleKind kind = samples.kind[s];
    if (kind != SampleKind::Interior && kind != SampleKind::Line) continue;
    const double f = rigidityFalloff((samples.X.row(static_cast<Index>(s)).transpose() - centre).norm(), radius, softness);
    if (f <= 0.0) continue;
    ++touched;
    cover[s] = std::max(cover[s], f);
    const double painted = strength * cover[s];
    double r = erase ? rho0[s] * (1.0 - painted) : std::max(rho0[s], painted < kRhoFloor ? 0.0 : painted);
    if (r < kRhoFloor) r = 0.0;
    rho[s] = std::clamp(r, 0.0, 1.0);
  }
  return touched;
}

void RigidityTool::press(AppState& state, const PointerEvent& e) {
  if (m_active || e.button != MouseButton::Left) return;
  const std::string problem = rigidityProblem(state);
  if (!problem.empty()) {
    postMessage(state, "Cannot paint rigidity: " + problem, false);
    return;
  }
  if (!state.session) {
    postMessage(state, "Busy: wait for the current job to finish before painting rigidity.", false);
    return;
  }
  const std::size_t n = static_cast<std::size_t>(state.bound->samples.size());
  m_active = true;
  m_erase = state.rigidBrush.erase != e.ctrl;
  m_rho0 = boundRigidity(state);
  m_rho0.resize(n, 0.0);
  m_cover.assign(n, 0.0);
  m_rho = m_rho0;
  m_last = e.position;
  dab(state, e.position);
}

void RigidityTool::dab(AppState& state, const Vec2& c) {
  paintRigidityDab(m_rho0, m_cover, m_rho, state.bound->samples, c, state.rigidBrush.radius, state.rigidBrush.softness,
                   state.rigidBrush.strength, m_erase);
  state.rigidityVersion.bump();
}

void RigidityTool::dabsTo(AppState& state, const Vec2& p) {
  m_last = dabsAlong(m_last, p, state.rigidBrush.radius, [&](const Vec2& c) { dab(state, c); });
}

void RigidityTool::drag(AppState& state, const PointerEvent& e) {
  if (m_active) dabsTo(state, e.position);
}

void RigidityTool::release(AppState& state, const PointerEvent& e) {
  if (!m_active) return;
  dabsTo(state, e.position);
  if (e.position != m_last) dab(state, e.position);  // the stroke ends where the mouse was released
  m_active = false;
  std::vector<double> after = std::move(m_rho);
  const bool changed = after != m_rho0;
  m_rho.clear();
  m_rho0.clear();
  m_cover.clear();
  state.rigidityVersion.bump();
  if (changed) startRigidity(state, std::move(after), m_erase ? "erase rigidity" : "paint rigidity");
}

void RigidityTool::cancel(AppState& state) {
  if (m_active) state.rigidityVersion.bump();
  m_active = false;
  m_rho.clear();
  m_rho0.clear();
  m_cover.clear();
}

}  // namespace kc::ui
