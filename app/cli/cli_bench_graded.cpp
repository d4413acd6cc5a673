// kcwarp-cli bench --graded: cages drawn tightly (legs 4 px apart and arms 6 px from the torso, a
// 3 px slit, a 2 px neck, an arm meeting the torso at a 2.9° armpit; tests/data/narrow) against the
// same cages with their gaps widened to 40 px, bound with defaults by each backend: bind time and
// its ratio, samples, partition of unity and reproduction inside the cage, and the weight that leaks
// across a gap. Then one neck on a 12-megapixel picture against the same scene at 0.1 megapixel.
// kcwarp-cli bench --backends (the same timed pairs): given cages bound with defaults by kc and by
// lbc, their bind times and ratio.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <numbers>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_common.h"
#include "kc/app/errors.h"
#include "kc/app/file_io.h"
#include "kc/app/image_io.h"
#include "kc/app/pipeline.h"

namespace kc::cli {
namespace {

/// Where a gap's leak is measured: probes `offsets` px inside the cage from the vertical wall
/// x = wall (direction `inward`, ±1), for y in [y0, y1]; the far side's controls are those `far`
/// selects (geodesically far from the probes, across the gap).
struct LeakProbe {
  double wall = 0.0, inward = 1.0, y0 = 0.0, y1 = 0.0;
  std::function<bool(const Vec2&)> far;
};

struct NarrowCase {
  std::string name;
  LeakProbe narrow, wide;
  bool leak = true;
};

std::vector<NarrowCase> narrowCases() {
  // person: the right leg's inner wall (x = 202 narrow, 220 wide), its lower half; far: the left leg's
  // lower controls. slit: the slit's left wall near the top (x = 148.5 narrow, 130 wide); far: the
  // controls right of the slit at its top, 280 px round it.
  auto leftLeg = [](const Vec2& c) { return c.x() < 200.0 && c.y() > 400.0; };
  auto rightTop = [](const Vec2& c) { return c.x() > 150.0 && c.y() < 60.0; };
  // armpit: the torso's wall x = 180 beside the arm, from 10 px below the armpit to 30 px above the
  // wedge's mouth; far: the arm's lower controls.
  auto lowerArm = [](const Vec2& c) { return c.x() > 185.0 && c.y() > 250.0; };
  return {{"person", {202.0, 1.0, 400.0, 460.0, leftLeg}, {220.0, 1.0, 400.0, 460.0, leftLeg}},
          {"slit", {148.5, -1.0, 55.0, 120.0, rightTop}, {130.0, -1.0, 55.0, 120.0, rightTop}},
          {"neck", {}, {}, false},
          {"armpit", {180.0, -1.0, 110.0, 270.0, lowerArm}, {180.0, -1.0, 110.0, 270.0, lowerArm}}};
}

struct Quality {
  double unity = 0.0, reproduction = 0.0, leak = 0.0;
};

/// Partition of unity and reproduction on a 2-px grid inside the cage; the largest |Σ far weights|
/// at the leak probes (1, 1.5, …, 3 px from the wall).
Quality measure(const app::Session& s, const LeakProbe* probe) {
  Quality q;
  const CageQueries inside(s.cage);
  std::vector<Vec2> pts;
  const double x0 = s.cage.C.col(0).minCoeff(), x1 = s.cage.C.col(0).maxCoeff(), y0 = s.cage.C.col(1).minCoeff(),
               y1 = s.cage.C.col(1).maxCoeff();
  for (double y = y0 + 0.5; y < y1; y += 2.0)
    for (double x = x0 + 0.5; x < x1; x += 2.0)
      if (inside.inside(Vec2(x, y))) pts.emplace_back(x, y);
  Points P(Index(pts.size()), 2);
  for (std::size_t k = 0; k < pts.size(); ++k) P.row(Index(k)) = pts[k].transpose();
  const Weights W = s.field->weightsAt(P);
  for (Index k = 0; k < P.rows(); ++k) {
    q.unity = std::max(q.unity, std::abs(W.row(k).sum() - 1.0));
    q.reproduction = std::max(q.reproduction, (W.row(k) * s.cage.C - P.row(k)).norm());
  }
  if (!probe) return q;
  std::vector<Index> far;
  for (Index i = 0; i < s.cage.size(); ++i)
    if (probe->far(s.cage.C.row(i))) far.push_back(i);
  std::vector<Vec2> leakPts;
  for (double d = 1.0; d <= 3.0; d += 0.5)
    for (double y = probe->y0; y <= probe->y1; y += 2.0) leakPts.emplace_back(probe->wall + probe->inward * d, y);
  Points L(Index(leakPts.size()), 2);
  for (std::size_t k = 0; k < leakPts.size(); ++k) L.row(Index(k)) = leakPts[k].transpose();
  const Weights WL = s.field->weightsAt(L);
  for (Index k = 0; k < L.rows(); ++k) {
    double sum = 0.0;
    for (Index i : far) sum += WL(k, i);
    q.leak = std::max(q.leak, std::abs(sum));
  }
  return q;
}

struct Timed {
  double seconds = 0.0;  // median over the runs
  std::vector<double> runs;
  std::vector<app::BindTimings> stages;  // each run's
  Index samples = 0;
  double hMin = 0.0, hMax = 0.0;
  app::Session session;
  std::string refused;
};

/// One more default bind of `cage` (automatic spacing), its wall time appended to t.runs; a refusal
/// is kept in t.refused and stops further runs.
void bindOnce(Timed& t, const Cage& cage, int w, int h, const app::BindParams& params) {
  if (!t.refused.empty()) return;
  try {
    app::BindParams p = params;
    p.spacing = app::automaticSpacing(cage, w, h, p);
    const auto t0 = std::chrono::steady_clock::now();
    t.session = app::bind(cage, w, h, p);
    t.runs.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    t.stages.push_back(t.session.report.timings);
    t.samples = t.session.samples.size();
    t.hMax = p.spacing;
    t.hMin = t.session.sizing ? t.session.sizing->hMin() : p.spacing;
  } catch (const std::exception& e) {
    t.refused = e.what();
  }
}

struct Bindable {
  Cage cage;
  int w = 0, h = 0;
};

/// `repeats` binds of each (b with paramsB when given), alternating (a, b, a, b, …), so that each b runs right after its a; the
/// ratio is the median over the pairs of b's time / a's (a change of the machine's load between
/// pairs cancels in it). Both Timed hold their median time.
double timedPair(const Bindable& a, const Bindable& b, const app::BindParams& params, int repeats, Timed& ta, Timed& tb,
                 const app::BindParams* paramsB = nullptr) {
  for (int r = 0; r < repeats; ++r) {
    bindOnce(ta, a.cage, a.w, a.h, params);
    bindOnce(tb, b.cage, b.w, b.h, paramsB ? *paramsB : params);
  }
  ta.seconds = median(ta.runs);
  tb.seconds = median(tb.runs);
  if (!ta.refused.empty() || !tb.refused.empty()) return 0.0;
  std::vector<double> ratios;
  for (std::size_t k = 0; k < ta.runs.size(); ++k) ratios.push_back(tb.runs[k] / ta.runs[k]);
  return median(ratios);
}

/// measure() of a bind that was not refused.
Quality measured(const Timed& t, const LeakProbe* probe) { return t.refused.empty() ? measure(t.session, probe) : Quality{}; }

/// ratio ≤ 0: no ratio column.
void row(const char* backend, const std::string& name, const Timed& t, const Quality& q, double ratio) {
  if (!t.refused.empty()) {
    std::printf("  %-4s %-14s refused: %.100s\n", backend, name.c_str(), t.refused.c_str());
    return;
  }
  std::printf("  %-4s %-14s %8.0f %8ld %6.2f-%-6.2f %9.1e %9.1e %8.4f", backend, name.c_str(), 1e3 * t.seconds,
              static_cast<long>(t.samples), t.hMin, t.hMax, q.unity, q.reproduction, q.leak);
  if (ratio > 0.0) std::printf(" %7.2fx", ratio);
  std::printf("\n");
  if (std::string_view(backend) != "kc") return;
  // Where the time goes: each stage's median over the runs (BindTimings).
  const auto stage = [&](double app::BindTimings::* m) {
    std::vector<double> v;
    for (const app::BindTimings& b : t.stages) v.push_back(b.*m);
    return 1e3 * median(v);
  };
  std::printf("  %-4s %-14s stages ms: sampling %.0f, kernel %.0f, factor %.0f, init %.0f, optimize %.0f, solve %.0f\n", "",
              "", stage(&app::BindTimings::sampling), stage(&app::BindTimings::assemble), stage(&app::BindTimings::factor),
              stage(&app::BindTimings::init), stage(&app::BindTimings::optimize), stage(&app::BindTimings::solve));
}

/// The picture size a test cage file names ("image_size": [w, h]).
std::pair<int, int> cageImageSize(const std::string& path) {
  const nlohmann::json j = nlohmann::json::parse(app::readTextFile(path, app::kMaxJsonFileBytes));
  return {j.at("image_size").at(0).get<int>(), j.at("image_size").at(1).get<int>()};
}

/// Two discs joined by a neck `neck` px wide (scaled by `scale`), 16 points a disc.
Cage neckCage(double scale, double neck) {
  std::vector<Vec2> p;
  const double half = neck / 2.0, r = 60.0 * scale;
  for (int side = 0; side < 2; ++side) {
    const double cx = (side == 0 ? 90.0 : 230.0) * scale, cy = 120.0 * scale, dir = side == 0 ? 1.0 : -1.0;
    const double joint = cx + dir * std::sqrt(r * r - half * half);
    p.emplace_back(joint, cy + dir * half);
    for (int k = 1; k < 16; ++k) {
      const double t = (side == 0 ? 0.0 : std::numbers::pi) + 2.0 * std::numbers::pi * k / 16.0;
      const Vec2 q(cx + r * std::cos(t), cy + r * std::sin(t));
      if (std::abs(q.y() - cy) > half + scale || dir * (q.x() - cx) < 50.0 * scale) p.push_back(q);
    }
    p.emplace_back(joint, cy - dir * half);
  }
  Points C(Index(p.size()), 2);
  for (std::size_t k = 0; k < p.size(); ++k) C.row(Index(k)) = p[k].transpose();
  return Cage::polygon(C);
}

}  // namespace

void benchGraded(const std::string& folder, int repeats) {
  // What `kcwarp-cli bind` and the GUI do by default: automatic spacing, the exterior band.
  const app::BindParams defaults{};
  std::printf("graded sampling: cages with narrow places (%s) and their gaps widened to 40 px, kcwarp-cli bind's\n"
              "defaults (automatic spacing, --exterior %s), median of %d binds, wide and narrow alternating (/wide:\n"
              "the median of the paired ratios); unity and reproduction: largest error\n"
              "on a 2 px grid inside the cage; leak: largest |sum of the far side's weights| 1-3 px from the gap\n",
              folder.c_str(), nameOf(defaults.exterior).c_str(), repeats);
  std::printf("  %-4s %-14s %8s %8s %13s %9s %9s %8s %8s\n", "", "cage", "bind ms", "samples", "spacing px", "unity",
              "repro px", "leak", "/wide");
  for (const NarrowCase& c : narrowCases()) {
    Bindable wide, narrow;
    for (auto [variant, b] : {std::pair<const char*, Bindable*>{"wide", &wide}, {"narrow", &narrow}}) {
      const std::string path = (std::filesystem::path(folder) / (c.name + "-" + variant + ".cage.json")).string();
      b->cage = app::loadCage(path);
      std::tie(b->w, b->h) = cageImageSize(path);
    }
    for (const char* backend : {"kc", "lbc"}) {
      app::BindParams p = defaults;
      p.backend = backend;
      Timed tw, tn;
      const double ratio = timedPair(wide, narrow, p, repeats, tw, tn);
      row(backend, c.name + "-wide", tw, measured(tw, c.leak ? &c.wide : nullptr), 0.0);
      row(backend, c.name + "-narrow", tn, measured(tn, c.leak ? &c.narrow : nullptr), ratio);
    }
  }
  // One 8 px neck on a 12 MP picture (4000 x 3000, the cage filling it) against the same scene at
  // 0.1 MP (the cage scaled by 1/11, its neck 0.73 px).
  std::printf("\n  one neck, 12 MP against 0.1 MP (kc, defaults):\n");
  const double big = 4000.0 / 330.0, small = big / 11.0;
  Timed t01, t12;
  const double ratio = timedPair({neckCage(small, 8.0 / 11.0), 364, 273}, {neckCage(big, 8.0), 4000, 3000}, defaults, repeats, t01, t12);
  row("kc", "neck 0.1 MP", t01, measured(t01, nullptr), 0.0);
  row("kc", "neck 12 MP", t12, measured(t12, nullptr), ratio);
}

void benchBackends(const std::vector<std::string>& cages, int repeats) {
  std::printf(
      "backends: each cage bound with kcwarp-cli bind's defaults by kc and by lbc (automatic spacing for each),\n"
      "median of %d binds alternating kc, lbc; lbc/kc: the median of the paired ratios\n",
      repeats);
  std::printf("  %-10s %8s %8s %8s %8s %10s %8s\n", "cage", "kc ms", "samples", "lbc ms", "vertices", "iterations", "lbc/kc");
  for (const std::string& path : cages) {
    Bindable b;
    b.cage = app::loadCage(path);
    std::filesystem::path picture(path);
    picture.replace_extension().replace_extension(".png");  // x.cage.json → x.png
    if (std::filesystem::exists(picture)) {
      const Image image = app::loadImage(picture.string());
      b.w = image.width, b.h = image.height;
    } else if (nlohmann::json::parse(app::readTextFile(path, app::kMaxJsonFileBytes)).contains("image_size")) {
      std::tie(b.w, b.h) = cageImageSize(path);
    } else {  // no picture named: the cage's bounding box and 40 px round it
      b.w = int(std::ceil(b.cage.C.col(0).maxCoeff())) + 40, b.h = int(std::ceil(b.cage.C.col(1).maxCoeff())) + 40;
    }
    app::BindParams kc, lbc;
    lbc.backend = "lbc";
    Timed tk, tl;
    const double ratio = timedPair(b, b, kc, repeats, tk, tl, &lbc);
    const std::string name = std::filesystem::path(path).filename().string();
    const std::string shortName = name.substr(0, name.find('.'));
    if (!tk.refused.empty() || !tl.refused.empty()) {
      std::printf("  %-10s refused: %.100s\n", shortName.c_str(), (tk.refused.empty() ? tl.refused : tk.refused).c_str());
      continue;
    }
    nlohmann::json report = nlohmann::json::object();
    if (tl.session.report.backend) tl.session.report.backend->toJson(report, false);
    std::printf("  %-10s %8.0f %8ld %8.0f %8ld %10d %7.2fx\n", shortName.c_str(), 1e3 * tk.seconds, static_cast<long>(tk.samples),
                1e3 * tl.seconds, static_cast<long>(report.value("mesh_vertices", Index{0})), report.value("iterations", 0),
                ratio);
  }
}

}  // namespace kc::cli
