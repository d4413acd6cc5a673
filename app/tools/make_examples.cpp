// kc_make_examples: draws the bundled example pictures with OpenCV and writes them, their cages
// and poses (ARCHITECTURE.md file formats) into images/ — no downloaded pictures.
//
//   kc_make_examples [OUT_DIR]      (default: <source>/images)
//
// checker  256×256 checkerboard with distinguishable corners, 4-point cage (thesis 6.3.2)
// star     five-pointed star with a checker texture, 10-point cage (thesis 6.2.1, 6.3.3)
// figure   a gingerbread man with a non-convex 30-point cage (in the spirit of the butterfly, 6.3.4)
// stick    a stick figure with a round head: an 8-point loop around the head and six open sticks
//          (neck, arms, torso, legs), 14 control points (thesis 6.2.2, Fig 6.17)

#include <cmath>
#include <filesystem>
#include <iostream>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "kc/app/file_io.h"
#include "kc/app/image_io.h"
#include "kc/core/deform.h"

namespace {

using kc::Cage;
using kc::HandlePose;
using kc::Points;
using kc::Pose;
using kc::Vec2;

/// A BGR cv::Mat → the core's RGBA image.
kc::Image toImage(const cv::Mat& bgr) {
  cv::Mat rgba;
  cv::cvtColor(bgr, rgba, cv::COLOR_BGR2RGBA);
  kc::Image img(rgba.cols, rgba.rows);
  for (int y = 0; y < rgba.rows; ++y) std::copy_n(rgba.ptr<std::uint8_t>(y), std::size_t(rgba.cols) * 4, img.pixel(0, y));
  return img;
}

Points toPoints(const std::vector<Vec2>& v) {
  Points P(static_cast<kc::Index>(v.size()), 2);
  for (std::size_t i = 0; i < v.size(); ++i) P.row(kc::Index(i)) = v[i].transpose();
  return P;
}

/// Handle pose that rotates control c by θ (screen counter-clockwise) about pivot o.
HandlePose rotateAbout(const Vec2& c, const Vec2& o, double theta) {
  const Eigen::Matrix2d R = kc::screenRotation(theta);
  return {R * (c - o) + o - c, theta};
}

void write(const std::string& dir, const std::string& name, const cv::Mat& bgr, const Cage& cage, const Pose& pose) {
  kc::validateCage(cage);
  kc::validatePose(pose, cage.size());
  kc::app::saveImage(dir + "/" + name + ".png", toImage(bgr));
  kc::app::saveCage(dir + "/" + name + ".cage.json", cage);
  kc::app::savePose(dir + "/" + name + ".pose.json", pose);
  std::cout << "wrote " << dir << "/" << name << ".{png,cage.json,pose.json} (" << cage.size() << " control points)\n";
}

// --- checker ---------------------------------------------------------------------------------

void makeChecker(const std::string& dir) {
  const int n = 256, sq = 32;
  cv::Mat img(n, n, CV_8UC3);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const bool dark = ((x / sq) + (y / sq)) % 2 == 0;
      img.at<cv::Vec3b>(y, x) = dark ? cv::Vec3b(60, 60, 60) : cv::Vec3b(235, 235, 235);
    }
  // Distinguishable corners: a coloured square with a letter in each (BGR colours).
  const struct { int x, y; cv::Scalar color; const char* label; } corners[] = {
      {0, 0, {40, 40, 220}, "A"}, {n - sq, 0, {40, 180, 40}, "B"}, {n - sq, n - sq, {220, 90, 30}, "C"},
      {0, n - sq, {30, 200, 230}, "D"}};
  for (const auto& c : corners) {
    cv::rectangle(img, cv::Rect(c.x, c.y, sq, sq), c.color, cv::FILLED);
    cv::putText(img, c.label, {c.x + 8, c.y + 24}, cv::FONT_HERSHEY_SIMPLEX, 0.8, cv::Scalar(255, 255, 255), 2, cv::LINE_AA);
  }
  const Cage cage = Cage::polygon(toPoints({{0, 0}, {255, 0}, {255, 255}, {0, 255}}));
  Pose pose = kc::restPose(4);
  pose[1].translate = Vec2(-28, 36);  // upper-right corner dragged down and in (thesis Fig. 6.27)
  pose[3] = {Vec2(18, -10), 0.25};    // lower-left pulled in and turned
  write(dir, "checker", img, cage, pose);
}

// --- star ------------------------------------------------------------------------------------

std::vector<Vec2> starPoints(const Vec2& centre, double outer, double inner) {
  std::vector<Vec2> p;
  for (int k = 0; k < 10; ++k) {
    const double a = -std::numbers::pi / 2 + k * std::numbers::pi / 5;  // first tip straight up
    const double r = k % 2 == 0 ? outer : inner;
    p.emplace_back(centre.x() + r * std::cos(a), centre.y() + r * std::sin(a));
  }
  return p;
}

void makeStar(const std::string& dir) {
  const int n = 320;
  const Vec2 centre(160, 168);
  cv::Mat img(n, n, CV_8UC3, cv::Scalar(250, 246, 240));
  // Checker texture clipped to the star.
  cv::Mat mask(n, n, CV_8U, cv::Scalar(0));
  std::vector<cv::Point> poly;
  for (const Vec2& p : starPoints(centre, 140, 58)) poly.emplace_back(int(std::lround(p.x())), int(std::lround(p.y())));
  cv::fillPoly(mask, std::vector<std::vector<cv::Point>>{poly}, cv::Scalar(255), cv::LINE_AA);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const bool dark = ((x / 16) + (y / 16)) % 2 == 0;
      const cv::Vec3b tex = dark ? cv::Vec3b(30, 110, 200) : cv::Vec3b(120, 220, 250);
      const float a = mask.at<std::uint8_t>(y, x) / 255.0f;
      cv::Vec3b& px = img.at<cv::Vec3b>(y, x);
      for (int c = 0; c < 3; ++c) px[c] = cv::saturate_cast<std::uint8_t>(a * tex[c] + (1 - a) * px[c]);
    }
  cv::polylines(img, poly, true, cv::Scalar(20, 40, 90), 2, cv::LINE_AA);
  const std::vector<Vec2> cagePts = starPoints(centre, 150, 64);  // encloses the drawn star
  const Cage cage = Cage::polygon(toPoints(cagePts));
  Pose pose = kc::restPose(10);
  // Tip of the bottom-right leg (index 4) pulled outwards and turned clockwise (thesis Figs 6.32–6.33).
  pose[4] = {Vec2(22, 18), -0.35};
  pose[0].translate = Vec2(-12, 4);  // top tip nudged left
  write(dir, "star", img, cage, pose);
}

// --- figure ----------------------------------------------------------------------------------

void makeFigure(const std::string& dir) {
  const int w = 320, h = 400;
  cv::Mat img(h, w, CV_8UC3, cv::Scalar(235, 245, 250));
  const cv::Scalar dough(40, 110, 180), icing(255, 255, 255), dark(30, 40, 60);
  auto limb = [&](cv::Point a, cv::Point b, int width) {
    cv::line(img, a, b, dough, width, cv::LINE_AA);
    cv::circle(img, b, width / 2, dough, cv::FILLED, cv::LINE_AA);
  };
  limb({120, 170}, {40, 212}, 44);   // arms
  limb({200, 170}, {280, 212}, 44);
  limb({135, 265}, {95, 360}, 50);   // legs
  limb({185, 265}, {225, 360}, 50);
  cv::ellipse(img, {160, 205}, {62, 82}, 0, 0, 360, dough, cv::FILLED, cv::LINE_AA);  // body
  cv::circle(img, {160, 80}, 50, dough, cv::FILLED, cv::LINE_AA);                    // head
  // Icing: zigzags on wrists and ankles, buttons, face.
  for (auto [x, y, dir] : {std::tuple{52, 207, 1}, std::tuple{268, 207, -1}}) {
    std::vector<cv::Point> zz;
    for (int k = 0; k < 5; ++k) zz.emplace_back(x + dir * (k % 2) * 10 - dir * 2, y - 18 + 9 * k);
    cv::polylines(img, zz, false, icing, 3, cv::LINE_AA);
  }
  for (auto [x, y] : {std::pair{100, 344}, std::pair{220, 344}}) {
    std::vector<cv::Point> zz;
    for (int k = 0; k < 5; ++k) zz.emplace_back(x - 18 + 9 * k, y + (k % 2) * 10);
    cv::polylines(img, zz, false, icing, 3, cv::LINE_AA);
  }
  const cv::Scalar buttons[] = {{60, 60, 220}, {60, 190, 60}, {220, 120, 40}};
  for (int k = 0; k < 3; ++k) {
    cv::circle(img, {160, 165 + 35 * k}, 10, buttons[k], cv::FILLED, cv::LINE_AA);
    cv::circle(img, {160, 165 + 35 * k}, 10, icing, 2, cv::LINE_AA);
  }
  cv::circle(img, {142, 70}, 7, icing, cv::FILLED, cv::LINE_AA);
  cv::circle(img, {178, 70}, 7, icing, cv::FILLED, cv::LINE_AA);
  cv::circle(img, {142, 70}, 3, dark, cv::FILLED, cv::LINE_AA);
  cv::circle(img, {178, 70}, 3, dark, cv::FILLED, cv::LINE_AA);
  cv::ellipse(img, {160, 92}, {22, 14}, 0, 20, 160, icing, 3, cv::LINE_AA);
  // Non-convex cage around the figure, clockwise on screen, 30 points.
  const std::vector<Vec2> pts = {
      {160, 18},  {206, 34},  {224, 80},  {204, 126},                                   // head, right
      {240, 140}, {292, 178}, {314, 212}, {294, 248}, {255, 246}, {222, 226},            // right arm
      {228, 272}, {262, 344}, {258, 390}, {218, 392}, {190, 340},                        // right leg
      {160, 300},                                                                        // crotch
      {130, 340}, {102, 392}, {62, 390},  {58, 344},  {92, 272},                         // left leg
      {98, 226},  {65, 246},  {26, 248},  {6, 212},   {28, 178},  {80, 140},             // left arm
      {116, 126}, {96, 80},   {114, 34}};                                                // head, left
  const Cage cage = Cage::polygon(toPoints(pts));
  Pose pose = kc::restPose(static_cast<kc::Index>(pts.size()));
  // Wave: the right arm's hand points turn upwards about the shoulder.
  const Vec2 shoulder(222, 170);
  for (int i : {5, 6, 7, 8}) pose[std::size_t(i)] = rotateAbout(pts[std::size_t(i)], shoulder, 0.6);
  pose[4] = rotateAbout(pts[4], shoulder, 0.3);
  // Left leg kicks outwards a little.
  for (int i : {17, 18, 19}) pose[std::size_t(i)].translate = Vec2(-14, -8);
  write(dir, "figure", img, cage, pose);
}

// --- stick figure ----------------------------------------------------------------------------

void makeStick(const std::string& dir) {
  const int w = 320, h = 400;
  cv::Mat img(h, w, CV_8UC3, cv::Scalar(246, 238, 228));
  cv::rectangle(img, cv::Rect(0, 372, w, h - 372), cv::Scalar(120, 190, 140), cv::FILLED);  // grass
  const Vec2 head(160, 72);
  const double ring = 52;  // the head's loop of control points; the drawn head (r 42) lies inside it
  std::vector<Vec2> pts;
  for (int k = 0; k < 8; ++k) {  // 0 at the top, clockwise on screen, every 45°
    const double a = -std::numbers::pi / 2 + k * std::numbers::pi / 4;
    pts.emplace_back(head.x() + ring * std::cos(a), head.y() + ring * std::sin(a));
  }
  const Vec2 shoulders(160, 168), handR(252, 226), handL(68, 226), hips(160, 270), footR(214, 360), footL(106, 360);
  for (const Vec2& p : {shoulders, handR, handL, hips, footR, footL}) pts.push_back(p);  // 8..13
  const cv::Scalar ink(70, 50, 40), shirt(60, 80, 200), trousers(140, 80, 40), skin(150, 190, 240);
  auto pt = [](const Vec2& p) { return cv::Point(int(std::lround(p.x())), int(std::lround(p.y()))); };
  auto stick = [&](const Vec2& a, const Vec2& b, const cv::Scalar& c) {
    cv::line(img, pt(a), pt(b), c, 14, cv::LINE_AA);
    cv::circle(img, pt(b), 7, c, cv::FILLED, cv::LINE_AA);
  };
  stick(pts[4], shoulders, skin);  // neck
  stick(shoulders, hips, shirt);   // torso
  stick(shoulders, handR, shirt);
  stick(shoulders, handL, shirt);
  stick(hips, footR, trousers);
  stick(hips, footL, trousers);
  for (const Vec2& hand : {handR, handL}) cv::circle(img, pt(hand), 9, skin, cv::FILLED, cv::LINE_AA);
  for (const Vec2& foot : {footR, footL}) cv::ellipse(img, pt(foot + Vec2(foot.x() > 160 ? 6 : -6, 4)), {14, 7}, 0, 0, 360, ink, cv::FILLED, cv::LINE_AA);
  // The head: face, eyes, smile, hair.
  cv::circle(img, pt(head), 42, skin, cv::FILLED, cv::LINE_AA);
  cv::ellipse(img, pt(head), {42, 42}, 0, 200, 340, ink, 9, cv::LINE_AA);
  cv::circle(img, pt(head + Vec2(-15, -4)), 5, ink, cv::FILLED, cv::LINE_AA);
  cv::circle(img, pt(head + Vec2(15, -4)), 5, ink, cv::FILLED, cv::LINE_AA);
  cv::ellipse(img, pt(head + Vec2(0, 10)), {18, 12}, 0, 20, 160, ink, 3, cv::LINE_AA);
  cv::circle(img, pt(head), 42, ink, 2, cv::LINE_AA);

  Cage cage;
  cage.C = toPoints(pts);
  cage.closed = false;
  for (int k = 0; k < 8; ++k) cage.edges.push_back({k, (k + 1) % 8});  // the head's loop: an interior
  for (const auto& e : std::vector<std::array<int, 2>>{{4, 8}, {8, 9}, {8, 10}, {8, 11}, {11, 12}, {11, 13}})
    cage.edges.push_back(e);  // sticks: neck, arms, torso, legs
  Pose pose = kc::restPose(cage.size());
  // The right arm waves (about the shoulders), the left leg steps out, the head tilts.
  pose[9] = rotateAbout(handR, shoulders, 0.9);
  pose[13].translate = Vec2(-26, -10);
  for (int k = 0; k < 8; ++k) pose[std::size_t(k)] = rotateAbout(pts[std::size_t(k)], pts[4], 0.2);
  write(dir, "stick", img, cage, pose);
}

}  // namespace

int main(int argc, char** argv) {
  const std::string dir = argc > 1 ? argv[1] : std::string(KC_SOURCE_DIR) + "/images";
  try {
    std::filesystem::create_directories(dir);
    makeChecker(dir);
    makeStar(dir);
    makeFigure(dir);
    makeStick(dir);
  } catch (const std::exception& e) {
    std::cerr << "kc_make_examples: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
