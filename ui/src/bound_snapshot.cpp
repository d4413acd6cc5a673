#include "kc/ui/bound_snapshot.h"

#include "kc/core/sizing.h"

namespace kc::ui {
namespace {

/// The session's structure lines as drawn: with exact lines (the field is linear along each line)
/// their ends, else their samples; with the weights there.
std::vector<BoundLine> structureLines(const app::Session& s) {
  std::vector<BoundLine> out;
  if (s.params.kc.exactLines && s.hasField()) {
    for (const StructureLine& l : s.structure.lines) {
      BoundLine b;
      b.X.resize(2, 2);
      b.X << l.a.transpose(), l.b.transpose();
      b.W = s.field->weightsAt(b.X);
      b.group = l.group;
      out.push_back(std::move(b));
    }
    return out;
  }
  if (s.samples.lines.size() != s.structure.lines.size() || s.W.rows() != s.samples.size()) return out;
  for (std::size_t k = 0; k < s.structure.lines.size(); ++k) {
    const auto& idx = s.samples.lines[k];
    BoundLine b;
    b.X.resize(static_cast<Index>(idx.size()), 2);
    b.W.resize(static_cast<Index>(idx.size()), s.W.cols());
    for (std::size_t i = 0; i < idx.size(); ++i) {
      b.X.row(static_cast<Index>(i)) = s.samples.X.row(idx[i]);
      b.W.row(static_cast<Index>(i)) = s.W.row(idx[i]);
    }
    b.group = s.structure.lines[k].group;
    out.push_back(std::move(b));
  }
  return out;
}

/// Each rigid polygon's outline: 16 points per edge, closed, with the field's weights there.
std::vector<BoundLine> rigidOutlines(const app::Session& s) {
  std::vector<BoundLine> out;
  if (!s.hasField()) return out;
  constexpr int kPerEdge = 16;
  for (const RigidRegion& r : s.structure.rigid) {
    const Index n = r.polygon.rows();
    if (n < 3) continue;
    BoundLine outline;
    outline.X.resize(n * kPerEdge + 1, 2);
    for (Index k = 0; k < n; ++k)
      for (int j = 0; j < kPerEdge; ++j)
        outline.X.row(k * kPerEdge + j) =
            r.polygon.row(k) + (r.polygon.row((k + 1) % n) - r.polygon.row(k)) * (double(j) / kPerEdge);
    outline.X.row(n * kPerEdge) = r.polygon.row(0);
    try {
      outline.W = s.field->weightsAt(outline.X);
    } catch (const std::exception&) {
      continue;
    }
    out.push_back(std::move(outline));
  }
  return out;
}

}  // namespace

std::shared_ptr<const BoundSnapshot> makeBoundSnapshot(const app::Session& s, const BoundSnapshot* previous) {
  auto b = std::make_shared<BoundSnapshot>();
  b->cage = s.cage;
  b->samples = s.samples;
  const bool sameSamples = previous && previous->samples.X.rows() == s.samples.X.rows() && previous->samples.X == s.samples.X &&
                           previous->spacing == s.params.spacing;
  b->sampleSpacing = sameSamples ? previous->sampleSpacing
                     : s.sizing  ? s.sizing->at(s.samples.X)
                                 : Eigen::VectorXd::Constant(s.samples.size(), s.params.spacing);
  b->spacing = s.params.spacing;
  b->minSpacing = s.sizing ? s.sizing->hMin() : s.params.spacing;
  b->sigma = s.report.meshVertices() > 0 ? 0.0 : s.sigma;
  b->method = s.params.kc.method;
  b->capabilities = app::sessionCapabilities(s);
  b->report = s.report;
  b->lines = structureLines(s);
  b->rigidOutlines = rigidOutlines(s);
  b->rigidity = s.rigidity;
  return b;
}

}  // namespace kc::ui
