#include "kc/core/structure/lines.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>

namespace kc {
namespace {

std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

std::string lineName(std::size_t k) { return "lines[" + std::to_string(k) + "]"; }

/// Smallest distance from segment a–b to any cage edge.
double segmentToCage(const Cage& cage, const Vec2& a, const Vec2& b) {
  double d = std::numeric_limits<double>::infinity();
  for (const auto& [i, j] : cageEdges(cage)) d = std::min(d, segmentSegmentDistance(a, b, cage.C.row(i), cage.C.row(j)));
  return d;
}

double angleDegrees(const Vec2& u, const Vec2& v) {
  const double c = std::abs(u.normalized().dot(v.normalized()));
  return std::acos(std::min(1.0, c)) * 180.0 / std::numbers::pi;
}

}  // namespace

void validateLines(const Cage& cage, std::span<const StructureLine> lines, double h, bool graded) {
  if (lines.empty()) return;
  if (!hasInterior(cage)) throw std::invalid_argument(lineName(0) + ": lines need a closed cage (an open cage has no inside)");
  std::map<int, std::vector<std::size_t>> groups;
  for (std::size_t k = 0; k < lines.size(); ++k) {
    const StructureLine& l = lines[k];
    const std::string name = lineName(k);
    if (!l.a.allFinite() || !l.b.allFinite()) throw std::invalid_argument(name + ": the end points are not finite");
    const double len = l.length();
    if (len == 0.0) throw std::invalid_argument(name + ": the line has zero length (both ends at the same point)");
    if (!graded && len < kMinLineSpacings * h)
      throw std::invalid_argument(name + ": the line is " + num(len) + " px long, shorter than " + num(kMinLineSpacings) +
                                  " sample spacings (" + num(kMinLineSpacings * h) + " px at spacing " + num(h) + ")");
    // A graded bind takes a line ending on the cage (its end becomes that boundary sample).
    const double onEdge = graded ? 1e-9 * std::max(1.0, cage.C.cwiseAbs().maxCoeff()) : -1.0;
    auto inside = [&](const Vec2& p) { return insideCage(cage, p) || distanceToCage(cage, p) <= onEdge; };
    if (!inside(l.a) || !inside(l.b) || !insideCage(cage, 0.5 * (l.a + l.b)) || segmentCrossesCage(cage, l.a, l.b))
      throw std::invalid_argument(name + ": the line (" + num(l.a.x()) + ", " + num(l.a.y()) + ") - (" + num(l.b.x()) + ", " +
                                  num(l.b.y()) + ") is not inside the cage (it lies outside or crosses a cage edge)");
    const double toCage = segmentToCage(cage, l.a, l.b);
    if (!graded && toCage < h)
      throw std::invalid_argument(name + ": the line comes within " + num(toCage) + " px of a cage edge, less than the spacing " +
                                  num(h) + " px");
    for (std::size_t j = 0; j < k && !graded; ++j) {
      const double d = segmentSegmentDistance(l.a, l.b, lines[j].a, lines[j].b);
      if (d == 0.0) throw std::invalid_argument(name + ": the line crosses " + lineName(j));
      if (!graded && d < h)
        throw std::invalid_argument(name + ": the line comes within " + num(d) + " px of " + lineName(j) +
                                    ", less than the spacing " + num(h) + " px");
    }
    if (l.group >= 0) groups[l.group].push_back(k);
  }
  if (graded) lineContacts(lines);  // throws for overlapping lines
  for (const auto& [g, members] : groups) {
    if (members.size() == 1)
      throw std::invalid_argument(lineName(members[0]) + ": its parallel group has no other line (a misspelt group name?)");
    const StructureLine& first = lines[members[0]];
    for (std::size_t k : members) {
      const double angle = angleDegrees(first.b - first.a, lines[k].b - lines[k].a);
      if (angle > kMaxParallelAngleDegrees)
        throw std::invalid_argument(lineName(k) + ": the line is at " + num(angle) + " degrees to " + lineName(members[0]) +
                                    " of its parallel group (at most " + num(kMaxParallelAngleDegrees) + " accepted)");
    }
  }
}

Points lineSamplePoints(const StructureLine& line, double h) {
  const Index pieces = std::max<Index>(1, static_cast<Index>(std::llround(line.length() / h)));
  Points P(pieces + 1, 2);
  for (Index k = 0; k <= pieces; ++k) {
    const double t = static_cast<double>(k) / static_cast<double>(pieces);
    P.row(k) = ((1.0 - t) * line.a + t * line.b).transpose();
  }
  P.row(pieces) = line.b.transpose();
  return P;
}

Points lineSamplePoints(const StructureLine& line, const SizingField& sizing) {
  const std::vector<double> t = segmentDivision(line.a, line.b, sizing);
  const Index pieces = static_cast<Index>(t.size()) - 1;
  Points P(pieces + 1, 2);
  for (Index k = 0; k <= pieces; ++k) P.row(k) = ((1.0 - t[std::size_t(k)]) * line.a + t[std::size_t(k)] * line.b).transpose();
  P.row(pieces) = line.b.transpose();
  return P;
}

void interpolateLineWeights(const Points& X, std::span<const Index> samples, Weights& W) {
  if (samples.size() < 2) throw std::invalid_argument("interpolateLineWeights: a line needs at least its two base points");
  const Index s = samples.front(), e = samples.back();
  const Vec2 a = X.row(s), b = X.row(e);
  const double len2 = (b - a).squaredNorm();
  if (!(len2 > 0.0)) throw std::invalid_argument("interpolateLineWeights: the base points coincide");
  const Eigen::RowVectorXd wa = W.row(s), wb = W.row(e);
  for (std::size_t k = 1; k + 1 < samples.size(); ++k) {
    const Vec2 p = X.row(samples[k]);
    const double t = (p - a).dot(b - a) / len2;  // (5.6): signed distance along a → b over |b − a|
    W.row(samples[k]) = (1.0 - t) * wa + t * wb;
  }
}

std::vector<LineContact> lineContacts(std::span<const StructureLine> lines) {
  double extent = 0.0;
  for (const StructureLine& l : lines) extent = std::max({extent, l.a.cwiseAbs().maxCoeff(), l.b.cwiseAbs().maxCoeff()});
  const double eps = 1e-9 * std::max(extent, 1.0);
  std::vector<LineContact> out;
  for (std::size_t l = 1; l < lines.size(); ++l)
    for (std::size_t k = 0; k < l; ++k) {
      const Vec2 a = lines[k].a, u = lines[k].b - a, c = lines[l].a, v = lines[l].b - c;
      if (segmentSegmentDistance(a, lines[k].b, c, lines[l].b) > eps) continue;
      const double den = u.x() * v.y() - u.y() * v.x();
      if (std::abs(den) <= 1e-12 * u.norm() * v.norm()) {
        // Collinear and touching: one shared point (end to end) is a contact, more an overlap.
        const double s0 = (c - a).dot(u) / u.squaredNorm(), s1 = (lines[l].b - a).dot(u) / u.squaredNorm();
        const double lo = std::max(0.0, std::min(s0, s1)), hi = std::min(1.0, std::max(s0, s1));
        if ((hi - lo) * u.norm() > eps) throw std::invalid_argument(lineName(l) + ": the line overlaps " + lineName(k));
        const Vec2 p = a + lo * u;
        const double tl = std::clamp((p - c).dot(v) / v.squaredNorm(), 0.0, 1.0);
        out.push_back({k, l, lo <= 0.5 ? 0.0 : 1.0, tl <= 0.5 ? 0.0 : 1.0, p});
        continue;
      }
      const Vec2 w = c - a;
      const double tk = std::clamp((w.x() * v.y() - w.y() * v.x()) / den, 0.0, 1.0);
      const double tl = std::clamp((w.x() * u.y() - w.y() * u.x()) / den, 0.0, 1.0);
      // Snap to an end within eps, so that an end on the other line is that end exactly.
      auto snap = [&](double t, double len) { return t * len <= eps ? 0.0 : (1.0 - t) * len <= eps ? 1.0 : t; };
      LineContact lc{k, l, snap(tk, u.norm()), snap(tl, v.norm()), Vec2::Zero()};
      lc.point = 0.5 * (a + lc.tk * u + c + lc.tl * v);
      out.push_back(lc);
    }
  return out;
}

void coupleMeetingLines(std::span<const LineContact> contacts, std::span<const std::array<Index, 2>> ends, Weights& W) {
  for (const LineContact& c : contacts)
    if (c.k >= ends.size() || c.l >= ends.size()) throw std::invalid_argument("coupleMeetingLines: a contact names a line without ends");
  if (contacts.empty()) return;
  // The end samples involved, each once (lines sharing an end share its row), and A (contacts ×
  // ends) with A·W_ends = the contacts' disagreements D.
  std::vector<Index> rows;
  auto column = [&](Index i) {
    const auto at = std::find(rows.begin(), rows.end(), i);
    if (at != rows.end()) return Index(at - rows.begin());
    rows.push_back(i);
    return Index(rows.size() - 1);
  };
  std::vector<std::array<std::pair<Index, double>, 4>> terms;
  for (const LineContact& c : contacts)
    terms.push_back({{{column(ends[c.k][0]), 1.0 - c.tk}, {column(ends[c.k][1]), c.tk},
                      {column(ends[c.l][0]), -(1.0 - c.tl)}, {column(ends[c.l][1]), -c.tl}}});
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(Index(contacts.size()), Index(rows.size()));
  for (Index r = 0; r < A.rows(); ++r)
    for (const auto& [col, coef] : terms[std::size_t(r)]) A(r, col) += coef;
  const Weights E = W(rows, Eigen::all);
  // The least-norm change Δ with A·(E + Δ) = 0; its rows are combinations of the rows of D.
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(A);
  W(rows, Eigen::all) = E - cod.solve((A * E).eval());
}

void coupleParallelLines(const Points& C, std::span<const StructureLine> lines, std::span<const std::array<Index, 2>> ends,
                         Weights& W) {
  if (ends.size() != lines.size()) throw std::invalid_argument("coupleParallelLines: one pair of ends per line");
  const Index m = C.rows();
  if (W.cols() != m) throw std::invalid_argument("coupleParallelLines: W must have one column per control point");
  std::map<int, std::vector<std::size_t>> groups;
  for (std::size_t k = 0; k < lines.size(); ++k)
    if (lines[k].group >= 0) groups[lines[k].group].push_back(k);
  if (groups.empty()) return;
  // M = [1 C] (m×3); the least-norm r with Mᵀr = q is M (MᵀM)⁻¹ q.
  Eigen::MatrixXd M(m, 3);
  M.col(0).setOnes();
  M.rightCols(2) = C;
  const Eigen::LDLT<Eigen::Matrix3d> MtM((M.transpose() * M).eval());
  for (const auto& [g, members] : groups) {
    const Vec2 u1 = (lines[members[0]].b - lines[members[0]].a).normalized();
    Vec2 ubar = Vec2::Zero();
    double total = 0.0;
    for (std::size_t k : members) {
      const double L = lines[k].length();
      const Vec2 u = (lines[k].b - lines[k].a) / L;
      ubar += L * L * (u.dot(u1) < 0.0 ? -1.0 : 1.0) * u;
      total += L * L;
    }
    ubar /= total;
    std::vector<Eigen::RowVectorXd> r(members.size());
    Eigen::RowVectorXd d = Eigen::RowVectorXd::Zero(m);
    for (std::size_t q = 0; q < members.size(); ++q) {
      const StructureLine& l = lines[members[q]];
      const double L = l.length(), s = (l.b - l.a).dot(u1) < 0.0 ? -1.0 : 1.0;
      const Vec2 delta = (l.b - l.a) / L - s * ubar;
      const Eigen::Vector3d rhs(0.0, delta.x(), delta.y());
      r[q] = (M * MtM.solve(rhs)).transpose();
      const auto [ia, ib] = ends[members[q]];
      const Eigen::RowVectorXd dhat = (W.row(ib) - W.row(ia)) / L;
      d += L * L * s * (dhat - r[q]);
    }
    d /= total;
    for (std::size_t q = 0; q < members.size(); ++q) {
      const StructureLine& l = lines[members[q]];
      const double L = l.length(), s = (l.b - l.a).dot(u1) < 0.0 ? -1.0 : 1.0;
      const Eigen::RowVectorXd dl = s * d + r[q];
      const auto [ia, ib] = ends[members[q]];
      const Eigen::RowVectorXd wa = 0.5 * (W.row(ia) + W.row(ib) - L * dl);
      W.row(ia) = wa;
      W.row(ib) = wa + L * dl;
    }
  }
}

double translatedLineDeviation(const Points& P, const Weights& Wp, const Points& T, Vec2* direction) {
  if (P.rows() < 2 || Wp.rows() != P.rows() || Wp.cols() != T.rows())
    throw std::invalid_argument("translatedLineDeviation: P, Wp (one row per point) and T (one row per control) disagree");
  const Points Q = P + Wp * T;
  const Vec2 a = Q.row(0), d = Vec2(Q.row(Q.rows() - 1)) - a;
  if (direction) *direction = d;
  const double len = d.norm();
  double worst = 0.0;
  for (Index k = 0; k < Q.rows(); ++k) {
    const Vec2 v = Vec2(Q.row(k)) - a;
    worst = std::max(worst, len > 0.0 ? std::abs(v.x() * d.y() - v.y() * d.x()) / len : v.norm());
  }
  return worst;
}

std::vector<StructureLine> randomLines(const Cage& cage, int count, double minLength, double maxLength, double h,
                                       std::uint64_t seed, RandomLineLayout layout) {
  std::mt19937_64 rng(seed);
  auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * static_cast<double>(rng() >> 11) * 0x1.0p-53; };
  const double x0 = cage.C.col(0).minCoeff(), x1 = cage.C.col(0).maxCoeff();
  const double y0 = cage.C.col(1).minCoeff(), y1 = cage.C.col(1).maxCoeff();
  const bool graded = layout == RandomLineLayout::Crossing;
  std::vector<StructureLine> lines;
  for (int attempt = 0; attempt < 10000 && static_cast<int>(lines.size()) < count; ++attempt) {
    StructureLine l;
    l.group = -1;
    const double len = uniform(minLength, maxLength);
    Vec2 u;
    if (layout == RandomLineLayout::ParallelPair && lines.size() == 1) {
      u = (lines[0].b - lines[0].a).normalized();
      const Vec2 normal(-u.y(), u.x());
      l.a = 0.5 * (lines[0].a + lines[0].b) + uniform(-4.0, 4.0) * h * normal + uniform(-0.5, 0.5) * len * u;
      if (rng() & 1) u = -u;  // either orientation: the coupling's signs (5.11) matter
      l.a -= 0.5 * len * u;
      l.group = 0;
    } else if (graded && !lines.empty()) {
      const StructureLine& other = lines[std::size_t(rng() % lines.size())];
      const Vec2 v = (other.b - other.a).normalized(), at = other.a + uniform(0.2, 0.8) * (other.b - other.a);
      const double turn = uniform(std::numbers::pi / 6.0, 5.0 * std::numbers::pi / 6.0);
      u = Vec2(std::cos(turn) * v.x() - std::sin(turn) * v.y(), std::sin(turn) * v.x() + std::cos(turn) * v.y());
      l.a = at - uniform(0.2, 0.8) * len * u;
    } else {
      const double angle = uniform(0.0, 2.0 * std::numbers::pi);
      u = Vec2(std::cos(angle), std::sin(angle));
      l.a = Vec2(uniform(x0, x1), uniform(y0, y1));
    }
    l.b = l.a + len * u;
    std::vector<StructureLine> trial = lines;
    trial.push_back(l);
    if (l.group == 0) trial[0].group = 0;
    try {
      validateLines(cage, trial, h, graded);
    } catch (const std::invalid_argument&) {
      continue;
    }
    lines = std::move(trial);
  }
  if (static_cast<int>(lines.size()) < count) throw std::invalid_argument("randomLines: could not place the lines in this cage");
  return lines;
}

}  // namespace kc
