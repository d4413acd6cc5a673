#include "kc/ui/tools/brush_tool.h"

#include <algorithm>
#include <cmath>

#include "kc/ui/app_state.h"
#include "kc/ui/edits.h"
#include "kc/ui/jobs.h"

namespace kc::ui {

double brushFalloff(double distance, double radius) {
  if (!(radius > 0.0) || distance >= radius) return 0.0;
  const double q = 1.0 - (distance / radius) * (distance / radius);
  return q * q;
}

Index paintDab(Weights& W0, const SampleSet& samples, Index control, const Vec2& centre, double radius, double amount,
               std::vector<char>& painted) {
  if (control < 0 || control >= W0.cols()) return 0;
  if (painted.size() != static_cast<std::size_t>(samples.size())) painted.assign(static_cast<std::size_t>(samples.size()), 0);
  const Index m = W0.cols();
  Index touched = 0;
  for (Index s = 0; s < samples.size(); ++s) {
    const SampleKind kind = samples.kind[static_cast<std::size_t>(s)];
    if (kind == SampleKind::Control || kind == SampleKind::Edge) continue;
    const double f = brushFalloff((samples.X.row(s).transpose() - centre).norm(), radius);
    if (f <= 0.0) continue;
    auto row = W0.row(s);
    const double target = std::clamp(row(control) + amount * f, 0.0, 1.0);
    const double others = row.sum() - row(control);
    const double remaining = 1.0 - target;
    for (Index j = 0; j < m; ++j) {
      if (j == control) continue;
      row(j) = others > 1e-12 ? row(j) * remaining / others : remaining / double(m - 1);
    }
    row(control) = target;
    painted[static_cast<std::size_t>(s)] = 1;
    ++touched;
  }
  return touched;
}

void BrushTool::press(AppState& state, const PointerEvent& e) {
  if (m_active || e.button != MouseButton::Left) return;
  if (!state.session) {
    postMessage(state, state.bound ? "Busy: wait for the current job to finish before painting." : "Bind a cage before painting.", false);
    return;
  }
  if (!state.bound->capabilities.painting) {
    postMessage(state, "This session cannot be painted: " + state.bound->capabilities.why, false);
    return;
  }
  if (state.activeControl < 0 || state.activeControl >= state.session->cage.size()) {
    postMessage(state, "Select a control point to paint its weights (click it with the pose tool).", false);
    return;
  }
  m_active = true;
  m_subtract = state.brush.subtract != e.ctrl;
  m_W0Before = state.session->W0;
  m_painted.assign(static_cast<std::size_t>(state.session->samples.size()), 0);
  m_last = e.position;
  paintDab(state.session->W0, state.session->samples, state.activeControl, e.position, state.brush.radius,
           m_subtract ? -state.brush.strength : state.brush.strength, m_painted);
}

void BrushTool::dabsTo(AppState& state, const Vec2& p) {
  const double amount = m_subtract ? -state.brush.strength : state.brush.strength;
  m_last = dabsAlong(m_last, p, state.brush.radius, [&](const Vec2& c) {
    paintDab(state.session->W0, state.session->samples, state.activeControl, c, state.brush.radius, amount, m_painted);
  });
}

void BrushTool::drag(AppState& state, const PointerEvent& e) {
  if (!m_active || !state.session) return;
  dabsTo(state, e.position);
}

void BrushTool::release(AppState& state, const PointerEvent& e) {
  if (!m_active || !state.session) {
    m_active = false;
    return;
  }
  dabsTo(state, e.position);
  m_active = false;
  WeightEdit edit;
  for (std::size_t s = 0; s < m_painted.size(); ++s)
    if (m_painted[s]) edit.rows.push_back(static_cast<Index>(s));
  if (edit.rows.empty()) return;
  const app::Session& session = *state.session;
  edit.W0Before = gatherRows(m_W0Before, edit.rows);
  edit.W0After = gatherRows(session.W0, edit.rows);  // W's changed rows: found when the re-optimization ends
  edit.methodBefore = edit.methodAfter = state.bound->method;
  m_W0Before.resize(0, 0);
  startReoptimize(state, std::move(edit), "paint w" + std::to_string(state.activeControl));
}

void BrushTool::cancel(AppState& state) {
  if (m_active && state.session && m_W0Before.rows() == state.session->W0.rows()) state.session->W0 = m_W0Before;
  m_active = false;
}

}  // namespace kc::ui
