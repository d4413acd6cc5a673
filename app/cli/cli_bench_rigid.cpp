// kcwarp-cli bench --rigid: rigid regions. Quality on the thesis's Fig 6.37
// set-up (the bundled star; rigid region = the inner part of the bottom-right leg; that leg's tip
// moved 40 px toward the star's centre) at several strengths; speed of a brush release
// (app::setRigidity) for a 500-sample region on the star and a 2,000-sample region on the figure.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <sys/resource.h>

#include "cli_common.h"
#include "kc/app/file_io.h"
#include "kc/app/image_io.h"
#include "kc/app/pipeline.h"
#include "kc/app/rigidity.h"
#include "kc/core/field/kernel_field.h"

namespace kc::cli {
namespace {

app::Session bindExample(const std::string& dir, const std::string& name, Cage& cage) {
  cage = app::loadCage(dir + "/" + name + ".cage.json");
  const app::ImageHeader h = app::readImageFileHeader(dir + "/" + name + ".png");
  return app::bind(cage, int(h.width), int(h.height), app::frameBindParams());
}

/// A copy of a bound session (through its file text: the field is rebuilt as when loading).
app::Session copyOf(const app::Session& s) { return app::sessionFromJson(app::sessionToJson(s), "bench"); }

/// Largest weight change between two fields at grid points (step 4 px over the image) farther
/// than `far` from every sample with ρ > 0.
double farChange(const app::Session& a, const app::Session& b, const std::vector<double>& rho, double far) {
  std::vector<Vec2> pts;
  for (double y = 2.0; y < a.imageHeight; y += 4.0)
    for (double x = 2.0; x < a.imageWidth; x += 4.0) {
      bool isFar = true;
      for (Index i = 0; i < a.samples.size() && isFar; ++i)
        isFar = rho[std::size_t(i)] == 0.0 || (a.samples.X.row(i).transpose() - Vec2(x, y)).norm() > far;
      if (isFar) pts.emplace_back(x, y);
    }
  Points P(Index(pts.size()), 2);
  for (std::size_t k = 0; k < pts.size(); ++k) P.row(Index(k)) = pts[k].transpose();
  return (a.field->weightsAt(P) - b.field->weightsAt(P)).cwiseAbs().maxCoeff();
}

/// ρ = 1 at the `count` samples inside the cage nearest to the cage's centroid.
std::vector<double> discRegion(const app::Session& s, Index count) {
  const Vec2 c = polygonCentroid(s.cage.C);
  std::vector<std::pair<double, Index>> d;
  for (Index i = 0; i < s.samples.size(); ++i)
    if (s.samples.kind[std::size_t(i)] != SampleKind::Exterior) d.emplace_back((s.samples.X.row(i).transpose() - c).norm(), i);
  std::sort(d.begin(), d.end());
  std::vector<double> rho(std::size_t(s.samples.size()), 0.0);
  for (Index k = 0; k < std::min<Index>(count, Index(d.size())); ++k) rho[std::size_t(d[std::size_t(k)].second)] = 1.0;
  return rho;
}

/// One timed brush release on `s` (app::setRigidity): milliseconds, minor page faults, and the
/// progress calls with the longest gap between two (how long a Cancel may wait).
struct Release {
  app::RigidityUpdate u;
  double ms = 0.0, gap = 0.0;
  long faults = 0;
  int calls = 0;
};

Release timedRelease(app::Session& s, const std::vector<double>& rho) {
  Release r;
  rusage before{}, after{};
  getrusage(RUSAGE_SELF, &before);
  auto last = std::chrono::steady_clock::now();
  r.u = app::setRigidity(s, rho, [&](const char*, double) {
    const auto now = std::chrono::steady_clock::now();
    r.gap = std::max(r.gap, std::chrono::duration<double>(now - last).count());
    last = now;
    ++r.calls;
    return true;
  });
  getrusage(RUSAGE_SELF, &after);
  r.ms = 1e3 * r.u.seconds;
  r.faults = after.ru_minflt - before.ru_minflt;
  return r;
}

/// After the QP iterations: "~" for the splitting path's ADMM iterations, " " for active-set rounds.
const char* methodMark(RigidityQpMethod m) { return m == RigidityQpMethod::Splitting ? "~" : " "; }

/// Per repeat: a session loaded from the bound one's text (its field not factorized, as after
/// opening a file); K is factorized first (timed apart: a loaded session's first release pays it),
/// then the release is timed on the factorized field — the GUI's case after a bind or a stroke.
void benchSpeed(const std::string& dir, const std::string& name, Index count, double goalMs, int repeats) {
  Cage cage;
  const app::Session plain = bindExample(dir, name, cage);
  const std::vector<double> rho = discRegion(plain, count);
  std::vector<double> ms, factor, faults;
  Release r;
  double gap = 0.0;
  int calls = 0;
  for (int k = 0; k < repeats; ++k) {
    app::Session s = copyOf(plain);
    const auto t0 = std::chrono::steady_clock::now();
    dynamic_cast<KernelField&>(*s.field).update(s.W);
    factor.push_back(1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    r = timedRelease(s, rho);
    ms.push_back(r.ms);
    faults.push_back(double(r.faults));
    gap = std::max(gap, r.gap);
    calls += r.calls;
  }
  const RigidityReport& q = r.u.report;
  std::printf("  %-7s %7ld %8ld %7ld %9ld %9ld %11.1f %9.1f %10.1f %8d%s %9.1f %8d %8.1f %8.0f %16.10g  (goal %.0f ms)\n", name.c_str(),
              long(q.region), long(q.nodes), long(q.controls), long(cage.size()), long(r.u.rows.size()), median(ms), median(factor),
              1e3 * q.solver.seconds, q.solver.iterations, methodMark(q.solver.method),
              1e3 * q.solver.factorSeconds, calls / repeats, 1e3 * gap, median(faults), q.solver.objective, goalMs);
}

void printSpeedHeader(int repeats) {
  std::printf("speed: app::setRigidity (brush release: restore, QP, field columns), median of %d runs\n", repeats);
  std::printf("  (release: on a factorized field, as in the GUI after a bind or a stroke; K ms: factorizing K and solving\n"
              "  every column on a loaded session, which its first release pays on top; QP it: active-set rounds, or ADMM\n"
              "  iterations when marked ~ (the splitting path of large regions); progress: calls per release and the\n"
              "  longest gap between two, i.e. how long a Cancel can wait; faults: minor page faults per release)\n");
  std::printf("  %-7s %7s %8s %7s %9s %9s %11s %9s %10s %9s %9s %8s %8s %8s %16s\n", "example", "region", "nodes", "active", "controls",
              "rows", "release ms", "K ms", "QP ms", "QP it", "factor ms", "progress", "gap ms", "faults", "QP objective");
}

/// Mean ‖J − R‖ over `polygon` for `pose` without and with the polygon made rigid (strength 1).
void otherSetUp(const app::Session& plain, const char* what, const Points& polygon, const Pose& pose) {
  const double none = app::measureRigidity(plain, polygon, pose).distortion;
  app::Session s = copyOf(plain);
  const RigidRegion region{polygon, 1.0};
  const std::vector<double> rho = rigidityOfRegions(s.samples.X, std::span(&region, 1));
  app::setRigidity(s, rho);
  const double with = app::measureRigidity(s, polygon, pose).distortion;
  std::printf("  %-58s %8.4f %8.4f %6.2f %10.2g %8.3g %8.3g\n", what, none, with, with / none,
              farChange(s, plain, rho, 6.0 * plain.sigma), plain.W.minCoeff(), s.W.minCoeff());
}

/// Other regions and poses than Fig 6.37's (docs/rigidity.md's table): the star's leg of tip 0
/// with that tip moved in and sideways, and the figure's head with a head control moved.
void benchOtherSetUps(const app::Session& star, const std::string& dir) {
  std::printf("other set-ups: mean |J-R| without, with (strength 1), ratio, largest weight change farther than 6 sigma,\n"
              "  smallest sample weight before and after\n");
  Cage turned = star.cage;  // the star's points renumbered so that starLegSetup's tip 4 is point 0
  for (Index i = 0; i < 10; ++i) turned.C.row(i) = star.cage.C.row((i + 6) % 10);
  const app::StarLegSetup leg = app::starLegSetup(turned);
  Pose in = restPose(10), side = restPose(10);
  in[0].translate = leg.pose[4].translate;
  side[0].translate = Vec2(-leg.pose[4].translate.y(), leg.pose[4].translate.x());
  otherSetUp(star, "star, leg of tip 0; tip 0 moved 40 px toward the centre", leg.polygon, in);
  otherSetUp(star, "star, leg of tip 0; tip 0 moved 40 px sideways", leg.polygon, side);
  Cage cage;
  const app::Session figure = bindExample(dir, "figure", cage);
  if (cage.size() != 30) return;
  Points head(8, 2);
  for (int k = 0; k < 8; ++k) head.row(k) << 160.0 + 30.0 * std::cos(k * 0.25 * M_PI), 72.0 + 30.0 * std::sin(k * 0.25 * M_PI);
  Pose top = restPose(30), hand = restPose(30);
  top[0].translate = Vec2(0.0, 30.0);
  hand[6].translate = Vec2(-10.0, -40.0);
  otherSetUp(figure, "figure, head (octagon r 30 at 160,72); control 0 down 30 px", head, top);
  otherSetUp(figure, "figure, same head; the right hand (control 6) up 40 px", head, hand);
}

}  // namespace

void benchRigid(const std::string& dir, int repeats, const std::string& speedOnly) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // line by line: each row as it is measured
  if (!speedOnly.empty()) {  // only the brush-release rows
    printSpeedHeader(repeats);
    if (speedOnly != "figure") benchSpeed(dir, "star", 500, 200.0, repeats);
    if (speedOnly != "star") benchSpeed(dir, "figure", 2000, 2000.0, repeats);
    return;
  }
  Cage cage;
  const app::Session plain = bindExample(dir, "star", cage);
  if (cage.size() != 10) throw app::InputError(dir + "/star.cage.json", "bench --rigid expects the bundled 10-point star");
  const app::StarLegSetup leg = app::starLegSetup(cage);
  const Points& poly = leg.polygon;
  const Pose& pose = leg.pose;
  const Vec2 centre = leg.centroid;
  const double sigma = plain.sigma;
  std::printf("rigid: thesis Fig 6.37 set-up on %s/star (%dx%d, defaults, sigma %.3g px): region = the triangle (%.1f,%.1f) "
              "(%.1f,%.1f) (%.1f,%.1f),\n  the inner part of the bottom-right leg; control 4 (its tip) moved 40 px toward the "
              "centroid (%.1f,%.1f); grid of 1 px in the region\n",
              dir.c_str(), plain.imageWidth, plain.imageHeight, sigma, poly(0, 0), poly(0, 1), poly(1, 0), poly(1, 1), poly(2, 0),
              poly(2, 1), centre.x(), centre.y());
  std::printf("  %8s %8s %10s %10s %12s %10s %12s %9s %7s %8s\n", "strength", "samples", "mean|J-R|", "unity", "reproduction",
              "min w", "far change", "solve ms", "QP it", "energy");
  const app::RigidityFigures none = app::measureRigidity(plain, poly, pose);
  std::printf("  %8s %8s %10.4f %10.2g %12.2g %10.3g %12s %9s %7s %8s\n", "none", "-", none.distortion, none.unity, none.reproduction,
              none.minWeight, "-", "-", "-", "-");
  double atOne = 0.0, unity = 0.0, repro = 0.0, far = 0.0;
  for (double strength : {0.25, 0.5, 0.75, 1.0}) {
    app::Session s = copyOf(plain);
    const RigidRegion region{poly, strength};
    const std::vector<double> rho = rigidityOfRegions(s.samples.X, std::span(&region, 1));
    const app::RigidityUpdate u = app::setRigidity(s, rho);
    const app::RigidityFigures f = app::measureRigidity(s, poly, pose);
    const double change = farChange(s, plain, rho, 6.0 * sigma);
    std::printf("  %8.2f %8ld %10.4f %10.2g %12.2g %10.3g %12.2g %9.1f %6d%s %8.3g\n", strength, long(u.report.region), f.distortion,
                f.unity, f.reproduction, f.minWeight, change, 1e3 * u.seconds, u.report.solver.iterations,
                methodMark(u.report.solver.method),
                u.report.energyAfter / std::max(u.report.energyBefore, 1e-300));
    if (strength == 1.0) atOne = f.distortion, unity = f.unity, repro = f.reproduction, far = change;
  }
  std::printf("  strength 1: mean |J-R| %.4f = %.2f of none (goal <= 0.5), unity %.2g, reproduction %.2g px (goal <= 1e-9),\n"
              "  largest weight change farther than 6 sigma %.2g (goal <= 1e-4)\n",
              atOne, atOne / none.distortion, unity, repro, far);
  benchOtherSetUps(plain, dir);
  printSpeedHeader(repeats);
  benchSpeed(dir, "star", 500, 200.0, repeats);
  benchSpeed(dir, "figure", 2000, 2000.0, repeats);
}

}  // namespace kc::cli
