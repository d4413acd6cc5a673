#include "kc/ui/tools/pose_tool.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "kc/ui/app_state.h"
#include "kc/ui/edits.h"

namespace kc::ui {

double screenAngle(const Vec2& d) { return std::atan2(-d.y(), d.x()); }

Index pickPoint(const Points& P, const Vec2& p, double radius) {
  Index best = -1;
  double bestDistance = radius;
  for (Index i = 0; i < P.rows(); ++i) {
    const double d = (P.row(i).transpose() - p).norm();
    if (d <= bestDistance) {
      bestDistance = d;
      best = i;
    }
  }
  return best;
}

namespace {

bool isSelected(const AppState& s, Index i) { return std::find(s.selection.begin(), s.selection.end(), i) != s.selection.end(); }

/// Sets the selection; a new selection forgets a pivot the user moved.
void setSelection(AppState& s, std::vector<Index> selection) {
  if (selection != s.selection) s.pivot.reset();
  s.selection = std::move(selection);
}

}  // namespace

Vec2 selectionPivot(const AppState& state) {
  if (state.pivot) return *state.pivot;
  const Points P = posedControls(state.bound->cage.C, state.pose);
  Vec2 sum = Vec2::Zero();
  int n = 0;
  for (Index i : state.selection)
    if (i >= 0 && i < P.rows()) sum += P.row(i).transpose(), ++n;
  return n > 0 ? Vec2(sum / n) : Vec2::Zero();
}

Pose rotateAbout(const Pose& before, const Points& C, const std::vector<Index>& selection, const Vec2& pivot, double angle) {
  Pose pose = before;
  const Eigen::Matrix2d R = screenRotation(angle);
  for (Index i : selection) {
    HandlePose& h = pose[static_cast<std::size_t>(i)];
    const Vec2 c = C.row(i).transpose();
    h.translate = R * (c + h.translate - pivot) + pivot - c;
    h.rotate += angle;
  }
  return pose;
}

void PoseTool::press(AppState& state, const PointerEvent& e) {
  if (!state.bound || m_mode != Mode::None) return;
  const Points P = posedControls(state.bound->cage.C, state.pose);
  const Index hit = pickPoint(P, e.position, e.pickRadius);
  m_start = m_current = e.position;
  m_before = state.pose;
  m_pivot = hit;
  m_additive = e.shift;
  if (state.selection.size() >= 2 && e.button == MouseButton::Left && !e.shift &&
      (selectionPivot(state) - e.position).norm() <= e.pickRadius) {  // the pivot marker wins over a point under it
    m_mode = Mode::MovePivot;
    return;
  }
  if (hit < 0 || (e.button == MouseButton::Right && state.selection.size() >= 2 && isSelected(state, hit))) {
    // A right-drag turns a multi-selection wherever it starts (off its points too).
    if (e.button == MouseButton::Left) {
      m_mode = Mode::Select;
    } else if (e.button == MouseButton::Right && state.selection.size() >= 2) {
      if (hit >= 0) state.activeControl = hit;
      m_mode = Mode::RotateGroup;
      m_groupPivot = selectionPivot(state);
      m_angleSet = false;
      m_angle = 0.0;
    }
    return;
  }
  if (e.shift && e.button == MouseButton::Left) {  // toggle membership, no drag
    std::vector<Index> selection = state.selection;
    auto it = std::find(selection.begin(), selection.end(), hit);
    if (it == selection.end()) selection.push_back(hit);
    else selection.erase(it);
    setSelection(state, std::move(selection));
    if (!state.selection.empty()) state.activeControl = state.selection.back();
    return;
  }
  if (!isSelected(state, hit)) setSelection(state, {hit});
  state.activeControl = hit;
  if (e.button == MouseButton::Left) {
    m_mode = Mode::Move;
  } else if (e.button == MouseButton::Right) {
    m_mode = Mode::Rotate;
    m_angle = 0.0;
    m_angleSet = (e.position - P.row(hit).transpose()).norm() >= e.pickRadius;
    m_startAngle = screenAngle(e.position - P.row(hit).transpose());
  }
}

void PoseTool::drag(AppState& state, const PointerEvent& e) {
  m_current = e.position;
  if (m_mode == Mode::MovePivot) {
    state.pivot = e.position;
    return;
  }
  if (m_mode == Mode::RotateGroup) {
    if (m_before.size() != static_cast<std::size_t>(state.bound->cage.size())) return;
    if ((e.position - m_groupPivot).norm() < e.pickRadius) return;
    if (!m_angleSet) {  // the reference direction: from the pivot to where the turn starts
      m_angleSet = true;
      m_startAngle = screenAngle(m_start - m_groupPivot);
    }
    m_angle = std::remainder(screenAngle(e.position - m_groupPivot) - m_startAngle, 2.0 * std::numbers::pi);
    setPose(state, rotateAbout(m_before, state.bound->cage.C, state.selection, m_groupPivot, m_angle));
    return;
  }
  if (m_mode == Mode::Move || m_mode == Mode::Rotate) {
    if (m_before.size() != static_cast<std::size_t>(state.bound->cage.size())) return;
    Pose pose = m_before;
    if (m_mode == Mode::Move) {
      const Vec2 delta = e.position - m_start;
      for (Index i : state.selection) pose[static_cast<std::size_t>(i)].translate += delta;
    } else {
      const Vec2 pivot = state.bound->cage.C.row(m_pivot).transpose() + m_before[static_cast<std::size_t>(m_pivot)].translate;
      // The reference direction is set once the mouse is a pick radius away from the pivot, so a
      // press right on the point does not jump.
      if ((e.position - pivot).norm() < e.pickRadius) return;
      if (!m_angleSet) {
        m_angleSet = true;
        m_startAngle = screenAngle(e.position - pivot);
      }
      m_angle = std::remainder(screenAngle(e.position - pivot) - m_startAngle, 2.0 * std::numbers::pi);
      for (Index i : state.selection) pose[static_cast<std::size_t>(i)].rotate += m_angle;
    }
    setPose(state, std::move(pose));
  }
}

void PoseTool::release(AppState& state, const PointerEvent& e) {
  drag(state, e);
  if (m_mode == Mode::Select) {
    const Points P = posedControls(state.bound->cage.C, state.pose);
    const Vec2 lo = m_start.cwiseMin(m_current), hi = m_start.cwiseMax(m_current);
    std::vector<Index> selection = m_additive ? state.selection : std::vector<Index>{};
    for (Index i = 0; i < P.rows(); ++i) {
      const Vec2 p = P.row(i).transpose();
      if ((p.array() >= lo.array()).all() && (p.array() <= hi.array()).all() &&
          std::find(selection.begin(), selection.end(), i) == selection.end())
        selection.push_back(i);
    }
    setSelection(state, std::move(selection));
    if (!state.selection.empty()) state.activeControl = state.selection.back();
  } else if (m_mode == Mode::Move || m_mode == Mode::Rotate || m_mode == Mode::RotateGroup) {
    commitPose(state, m_before, m_mode == Mode::Move ? "move control" : m_mode == Mode::Rotate ? "rotate control" : "rotate selection");
  }
  m_mode = Mode::None;
}

void PoseTool::cancel(AppState& state) {
  if (m_mode == Mode::Move || m_mode == Mode::Rotate || m_mode == Mode::RotateGroup) setPose(state, m_before);
  m_mode = Mode::None;
}

}  // namespace kc::ui
