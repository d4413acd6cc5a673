// Structure lines in the kernel backend (thesis 5.3.3).

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <random>
#include <stdexcept>

#include "backends.h"
#include "kc/app/export.h"
#include "kc/app/line_metrics.h"
#include "kc/core/deform.h"
#include "kc/core/field/line_correction.h"
#include "kc/core/structure/line_blend.h"
#include "kc/core/structure/lines.h"
#include "kc/core/structure/rigidity.h"
#include "kc/core/warp_mesh.h"

namespace kc::app {
namespace {

/// Edge linearization (`--linear-edges`): nodes within 4σ of an edge (a wider reach than the
/// lines' 2.5σ, which left the edges less linear with a deeper negative lobe) and two sweeps, which
/// settle the corners two edges share. The samples around an edge are held softly at a third of
/// the lines' weight: the lobe halves and the edges stay within a third of a 1e-3 linearity.
const LinearityOptions kEdgeLinearity = [] {
  LinearityOptions o;
  o.reach = 4.0;
  o.sweeps = 2;
  o.freeWeight = 0.001;
  return o;
}();

/// The largest L1 distance of the field's weights from linear between the ends, over 101 points
/// along each line.
double lineMisfit(const KernelField& field, std::span<const StructureLine> lines) {
  constexpr Index kPoints = 101;
  double worst = 0.0;
  for (const StructureLine& l : lines) {
    const Weights W = field.weightsAt(lineSamplePoints(l, l.length() / double(kPoints - 1)));
    const Index last = W.rows() - 1;
    for (Index k = 0; k <= last; ++k) {
      const double t = double(k) / double(last);
      worst = std::max(worst, (W.row(k) - (1.0 - t) * W.row(0) - t * W.row(last)).cwiseAbs().sum());
    }
  }
  return worst;
}

}  // namespace

void installLineCorrection(const Session& s, KernelField& field) {
  if (!s.params.kc.exactLines || s.structure.lines.empty()) {
    field.setLineCorrection(nullptr);
    return;
  }
  const std::vector<StructureLine>& lines = s.structure.lines;
  std::vector<Points> rigid;  // the rigid regions keep the weights the rigidity QP gives them
  for (const RigidRegion& r : s.structure.rigid)
    if (r.strength > 0.0) rigid.push_back(r.polygon);
  field.setLineCorrection(std::make_shared<LineCorrection>(s.cage, lines, lineContacts(lines), s.sigma, rigid));
}

LinearityReport applyLines(Session& s, KernelField& field) {
  const std::vector<StructureLine>& lines = s.structure.lines;
  const bool edges = s.params.kc.linearEdges;
  field.setLineCorrection(nullptr);  // the post-processing reads the field of the weights alone
  if (lines.empty() && !edges) return {};
  std::vector<char> keep(static_cast<std::size_t>(s.samples.size()), 0);
  for (Index i = 0; i < s.samples.size(); ++i) {
    const SampleKind k = s.samples.kind[static_cast<std::size_t>(i)];
    keep[static_cast<std::size_t>(i)] = k == SampleKind::Control || k == SampleKind::Edge || k == SampleKind::Line;
  }
  LinearityReport edgeReport;
  if (edges) {  // the loops' edges, from control a's Lagrange weights to control b's (4.7); not the sticks
    std::vector<LinearSegment> segments;
    const Index m = s.cage.size();
    for (const auto& [a, b] : loopEdges(s.cage))
      segments.push_back({s.cage.C.row(a).transpose(), s.cage.C.row(b).transpose(), Eigen::RowVectorXd::Unit(m, a),
                          Eigen::RowVectorXd::Unit(m, b)});
    edgeReport = makeLinearAlong(field, segments, keep, s.W, kEdgeLinearity);  // leaves field holding s.W
  }
  if (lines.empty()) return edgeReport;
  if (s.params.kc.exactLines) {  // field holds s.W: the correction is all there is to do
    const auto t0 = std::chrono::steady_clock::now();
    LinearityReport r = edgeReport;
    r.before = lineMisfit(field, lines);
    installLineCorrection(s, field);
    r.after = lineMisfit(field, lines);
    r.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
  }
  if (s.samples.lines.size() != lines.size())
    throw std::invalid_argument("the session has " + std::to_string(lines.size()) + " lines but samples for " +
                                std::to_string(s.samples.lines.size()));
  std::vector<std::array<Index, 2>> ends;
  for (const auto& idx : s.samples.lines) ends.push_back({idx.front(), idx.back()});
  coupleParallelLines(s.cage.C, lines, ends, s.W);
  const std::vector<LineContact> contacts = lineContacts(lines);
  coupleMeetingLines(contacts, ends, s.W);  // lines that meet agree where they meet
  blendLineNeighbourhoods(s.cage, lines, s.samples, s.sigma, field, s.W);
  for (const auto& idx : s.samples.lines) interpolateLineWeights(s.samples.X, idx, s.W);
  field.update(s.W);

  std::vector<LinearSegment> segments;
  for (std::size_t k = 0; k < lines.size(); ++k) {
    const auto [a, b] = ends[k];
    segments.push_back({s.samples.X.row(a).transpose(), s.samples.X.row(b).transpose(), s.W.row(a), s.W.row(b)});
  }
  LinearityReport r = makeLinearAlong(field, segments, keep, s.W);
  r.seconds += edgeReport.seconds;
  r.adjusted += edgeReport.adjusted;
  r.changedRows += edgeReport.changedRows;
  r.fitPoints += edgeReport.fitPoints;
  return r;
}

}  // namespace kc::app

namespace kc::app {

std::vector<Points> randomTranslations(Index m, int trials, double maxTranslation, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-maxTranslation, maxTranslation);
  std::vector<Points> poses;
  for (int t = 0; t < trials; ++t) {
    Points T(m, 2);
    for (Index i = 0; i < m; ++i) T.row(i) << u(rng), u(rng);
    poses.push_back(std::move(T));
  }
  return poses;
}

FoldFigures measureFolds(const Session& s, int trials, double maxTranslation, std::uint64_t seed) {
  if (!s.hasField()) throw std::invalid_argument("measureFolds: the session has no field");
  FoldFigures f;
  WarpMesh mesh = buildWarpMesh(s, warpMeshOptionsFor(s, OutsideMode::Fixed));  // the inside alone: no background repair
  f.minJacobian = 1.0;
  for (const Points& T : randomTranslations(s.cage.size(), trials, maxTranslation, seed)) {
    const DeformReport r = mesh.deform(poseFromPositions(s.cage.C, s.cage.C + T));
    f.foldedPoses += r.flippedTriangles > 0;
    f.flipped += r.flippedTriangles;
    f.minJacobian = std::min(f.minJacobian, r.minJacobian);
  }
  return f;
}

LineFigures measureLines(const Session& s, const std::vector<StructureLine>& lines, int trials, double maxTranslation,
                         std::uint64_t seed) {
  LineFigures f;
  if (!s.hasField()) throw std::invalid_argument("measureLines: the session has no field");
  constexpr Index kPoints = 301;
  std::vector<Points> P;
  std::vector<Weights> W;
  for (const StructureLine& l : lines) {
    Points Q = lineSamplePoints(l, l.length() / double(kPoints - 1));
    W.push_back(s.field->weightsAt(Q));
    f.unity = std::max(f.unity, (W.back().rowwise().sum().array() - 1.0).abs().maxCoeff());
    f.reproduction = std::max(f.reproduction, (W.back() * s.cage.C - Q).cwiseAbs().maxCoeff());
    P.push_back(std::move(Q));
  }
  for (const Points& T : randomTranslations(s.cage.size(), trials, maxTranslation, seed)) {
    std::vector<Vec2> dirs(lines.size());
    for (std::size_t k = 0; k < lines.size(); ++k) f.deviation = std::max(f.deviation, translatedLineDeviation(P[k], W[k], T, &dirs[k]));
    for (std::size_t k = 0; k < lines.size(); ++k)
      for (std::size_t j = 0; j < k; ++j)
        if (lines[k].group >= 0 && lines[k].group == lines[j].group) {
          const double c = std::abs(dirs[k].normalized().dot(dirs[j].normalized()));
          f.angle = std::max(f.angle, std::acos(std::min(1.0, c)) * 180.0 / std::numbers::pi);
        }
  }
  return f;
}

}  // namespace kc::app
