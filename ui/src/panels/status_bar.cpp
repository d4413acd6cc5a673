#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "kc/app/errors.h"
#include "kc/ui/edits.h"
#include "kc/ui/panels/panels.h"
#include "kc/ui/panels/widgets.h"

namespace kc::ui {
namespace {

/// A message as drawn: one line of at most kMaxMessageBytes whatever was stored in the state
/// (the banner wraps it; the status bar shows what fits on its line).
std::string shown(const std::string& text) { return app::oneLine(text, kMaxMessageBytes); }

/// `text` cut to `maxWidth` pixels of the current font, "..." marking the cut.
std::string fitted(const std::string& text, float maxWidth) {
  if (ImGui::CalcTextSize(text.c_str()).x <= maxWidth) return text;
  const char* end = text.c_str();
  ImGui::GetFont()->CalcTextSizeA(ImGui::GetFontSize(), std::max(0.0f, maxWidth - ImGui::CalcTextSize("...").x), 0.0f, text.c_str(),
                                  text.c_str() + text.size(), &end);
  return std::string(text.c_str(), end) + "...";
}

/// Errors stay on the canvas until dismissed, wrapped at 40 font sizes.
void errorBanner(AppState& state) {
  std::size_t index = state.messages.size();
  for (std::size_t k = state.messages.size(); k-- > 0;)
    if (state.messages[k].error) {
      index = k;
      break;
    }
  if (index == state.messages.size()) return;
  const View& v = state.view;
  ImGui::SetNextWindowPos(ImVec2(static_cast<float>(v.canvasMin.x() + 0.5 * v.canvasSize.x()), static_cast<float>(v.canvasMin.y() + 48)),
                          ImGuiCond_Always, ImVec2(0.5f, 0.0f));
  ImGui::SetNextWindowBgAlpha(0.92f);
  ImGui::PushStyleColor(ImGuiCol_WindowBg, ImVec4(0.35f, 0.06f, 0.08f, 1.0f));
  ImGui::Begin("##error", nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings |
                   ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoMove);
  ImGui::PushTextWrapPos(ImGui::GetFontSize() * 40.0f);
  ImGui::TextUnformatted(shown(state.messages[index].text).c_str());
  ImGui::PopTextWrapPos();
  if (button(state, "Dismiss", "Hide this message.")) state.messages.erase(state.messages.begin() + static_cast<long>(index));
  ImGui::End();
  ImGui::PopStyleColor();
}

}  // namespace

void drawStatusBar(AppState& state, float y, float width, float height) {
  errorBanner(state);
  ImGui::SetNextWindowPos(ImVec2(0, y));
  ImGui::SetNextWindowSize(ImVec2(width, height));
  ImGui::Begin("##status", nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoSavedSettings |
                   ImGuiWindowFlags_NoBringToFrontOnFocus);
  if (state.worker.busy()) {
    const std::string stage = state.worker.stage();
    const std::string label = state.worker.name() + (stage.empty() ? "" : ": " + stage);
    ImGui::ProgressBar(static_cast<float>(state.worker.fraction()), ImVec2(260, 0), label.c_str());
    ImGui::SameLine();
    if (state.worker.cancelRequested()) ImGui::TextDisabled("cancelling...");
    else if (ImGui::SmallButton("Cancel##job")) state.worker.cancel();
    tooltip("Stop this job; nothing you made is lost.");
    markWidget(state, "Cancel##job");
    ImGui::SameLine();
  }
  char right[160];
  std::snprintf(right, sizeof right, "%.0f%%   x %.0f  y %.0f   %.1f ms/frame", state.view.zoom * 100.0, state.mouseImage.x(),
                state.mouseImage.y(), state.timings.frameMs);
  if (!state.messages.empty()) {
    const Message& m = state.messages.back();
    // What fits between the progress bar and the solver warnings and zoom on the right.
    const float reserved = ImGui::CalcTextSize(right).x + 40.0f + ImGui::CalcTextSize("solver: 99 warnings").x +
                           (m.offersUndo ? ImGui::CalcTextSize("Undo").x + 20.0f : 0.0f);
    const std::string text = fitted(shown(m.text), width - ImGui::GetCursorPosX() - reserved);
    if (m.error) ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.45f, 1.0f), "%s", text.c_str());
    else if (m.offersUndo) ImGui::TextColored(ImVec4(1.0f, 0.8f, 0.3f, 1.0f), "%s", text.c_str());
    else ImGui::TextUnformatted(text.c_str());
    if (m.offersUndo && state.undo.canUndo() && !state.worker.busy()) {
      ImGui::SameLine();
      if (ImGui::SmallButton("Undo##fold")) undo(state);
      tooltip("Undo the change that folded the picture (Ctrl+Z).");
      markWidget(state, "Undo##fold");
    }
  }
  if (state.bound && state.bound->report.anyProblem()) {
    // Solver outcomes that fell back stay visible while the session is open (details: diagnostics panel).
    const std::vector<std::string> problems = state.bound->report.problems();
    ImGui::SameLine();
    ImGui::TextColored(ImVec4(1.0f, 0.75f, 0.2f, 1.0f), "solver: %zu warning%s", problems.size(), problems.size() == 1 ? "" : "s");
    if (ImGui::IsItemHovered()) {
      std::string all;
      for (const std::string& p : problems) all += (all.empty() ? "" : "\n") + p;
      ImGui::SetTooltip("%s", all.c_str());
    }
    markWidget(state, "solver_warnings");
  }
  const float w = ImGui::CalcTextSize(right).x;
  ImGui::SameLine(std::max(ImGui::GetCursorPosX() + 20.0f, width - w - 16.0f));
  ImGui::TextDisabled("%s", right);
  ImGui::End();
}

}  // namespace kc::ui
