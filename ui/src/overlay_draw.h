#pragma once
// Drawing helpers shared by the canvas overlays (canvas_overlay.cpp, line_overlay.cpp): private to
// kc::ui's sources.
#include <imgui.h>

#include <string>
#include <vector>

#include "kc/core/types.h"
#include "kc/ui/canvas.h"

namespace kc::ui::overlay {

inline ImVec2 im(const Vec2& v) { return {static_cast<float>(v.x()), static_cast<float>(v.y())}; }
inline ImU32 rgba(int r, int g, int b, int a = 255) { return IM_COL32(r, g, b, a); }

/// A label with a dark box behind it (kTagPad px beyond the text), the text's top-left corner at
/// `at` (screen pixels), `size` the text's (ImGui::CalcTextSize): point numbers, line names.
inline constexpr float kTagPad[2] = {3.0f, 1.0f};
inline void drawTag(ImDrawList* dl, const ImVec2& at, const std::string& text, ImU32 color, const ImVec2& size) {
  if (text.empty()) return;
  dl->AddRectFilled({at.x - kTagPad[0], at.y - kTagPad[1]}, {at.x + size.x + kTagPad[0], at.y + size.y + kTagPad[1]},
                    rgba(20, 20, 28, 210), 3.0f);
  dl->AddText(at, color, text.c_str());
}

/// A tag to draw: its text's preferred top-left corner (screen pixels), text and colour.
struct Tag {
  ImVec2 at;
  std::string text;
  ImU32 color;
};

/// Draws the tags, each at its place unless its box would cover an earlier one's (tagPlaces).
inline void drawTags(ImDrawList* dl, const std::vector<Tag>& tags) {
  Points at(Index(tags.size()), 2), size(Index(tags.size()), 2);
  std::vector<ImVec2> text(tags.size(), ImVec2(0, 0));
  for (std::size_t k = 0; k < tags.size(); ++k) {
    if (!tags[k].text.empty()) text[k] = ImGui::CalcTextSize(tags[k].text.c_str());
    at.row(Index(k)) << tags[k].at.x - kTagPad[0], tags[k].at.y - kTagPad[1];
    size.row(Index(k)) << (tags[k].text.empty() ? 0.0 : text[k].x + 2 * kTagPad[0]), text[k].y + 2 * kTagPad[1];
  }
  const Points place = tagPlaces(at, size);
  for (std::size_t k = 0; k < tags.size(); ++k)
    drawTag(dl, ImVec2(float(place(Index(k), 0)) + kTagPad[0], float(place(Index(k), 1)) + kTagPad[1]), tags[k].text, tags[k].color,
            text[k]);
}

}  // namespace kc::ui::overlay
