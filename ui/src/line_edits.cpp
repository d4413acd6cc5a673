#include "kc/ui/line_edits.h"

#include <algorithm>
#include <regex>
#include <stdexcept>

#include "kc/app/pipeline.h"
#include "kc/core/structure/lines.h"
#include "kc/ui/edits.h"
#include "kc/ui/jobs.h"

namespace kc::ui {

int pickLine(const app::Structure& lines, const Vec2& p, double radius) {
  int best = -1;
  double bestDistance = radius;
  for (std::size_t k = 0; k < lines.lines.size(); ++k) {
    const double d = pointSegmentDistance(p, lines.lines[k].a, lines.lines[k].b);
    if (d <= bestDistance) bestDistance = d, best = static_cast<int>(k);
  }
  return best;
}

std::string linesProblem(const AppState& state, const app::Structure& lines) {
  if (lines.empty()) return {};
  if (!shownCapabilities(state).lines)
    return "lines are kept straight by KC weights only (choose KC in the Bind panel)";
  if (!state.cageValid) return "the cage must be closed and valid first (" + state.cageStatus + ")";
  const app::BindParams params = bindParamsFor(state, state.cage, state.source.width, state.source.height);
  try {
    // The check of kcwarp-cli bind --structure: a graded bind takes lines that cross, meet, run
    // close to the cage or end on it; a uniform one (--uniform-spacing) keeps them a spacing apart.
    validateLines(state.cage, lines.lines, params.spacing, app::gradedSampling(params) || app::exactLines(params));
  } catch (const std::invalid_argument& e) {
    return std::regex_replace(e.what(), std::regex(R"(lines\[(\d+)\])"), "line $1");
  }
  return {};
}

bool applyLines(AppState& state, const app::Structure& lines) {
  if (state.bound && state.worker.busy()) return false;
  state.lines = lines;
  state.lineSelection.erase(std::remove_if(state.lineSelection.begin(), state.lineSelection.end(),
                                           [&](int k) { return k >= static_cast<int>(lines.lines.size()); }),
                            state.lineSelection.end());
  if (state.bound) return startBind(state, true, /*keepPoseAndHistory=*/true);
  return true;
}

bool editLines(AppState& state, app::Structure lines, std::string label) {
  if (state.bound && state.worker.busy()) {
    postMessage(state, "Busy: change the lines after the current job has finished.", false);
    return false;
  }
  const std::string problem = linesProblem(state, lines);
  if (!problem.empty()) {
    postMessage(state, "Line refused: " + problem + ".", true);
    return false;
  }
  const app::Structure before = state.lines;
  state.undo.push({std::move(label), LinesEdit{before, lines}});
  if (!applyLines(state, lines)) {  // the bind could not start (its message says why): nothing changed
    state.lines = before;
    state.undo.popUndo();
    return false;
  }
  state.unsaved = true;
  return true;
}

int tidyGroups(app::Structure& s) {
  std::vector<int> count(s.groups.size(), 0);
  for (const StructureLine& l : s.lines)
    if (l.group >= 0) ++count[static_cast<std::size_t>(l.group)];
  int ungrouped = 0;
  std::vector<int> renumber(s.groups.size(), -1);
  std::vector<std::string> names;
  for (std::size_t g = 0; g < s.groups.size(); ++g)
    if (count[g] >= 2) renumber[g] = static_cast<int>(names.size()), names.push_back(s.groups[g]);
  for (StructureLine& l : s.lines)
    if (l.group >= 0) {
      if (renumber[static_cast<std::size_t>(l.group)] < 0) ++ungrouped;
      l.group = renumber[static_cast<std::size_t>(l.group)];
    }
  s.groups = std::move(names);
  return ungrouped;
}

bool sameLines(const app::Structure& a, const app::Structure& b) {
  if (a.lines.size() != b.lines.size() || a.groups != b.groups) return false;
  for (std::size_t k = 0; k < a.lines.size(); ++k)
    if (a.lines[k].a != b.lines[k].a || a.lines[k].b != b.lines[k].b || a.lines[k].group != b.lines[k].group) return false;
  return true;
}

namespace {

bool selected(const AppState& state, std::size_t k) {
  return std::find(state.lineSelection.begin(), state.lineSelection.end(), static_cast<int>(k)) != state.lineSelection.end();
}

}  // namespace

bool groupSelectedLines(AppState& state, const std::string& name) {
  if (name.empty()) {
    postMessage(state, "Give the parallel group a name.", false);
    return false;
  }
  app::Structure after = state.lines;
  auto it = std::find(after.groups.begin(), after.groups.end(), name);
  const int g = static_cast<int>(it - after.groups.begin());
  if (it == after.groups.end()) after.groups.push_back(name);
  for (std::size_t k = 0; k < after.lines.size(); ++k)
    if (selected(state, k)) after.lines[k].group = g;
  tidyGroups(after);
  if (std::find(after.groups.begin(), after.groups.end(), name) == after.groups.end()) {
    postMessage(state, "Select at least two lines to make them parallel.", false);
    return false;
  }
  return editLines(state, std::move(after), "make lines parallel (" + name + ")");
}

bool ungroupSelectedLines(AppState& state) {
  app::Structure after = state.lines;
  for (std::size_t k = 0; k < after.lines.size(); ++k)
    if (selected(state, k)) after.lines[k].group = -1;
  tidyGroups(after);
  if (sameLines(after, state.lines)) return false;
  return editLines(state, std::move(after), "lines not parallel");
}

bool deleteSelectedLines(AppState& state) {
  app::Structure after;
  after.groups = state.lines.groups;
  for (std::size_t k = 0; k < state.lines.lines.size(); ++k)
    if (!selected(state, k)) after.lines.push_back(state.lines.lines[k]);
  if (after.lines.size() == state.lines.lines.size()) return false;
  const int dissolved = tidyGroups(after);
  const std::size_t n = state.lines.lines.size() - after.lines.size();
  if (!editLines(state, std::move(after), n == 1 ? "delete line" : "delete lines")) return false;
  state.lineSelection.clear();
  if (dissolved > 0) postMessage(state, "A parallel group was left with one line: that line is no longer grouped.", false);
  return true;
}

}  // namespace kc::ui
