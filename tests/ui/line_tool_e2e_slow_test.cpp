// End to end: the line tool in a real window under Xvfb, driven with real X input (xdotool), as a
// person uses it. A picture with a straight dark bar; the user draws a line along the bar by two
// clicks (kcwarp re-binds), drags a control point with the pose tool and exports: the bar in the
// exported warp is straight. Deleting the line (right-click) re-binds without it and keeps the
// pose: the same export now shows the bar bent (so the first check can fail). Undo brings it back.
#include <cmath>

#include "gui_session.h"
#include "kc/app/file_io.h"

namespace kc::test {
namespace {

constexpr int kWidth = 320, kHeight = 240;
constexpr double kBarY = 120.0, kBarX0 = 70.0, kBarX1 = 250.0;

/// A light picture with a faint grid and a dark horizontal bar 6 px thick from kBarX0 to kBarX1.
Image barPicture() {
  Image img(kWidth, kHeight, Rgba{235, 235, 240, 255});
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      std::uint8_t* p = img.pixel(x, y);
      if (x % 20 == 0 || y % 20 == 0) p[0] = p[1] = 200, p[2] = 215;
      if (std::abs(y - kBarY) <= 3.0 && x >= kBarX0 && x <= kBarX1) p[0] = p[1] = p[2] = 20;
    }
  return img;
}

/// The bar in a warped picture: for each column, the mean row of its dark pixels (R, G, B < 90);
/// returns the largest distance of these centres from their least-squares line, over the middle
/// 90% of the columns the bar covers (its ends are cut off square by the pixel grid).
double barBend(const Image& img, double* slope = nullptr) {
  std::vector<double> xs, ys;
  for (int x = 0; x < img.width; ++x) {
    double sum = 0.0;
    int n = 0;
    for (int y = 0; y < img.height; ++y) {
      const std::uint8_t* p = const_cast<Image&>(img).pixel(x, y);
      if (p[3] > 0 && p[0] < 90 && p[1] < 90 && p[2] < 90) sum += y, ++n;
    }
    if (n > 0) xs.push_back(x), ys.push_back(sum / n);
  }
  if (xs.size() < 20) return -1.0;
  const std::size_t cut = xs.size() / 20;
  std::vector<double> X(xs.begin() + cut, xs.end() - cut), Y(ys.begin() + cut, ys.end() - cut);
  double mx = 0, my = 0;
  for (std::size_t k = 0; k < X.size(); ++k) mx += X[k], my += Y[k];
  mx /= X.size(), my /= Y.size();
  double sxy = 0, sxx = 0;
  for (std::size_t k = 0; k < X.size(); ++k) sxy += (X[k] - mx) * (Y[k] - my), sxx += (X[k] - mx) * (X[k] - mx);
  const double b = sxy / sxx;
  if (slope) *slope = b;
  double worst = 0.0;
  for (std::size_t k = 0; k < X.size(); ++k) worst = std::max(worst, std::abs(Y[k] - (my + b * (X[k] - mx))) / std::sqrt(1 + b * b));
  return worst;
}

TEST_F(GuiSession, ALineDrawnByClickingStaysStraightWhenAPointIsDragged) {
  const fs::path image = dir / "bar.png", cagePath = dir / "bar.cage.json";
  app::saveImage(image.string(), barPicture());
  Points C(6, 2);
  C << 20, 20, 160, 20, 300, 20, 300, 220, 160, 220, 20, 220;
  app::saveCage(cagePath.string(), Cage::polygon(C));
  startApp({image.string(), "--cage", cagePath.string()});
  json s = waitFor([](const json& j) { return j.value("bound", false) && !j.value("busy", true); }, 90);
  ASSERT_TRUE(s.value("bound", false));
  const int wx = s["window"][0], wy = s["window"][1];
  auto screen = [&](const json& st, double x, double y) { return screenOf(st, Vec2(x, y)); };
  EXPECT_NEAR(barBend(app::loadImage(image.string())), 0.0, 1e-9) << "the picture's bar is straight";

  // 1. Line tool (L); click at both ends of the bar: kcwarp binds again with the line.
  key("l");
  s = waitFor([](const json& j) { return j.value("tool", "") == "lines"; });
  const Vec2 a = screen(s, kBarX0 + 4, kBarY), b = screen(s, kBarX1 - 4, kBarY);
  click(a.x(), a.y());
  click(b.x(), b.y());
  s = waitFor([](const json& j) { return j["lines"].size() == 1 && j.value("bound_lines", 0) == 1 && !j.value("busy", true); }, 90);
  ASSERT_EQ(s["lines"].size(), 1u);
  EXPECT_NEAR(s["lines"][0]["a"][0].get<double>() + wx, a.x(), 2.0);
  EXPECT_NEAR(s["lines"][0]["b"][1].get<double>() + wy, b.y(), 2.0);
  screenshot("01-line-drawn.png");

  // 2. Pose tool (P); drag the top right control point 70 px down and 40 px left (picture pixels):
  // the line's ends move by different amounts, so the bar must tilt and stay straight.
  key("p");
  s = waitFor([](const json& j) { return j.value("tool", "") == "pose"; });
  const double zoom = s["view"]["zoom"];
  const double cx = s["controls"][2][0].get<double>() + wx, cy = s["controls"][2][1].get<double>() + wy;
  const int undoBefore = s["undo"];
  drag(cx, cy, cx - 40 * zoom, cy + 70 * zoom, 1);
  s = waitFor([&](const json& j) { return j.value("undo", 0) == undoBefore + 1 && j.value("idle", false); });
  EXPECT_NEAR(s["pose_translate"][2][1].get<double>(), 70.0, 2.0);
  screenshot("02-posed-with-line.png");

  // 3. Export (Ctrl+E): the bar is straight in the warped picture.
  xdo("mousemove 500 500");
  key("ctrl+e");
  s = waitFor([](const json& j) { return j.value("exports", 0) == 1 && !j.value("busy", true); });
  fs::copy_file(dir / "export.png", dir / "with-line.png", fs::copy_options::overwrite_existing);
  double slope = 0.0;
  const double withLine = barBend(app::loadImage((dir / "with-line.png").string()), &slope);
  std::printf("bar bend with the line: %.3f px (slope %.4f)\n", withLine, slope);
  EXPECT_GE(withLine, 0.0);
  EXPECT_GT(std::abs(slope), 0.02) << "the pose was meant to tilt the bar";
  EXPECT_LT(withLine, 1.0) << "the bar along the line bends in the warped picture";

  // 4. Line tool, right-click the line: it is deleted, kcwarp binds without it, the pose stays.
  key("l");
  s = waitFor([](const json& j) { return j.value("tool", "") == "lines"; });
  const Vec2 mid = screen(s, 0.5 * (kBarX0 + kBarX1), kBarY);
  drag(mid.x(), mid.y(), mid.x(), mid.y(), 3, 0);
  s = waitFor([](const json& j) { return j["lines"].empty() && j.value("bound_lines", 1) == 0 && !j.value("busy", true); }, 90);
  EXPECT_NEAR(s["pose_translate"][2][1].get<double>(), 70.0, 2.0) << "the pose survives the re-bind";
  key("p");
  waitFor([](const json& j) { return j.value("tool", "") == "pose"; });
  screenshot("03-posed-without-line.png");
  xdo("mousemove 500 500");
  key("ctrl+e");
  s = waitFor([](const json& j) { return j.value("exports", 0) == 2 && !j.value("busy", true); });
  const double withoutLine = barBend(app::loadImage((dir / "export.png").string()));
  std::printf("bar bend without the line: %.3f px\n", withoutLine);
  EXPECT_GT(withoutLine, 2.0) << "the pose hardly bends the bar without the line: this test could not fail";
  EXPECT_GT(withoutLine, 4.0 * withLine);

  // 5. Undo (Ctrl+Z) the deletion: the line is back and bound again.
  key("ctrl+z");
  s = waitFor([](const json& j) { return j["lines"].size() == 1 && j.value("bound_lines", 0) == 1 && !j.value("busy", true); }, 90);
  EXPECT_NEAR(s["pose_translate"][2][1].get<double>(), 70.0, 2.0);
  for (const json& m : s["messages"]) EXPECT_FALSE(m["error"].get<bool>()) << m["text"];

  keepShots("lines-", {"01-line-drawn.png", "02-posed-with-line.png", "03-posed-without-line.png", "with-line.png", "export.png"});
}

}  // namespace
}  // namespace kc::test
