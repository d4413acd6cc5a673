// Structure lines in the kernel backend (thesis 5.3.3).

#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include "backends.h"
#include "kc/app/line_metrics.h"
#include "kc/core/structure/lines.h"

namespace kc::app {

LinearityReport applyLines(Session& s, KernelField& field) {
  const std::vector<StructureLine>& lines = s.structure.lines;
  if (lines.empty()) return {};
  if (s.samples.lines.size() != lines.size())
    throw std::invalid_argument("the session has " + std::to_string(lines.size()) + " lines but samples for " +
                                std::to_string(s.samples.lines.size()));
  std::vector<std::array<Index, 2>> ends;
  for (const auto& idx : s.samples.lines) ends.push_back({idx.front(), idx.back()});
  coupleParallelLines(s.cage.C, lines, ends, s.W);
  for (const auto& idx : s.samples.lines) interpolateLineWeights(s.samples.X, idx, s.W);
  field.update(s.W);

  std::vector<LinearSegment> segments;
  for (std::size_t k = 0; k < lines.size(); ++k) {
    const auto [a, b] = ends[k];
    segments.push_back({s.samples.X.row(a).transpose(), s.samples.X.row(b).transpose(), s.W.row(a), s.W.row(b)});
  }
  std::vector<char> keep(static_cast<std::size_t>(s.samples.size()), 0);
  for (Index i = 0; i < s.samples.size(); ++i) {
    const SampleKind k = s.samples.kind[static_cast<std::size_t>(i)];
    keep[static_cast<std::size_t>(i)] = k == SampleKind::Control || k == SampleKind::Edge || k == SampleKind::Line;
  }
  return makeLinearAlong(field, segments, keep, s.W);
}

}  // namespace kc::app

namespace kc::app {

LineFigures measureLines(const Session& s, const std::vector<StructureLine>& lines, int trials, double maxTranslation,
                         std::uint64_t seed) {
  LineFigures f;
  if (!s.hasField()) throw std::invalid_argument("measureLines: the session has no field");
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-maxTranslation, maxTranslation);
  constexpr Index kPoints = 301;
  std::vector<Points> P;
  std::vector<Weights> W;
  for (const StructureLine& l : lines) {
    Points Q(kPoints, 2);
    for (Index k = 0; k < kPoints; ++k) {
      const double t = double(k) / double(kPoints - 1);
      Q.row(k) = ((1.0 - t) * l.a + t * l.b).transpose();
    }
    W.push_back(s.field->weightsAt(Q));
    f.unity = std::max(f.unity, (W.back().rowwise().sum().array() - 1.0).abs().maxCoeff());
    f.reproduction = std::max(f.reproduction, (W.back() * s.cage.C - Q).cwiseAbs().maxCoeff());
    P.push_back(std::move(Q));
  }
  for (int t = 0; t < trials; ++t) {
    Points T(s.cage.size(), 2);
    for (Index i = 0; i < T.rows(); ++i) T.row(i) << u(rng), u(rng);
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
