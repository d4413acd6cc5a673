#pragma once
// Drawing helpers shared by the canvas overlays (canvas_overlay.cpp, line_overlay.cpp): private to
// kc::ui's sources.
#include <imgui.h>

#include <string>

#include "kc/core/types.h"

namespace kc::ui::overlay {

inline ImVec2 im(const Vec2& v) { return {static_cast<float>(v.x()), static_cast<float>(v.y())}; }
inline ImU32 rgba(int r, int g, int b, int a = 255) { return IM_COL32(r, g, b, a); }

/// A label with a dark box behind it, its top-left corner at `at` (screen pixels): point numbers,
/// line names.
inline void drawTag(ImDrawList* dl, const ImVec2& at, const std::string& text, ImU32 color) {
  if (text.empty()) return;
  const ImVec2 size = ImGui::CalcTextSize(text.c_str());
  dl->AddRectFilled({at.x - 3, at.y - 1}, {at.x + size.x + 3, at.y + size.y + 1}, rgba(20, 20, 28, 210), 3.0f);
  dl->AddText(at, color, text.c_str());
}

}  // namespace kc::ui::overlay
