// End to end, binding again keeps the person's work: kcwarp in a real window under Xvfb, driven by
// xdotool — a pose and a paint stroke, then Ctrl+B: the question names the stroke, the bind keeps
// the pose, and one Ctrl+Z brings back the previous weights (with the stroke) and the pose.
#include "gui_session.h"

namespace kc::test {
namespace {

TEST_F(GuiSession, RebindKeepsThePoseAsksAboutTheStrokeAndOneUndoRestoresTheBind) {
  const std::string images = std::string(KC_SOURCE_DIR) + "/images/";
  startApp({images + "checker.png", "--cage", images + "checker.cage.json", "--spacing", "16"});
  json s = waitFor([](const json& j) { return j.value("bound", false) && !j.value("busy", true); }, 60);
  ASSERT_TRUE(s.value("bound", false));
  const int wx = s["window"][0], wy = s["window"][1];

  // A pose: control point 1 dragged.
  const double cx = s["controls"][1][0].get<double>() + wx, cy = s["controls"][1][1].get<double>() + wy;
  drag(cx, cy, cx - 60, cy + 40, 1);
  s = waitFor([](const json& j) { return j.value("undo", 0) == 1 && j.value("idle", false); });
  const json pose = s["pose_translate"];
  ASSERT_GT(std::abs(pose[1][0].get<double>()), 10.0);

  // A paint stroke for control 1.
  s = paintCheckerStroke(2);
  const double painted = s["weights_fingerprint"];

  // Bind again (Ctrl+B): the question names the stroke; nothing changes before the answer.
  xdo("mousemove 500 500");
  key("ctrl+b");
  s = waitFor([](const json& j) { return j.value("prompt", "") == "Bind again"; }, 10);
  EXPECT_NE(s.value("question", "").find("paint w1"), std::string::npos) << s.value("question", "");
  EXPECT_EQ(s["weights_fingerprint"].get<double>(), painted);
  screenshot("01-question.png");
  s = waitFor([](const json& j) { return j["widgets"].contains("Bind again"); }, 10);
  click(s["widgets"]["Bind again"][0].get<double>() + wx, s["widgets"]["Bind again"][1].get<double>() + wy);
  s = waitFor([](const json& j) { return j.value("undo", 0) == 3 && j.value("prompt", "x").empty() && !j.value("busy", true); }, 60);
  EXPECT_EQ(s["pose_translate"], pose) << "the pose is kept";
  EXPECT_NE(s["weights_fingerprint"].get<double>(), painted) << "new weights, without the stroke";

  // One Ctrl+Z: the previous bind, its weights with the stroke, and the pose.
  key("ctrl+z");
  s = waitFor([](const json& j) { return j.value("undo", 0) == 2 && !j.value("busy", true); }, 20);
  EXPECT_EQ(s["weights_fingerprint"].get<double>(), painted);
  EXPECT_EQ(s["pose_translate"], pose);
  EXPECT_EQ(s["redo"], 1);
  keepShots("rebind-", {"01-question.png"});
}

}  // namespace
}  // namespace kc::test
