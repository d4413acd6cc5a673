// End to end: the rigidity brush in a real window under Xvfb, driven with real X input (xdotool),
// as a person uses it. The picture is a coordinate ramp (red = x, green = y), so every pixel of an
// exported warp says where in the picture it came from, and the warp's local Jacobian can be read
// off the exported pixels. The user binds, paints a stroke over a region with the rigidity brush (R),
// drags a control point with the pose tool and exports; then clears the rigidity (the pose stays)
// and exports again. Measured on the exported pixels: how far the warp is from a rotation over the
// painted region (mean ‖J − R‖_F), with and without the stroke — checked against the same measure
// of the saved session's field (app::measureRigidity) — and that the stroke changed the export
// only near the region.
#include <Eigen/Dense>
#include <cmath>

#include "gui_session.h"
#include "kc/app/file_io.h"
#include "kc/app/rigidity.h"

namespace kc::test {
namespace {

constexpr int kSize = 256;
const Vec2 kCentre(150, 105);   // the painted region: a stroke across it
constexpr double kHalf = 22.0;  // the stroke runs kCentre ± (kHalf, 0); the brush radius is 25 px

/// Red = x, green = y (pixel centres), blue 128: bilinear resampling keeps it exact.
Image rampPicture() {
  Image img(kSize, kSize, Rgba{0, 0, 128, 255});
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      std::uint8_t* p = img.pixel(x, y);
      p[0] = static_cast<std::uint8_t>(x);
      p[1] = static_cast<std::uint8_t>(y);
    }
  return img;
}

/// The warp's distortion over the picture points within `radius` of `centre` (rest positions, as
/// the ramp encodes them): at every exported pixel whose rest position lies there, the affine map
/// from output to rest pixels is fitted by least squares over the 7×7 pixels around it (its
/// matrix A is the inverse Jacobian), J = A⁻¹, and ‖J − R‖_F with R the nearest rotation (polar
/// decomposition) is averaged. `count` receives the number of pixels measured.
double rampDistortion(const Image& img, const Vec2& centre, double radius, int* count = nullptr) {
  auto rest = [&](int x, int y, Vec2& q) {
    const std::uint8_t* p = const_cast<Image&>(img).pixel(x, y);
    if (p[3] < 255 || std::abs(int(p[2]) - 128) > 2) return false;
    q = Vec2(p[0], p[1]);
    return true;
  };
  double sum = 0.0;
  int n = 0;
  for (int y = 3; y < img.height - 3; ++y)
    for (int x = 3; x < img.width - 3; ++x) {
      Vec2 q = Vec2::Zero();
      if (!rest(x, y, q) || (q - centre).norm() > radius) continue;
      Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
      Eigen::Matrix<double, 3, 2> b = Eigen::Matrix<double, 3, 2>::Zero();
      bool ok = true;
      for (int dy = -3; dy <= 3 && ok; ++dy)
        for (int dx = -3; dx <= 3 && ok; ++dx) {
          Vec2 r = Vec2::Zero();
          ok = rest(x + dx, y + dy, r);
          const Eigen::Vector3d v(dx, dy, 1.0);
          M += v * v.transpose();
          b += v * r.transpose();
        }
      if (!ok) continue;
      const Eigen::Matrix<double, 3, 2> X = M.ldlt().solve(b);  // r ≈ [dx dy 1] X
      const Eigen::Matrix2d A = X.topRows<2>().transpose();     // ∂rest/∂output
      if (std::abs(A.determinant()) < 1e-6) continue;
      const Eigen::Matrix2d J = A.inverse();
      Eigen::JacobiSVD<Eigen::Matrix2d> svd(J, Eigen::ComputeFullU | Eigen::ComputeFullV);
      Eigen::Matrix2d D = Eigen::Matrix2d::Identity();
      D(1, 1) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
      sum += (J - svd.matrixU() * D * svd.matrixV().transpose()).norm();
      ++n;
    }
  if (count) *count = n;
  return n > 0 ? sum / n : -1.0;
}

/// Rest positions (from the ramp) of the pixels where two exports differ by more than one level in red or green; returns the largest distance of one from `centre` (0 when none differ) and the count.
double farthestChange(const Image& a, const Image& b, const Vec2& centre, long* changed) {
  double far = 0.0;
  long n = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const std::uint8_t* p = const_cast<Image&>(a).pixel(x, y);
      const std::uint8_t* q = const_cast<Image&>(b).pixel(x, y);
      // A change of one level is rounding: the rigidity's global term (≤ ~2e-4 in weight, docs/rigidity.md)
      // times the pose's displacement moves a source position by a few hundredths of a pixel.
      if (std::abs(int(p[0]) - int(q[0])) <= 1 && std::abs(int(p[1]) - int(q[1])) <= 1) continue;
      ++n;
      far = std::max(far, (Vec2(p[0], p[1]) - centre).norm());
    }
  *changed = n;
  return far;
}

TEST_F(GuiSession, ARigidStrokeChangesTheExportedWarpAroundTheRegionAsTheFieldSays) {
  const fs::path image = dir / "ramp.png", cagePath = dir / "ramp.cage.json";
  app::saveImage(image.string(), rampPicture());
  Points C(6, 2);
  C << 10, 10, 128, 10, 245, 10, 245, 245, 128, 245, 10, 245;
  app::saveCage(cagePath.string(), Cage::polygon(C));
  startApp({image.string(), "--cage", cagePath.string()});
  json s = waitFor([](const json& j) { return j.value("bound", false) && !j.value("busy", true); }, 90);
  ASSERT_TRUE(s.value("bound", false));
  const int wx = s["window"][0], wy = s["window"][1];

  // 1. Rigidity brush (R); one stroke across the region: ρ is painted and re-solved around it.
  key("r");
  s = waitFor([](const json& j) { return j.value("tool", "") == "rigid"; });
  const Vec2 a = screenOf(s, kCentre - Vec2(kHalf, 0)), b = screenOf(s, kCentre + Vec2(kHalf, 0));
  drag(a.x(), a.y(), b.x(), b.y(), 1);
  s = waitFor([](const json& j) { return j.value("rigid_samples", 0) > 0 && j.value("undo", 0) == 1 && j.value("idle", false); }, 120);
  const int rigid = s.value("rigid_samples", 0);
  std::printf("rigid samples after the stroke: %d\n", rigid);
  EXPECT_GT(rigid, 20);
  screenshot("01-painted.png");

  // 2. Pose tool (P); drag the top right control point 40 px left and 70 px down.
  key("p");
  s = waitFor([](const json& j) { return j.value("tool", "") == "pose"; });
  const double zoom = s["view"]["zoom"];
  const double cx = s["controls"][2][0].get<double>() + wx, cy = s["controls"][2][1].get<double>() + wy;
  drag(cx, cy, cx - 40 * zoom, cy + 70 * zoom, 1);
  s = waitFor([](const json& j) { return j.value("undo", 0) == 2 && j.value("idle", false); });
  EXPECT_NEAR(s["pose_translate"][2][1].get<double>(), 70.0, 2.0);
  key("r");
  waitFor([](const json& j) { return j.value("tool", "") == "rigid"; });
  xdo("mousemove 1300 800");  // off the canvas: no brush ring in the screenshot
  screenshot("02-posed-with-rigidity.png");

  // 3. Save the session (Ctrl+S, the path typed into the dialog) and export (Ctrl+E) with the stroke.
  key("ctrl+s");
  pause(300);
  xdo("key --delay 20 ctrl+a");
  xdo("type --delay 15 '" + (dir / "rigid.kcw.json").string() + "'");
  key("Return");
  s = waitFor([](const json& j) { return !j.value("unsaved", true) && !j.value("busy", true); });
  ASSERT_TRUE(fs::exists(dir / "rigid.kcw.json"));
  key("ctrl+e");
  s = waitFor([](const json& j) { return j.value("exports", 0) == 1 && !j.value("busy", true); });
  fs::copy_file(dir / "export.png", dir / "with-stroke.png", fs::copy_options::overwrite_existing);

  // 4. Clear rigidity (the panel's button; the pose stays) and export again.
  s = waitFor([](const json& j) { return j["widgets"].contains("Clear rigidity"); });
  const double bx = s["widgets"]["Clear rigidity"][0].get<double>() + wx, by = s["widgets"]["Clear rigidity"][1].get<double>() + wy;
  click(bx, by);
  s = waitFor([](const json& j) { return j.value("rigid_samples", 1) == 0 && j.value("undo", 0) == 3 && j.value("idle", false); }, 120);
  EXPECT_NEAR(s["pose_translate"][2][1].get<double>(), 70.0, 2.0) << "clearing the rigidity keeps the pose";
  key("ctrl+e");
  s = waitFor([](const json& j) { return j.value("exports", 0) == 2 && !j.value("busy", true); });
  fs::copy_file(dir / "export.png", dir / "without-stroke.png", fs::copy_options::overwrite_existing);
  for (const json& m : s["messages"]) EXPECT_FALSE(m["error"].get<bool>()) << m["text"];

  // 5. The exported pixels over the painted core (rest positions within 15 px of the stroke's
  // centre), with the stroke and without it, against the saved session's field over the same disc.
  const Image with = app::loadImage((dir / "with-stroke.png").string());
  const Image without = app::loadImage((dir / "without-stroke.png").string());
  int nWith = 0, nWithout = 0;
  const double dWith = rampDistortion(with, kCentre, 15.0, &nWith), dWithout = rampDistortion(without, kCentre, 15.0, &nWithout);
  app::Session saved = app::loadSession((dir / "rigid.kcw.json").string());
  EXPECT_EQ(std::count_if(saved.rigidity.begin(), saved.rigidity.end(), [](double r) { return r > 0.0; }), rigid);
  Points disc(48, 2);
  for (Index k = 0; k < disc.rows(); ++k)
    disc.row(k) = (kCentre + 15.0 * Vec2(std::cos(2 * M_PI * k / 48), std::sin(2 * M_PI * k / 48))).transpose();
  const double fieldWith = app::measureRigidity(saved, disc, saved.pose).distortion;
  app::setRigidity(saved, std::vector<double>(saved.rigidity.size(), 0.0));
  const double fieldWithout = app::measureRigidity(saved, disc, saved.pose).distortion;
  long changed = 0;
  const double far = farthestChange(with, without, kCentre, &changed);
  std::printf("mean |J-R| over the painted core, exported pixels: %.4f with the stroke (%d px), %.4f without (%d px); "
              "the session's field: %.4f with, %.4f without\n%ld pixels differ, the farthest %.1f px from the stroke's centre\n",
              dWith, nWith, dWithout, nWithout, fieldWith, fieldWithout, changed, far);
  EXPECT_GT(nWith, 300);
  EXPECT_GT(nWithout, 300);
  EXPECT_GT(dWithout, 0.05) << "the pose hardly distorts the region";
  // The export shows the field's distortion (the display mesh is piecewise linear on a 4 px grid).
  EXPECT_NEAR(dWith, fieldWith, 0.02);
  EXPECT_NEAR(dWithout, fieldWithout, 0.02);
  // The stroke moved the exported region the way the field says: the difference has the field's sign.
  ASSERT_GT(std::abs(fieldWith - fieldWithout), 0.003) << "the stroke hardly changed the field over the region";
  EXPECT_EQ(dWith < dWithout, fieldWith < fieldWithout);
  EXPECT_GT(changed, 100) << "the stroke did not change the export";
  // The painted samples lie within 22 + 25 px of the centre; weights change within 6σ (σ ≈ 5.3 px at
  // the automatic 6 px spacing) of them; the display of a change spreads by one 4 px mesh cell.
  EXPECT_LT(far, 47.0 + 6.0 * 5.4 + 8.0) << "the stroke changed the export far from the region";

  keepShots("rigid-", {"01-painted.png", "02-posed-with-rigidity.png", "with-stroke.png", "without-stroke.png"});
}

}  // namespace
}  // namespace kc::test
