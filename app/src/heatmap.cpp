#include "kc/app/heatmap.h"
#include "kc/app/pipeline.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace kc::app {
namespace {

cv::Mat wrap(Image& image) { return cv::Mat(image.height, image.width, CV_8UC4, image.rgba.data()); }
cv::Scalar scalar(Rgba c) { return cv::Scalar(c.r, c.g, c.b, c.a); }
cv::Point toPoint(double x, double y) { return cv::Point(int(std::lround(x * 16)), int(std::lround(y * 16))); }
constexpr int kShift = 4;  // sub-pixel bits for cv drawing

std::string tickText(double v, HeatScale scale) {
  char buf[32];
  if (scale == HeatScale::Log) std::snprintf(buf, sizeof buf, "1e%d", int(std::lround(v)));
  else std::snprintf(buf, sizeof buf, "%.3g", std::abs(v) < 1e-12 ? 0.0 : v);
  return buf;
}

std::vector<cv::Point> polygonPoints(const Points& P) {
  std::vector<cv::Point> pts;
  for (Index i = 0; i < P.rows(); ++i) pts.push_back(toPoint(P(i, 0), P(i, 1)));
  return pts;
}

void drawPolygon(Image& image, const Cage& cage, const Points& P, Rgba color, const OverlayStyle& style) {
  cv::Mat m = wrap(image);
  const std::vector<cv::Point> pts = polygonPoints(P);
  if (cage.closed && cage.edges.empty()) {
    cv::polylines(m, pts, true, scalar(color), style.thickness, cv::LINE_AA, kShift);
  } else {
    for (const auto& e : cage.edges)
      cv::line(m, pts[std::size_t(e[0])], pts[std::size_t(e[1])], scalar(color), style.thickness, cv::LINE_AA, kShift);
  }
  if (style.pointRadius > 0)
    for (const auto& p : pts) cv::circle(m, p, style.pointRadius << kShift, scalar(color), cv::FILLED, cv::LINE_AA, kShift);
}

}  // namespace

Rgba heatColor(double t) {
  static constexpr std::array<std::array<double, 3>, 5> kAnchors{
      {{68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}}};
  t = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0) * (kAnchors.size() - 1);
  const std::size_t k = std::min<std::size_t>(std::size_t(t), kAnchors.size() - 2);
  const double f = t - double(k);
  Rgba c{0, 0, 0, 255};
  std::uint8_t* out[3] = {&c.r, &c.g, &c.b};
  for (int ch = 0; ch < 3; ++ch)
    *out[ch] = static_cast<std::uint8_t>(std::lround(kAnchors[k][std::size_t(ch)] * (1 - f) + kAnchors[k + 1][std::size_t(ch)] * f));
  return c;
}

Image colorizeField(const RowMatrix& V, const HeatmapOptions& options, const std::string& title,
                    HeatmapReport* report) {
  const int w = int(V.cols()), h = int(V.rows());
  if (w <= 0 || h <= 0) throw std::invalid_argument("heatmap: empty field");
  HeatmapReport rep;
  rep.minValue = V.minCoeff();
  rep.maxValue = V.maxCoeff();
  // Map value → t ∈ [0, 1].
  double lo, hi;
  if (options.scale == HeatScale::Log) {
    if (!(options.logFloor > 0)) throw std::invalid_argument("heatmap: log floor must be positive");
    lo = std::log10(options.logFloor);
    hi = std::max(std::log10(std::max(rep.maxValue, options.logFloor)), lo + 1.0);
    rep.lowEnd = options.logFloor;
    rep.highEnd = std::pow(10.0, hi);
  } else if (options.minValue < options.maxValue) {
    lo = rep.lowEnd = options.minValue;
    hi = rep.highEnd = options.maxValue;
  } else {
    lo = rep.lowEnd = std::min(0.0, rep.minValue);
    hi = rep.highEnd = std::max(rep.maxValue, lo + 1e-12);
  }
  const auto toT = [&](double v) {
    if (options.scale == HeatScale::Log) v = std::log10(std::max(v, options.logFloor));
    return (v - lo) / (hi - lo);
  };
  const int bar = options.colorBar ? 100 : 0;
  Image out(w + bar, h, Rgba{255, 255, 255, 255});
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Rgba c = heatColor(toT(V(y, x)));
      std::copy_n(&c.r, 4, out.pixel(x, y));
    }
  if (bar > 0) {
    cv::Mat m = wrap(out);
    const int top = std::min(24, h / 8), bottom = h - std::min(12, h / 16), x0 = w + 10, x1 = w + 26;
    for (int y = top; y <= bottom; ++y) {
      const Rgba c = heatColor(double(bottom - y) / std::max(1, bottom - top));
      cv::line(m, {x0, y}, {x1, y}, scalar(c), 1);
    }
    cv::rectangle(m, {x0, top}, {x1, bottom}, cv::Scalar(0, 0, 0, 255), 1);
    const double fs = std::clamp(h / 700.0, 0.3, 0.5);
    const int ticks = options.scale == HeatScale::Log ? int(std::lround(hi - lo)) : 4;
    for (int k = 0; k <= ticks; ++k) {
      const double f = double(k) / ticks;
      const int y = int(std::lround(bottom - f * (bottom - top)));
      cv::line(m, {x1, y}, {x1 + 4, y}, cv::Scalar(0, 0, 0, 255), 1);
      cv::putText(m, tickText(lo + f * (hi - lo), options.scale), {x1 + 6, y + 4}, cv::FONT_HERSHEY_SIMPLEX, fs,
                  cv::Scalar(0, 0, 0, 255), 1, cv::LINE_AA);
    }
    if (top >= 12)
      cv::putText(m, title, {w + 4, top - 8}, cv::FONT_HERSHEY_SIMPLEX, fs, cv::Scalar(0, 0, 0, 255), 1, cv::LINE_AA);
  }
  if (report) *report = rep;
  return out;
}

Image weightHeatmap(const WeightFunction& weightsAt, const Cage& cage, int width, int height, Index control,
                    const HeatmapOptions& options, HeatmapReport* report) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("heatmap: image size must be positive");
  if (control < 0 || (cage.size() > 0 && control >= cage.size()))
    throw std::invalid_argument("heatmap: control point " + std::to_string(control) + " does not exist (the cage has " +
                                std::to_string(cage.size()) + ")");
  const int step = std::max(1, options.gridStep);
  const int gx = (width - 1 + step - 1) / step + 1, gy = (height - 1 + step - 1) / step + 1;
  Points P(Index(gx) * gy, 2);
  for (int j = 0; j < gy; ++j)
    for (int i = 0; i < gx; ++i) P.row(Index(j) * gx + i) << std::min(i * step, width - 1), std::min(j * step, height - 1);
  const Weights W = weightsAt(P);
  if (W.rows() != P.rows() || control >= W.cols())
    throw std::invalid_argument("heatmap: the weight function returned the wrong shape");
  // Bilinear interpolation of the grid onto every pixel.
  RowMatrix V(height, width);
  for (int y = 0; y < height; ++y) {
    const int j = std::min(y / step, gy - 2 < 0 ? 0 : gy - 2);
    const double y0 = std::min(j * step, height - 1), y1 = std::min((j + 1) * step, height - 1);
    const double fy = y1 > y0 ? (y - y0) / (y1 - y0) : 0.0;
    const int j1 = std::min(j + 1, gy - 1);
    for (int x = 0; x < width; ++x) {
      const int i = std::min(x / step, gx - 2 < 0 ? 0 : gx - 2);
      const double x0 = std::min(i * step, width - 1), x1 = std::min((i + 1) * step, width - 1);
      const double fx = x1 > x0 ? (x - x0) / (x1 - x0) : 0.0;
      const int i1 = std::min(i + 1, gx - 1);
      const auto w = [&](int a, int b) { return W(Index(b) * gx + a, control); };
      V(y, x) = (1 - fy) * ((1 - fx) * w(i, j) + fx * w(i1, j)) + fy * ((1 - fx) * w(i, j1) + fx * w(i1, j1));
    }
  }
  HeatmapReport rep;
  Image out = colorizeField(V, options, "w" + std::to_string(control), &rep);
  rep.points = P.rows();
  if (options.drawCage && cage.size() > 0) {
    OverlayStyle style;
    drawCage(out, cage, Rgba{255, 255, 255, 255}, style, control);
  }
  if (report) *report = rep;
  return out;
}

Image weightHeatmap(const Session& session, Index control, const HeatmapOptions& options, HeatmapReport* report) {
  if (!session.hasField()) throw std::invalid_argument("heatmap: the session has no coordinate field");
  // A session sampled in a band around the cage has no weights beyond it (the field there is only
  // its affine extrapolation): those points show 0, as outside a mesh field's domain.
  const bool band = session.params.exterior == sampling::ExteriorExtent::Band;
  const sampling::Rect region =
      band ? sampling::sampledRegion(session.cage, samplingOptions(session.imageWidth, session.imageHeight, session.params))
           : sampling::Rect{};
  return weightHeatmap(
      [&](const Points& P) {
        Weights W = session.field->weightsAt(P);
        if (band)
          for (Index i = 0; i < P.rows(); ++i)
            if (!region.contains(P.row(i))) W.row(i).setZero();
        return W;
      },
      session.cage, session.imageWidth, session.imageHeight, control, options, report);
}

Rgba sampleColor(SampleKind kind) {
  switch (kind) {
    case SampleKind::Control: return {230, 30, 30, 255};
    case SampleKind::Edge: return {255, 150, 0, 255};
    case SampleKind::Line: return {220, 0, 220, 255};
    case SampleKind::Interior: return {40, 90, 255, 255};
    case SampleKind::Exterior: return {150, 150, 150, 255};
  }
  return {0, 0, 0, 255};
}

void drawCage(Image& image, const Cage& cage, Rgba color, const OverlayStyle& style, Index highlight) {
  image.validate();
  drawPolygon(image, cage, cage.C, color, style);
  if (highlight >= 0 && highlight < cage.size()) {
    cv::Mat m = wrap(image);
    const cv::Point p = toPoint(cage.C(highlight, 0), cage.C(highlight, 1));
    cv::circle(m, p, (style.pointRadius + 4) << kShift, cv::Scalar(230, 30, 30, 255), 2, cv::LINE_AA, kShift);
  }
}

void drawDeformedCage(Image& image, const Cage& cage, const Points& P, const OverlayStyle& style) {
  image.validate();
  if (P.rows() != cage.size()) throw std::invalid_argument("overlay: deformed cage has the wrong number of points");
  drawPolygon(image, cage, P, style.deformedCage, style);
}

void drawDeformedLines(Image& image, const Session& session, const Pose& pose, const OverlayStyle& style) {
  drawDeformedLines(image, session, session.structure.lines, pose, style);
  if (session.structure.rigid.empty() || !session.hasField()) return;
  cv::Mat m = wrap(image);
  constexpr Index kPerEdge = 16;
  for (const RigidRegion& r : session.structure.rigid) {
    const Index n = r.polygon.rows();
    Points P(n * kPerEdge, 2);
    for (Index e = 0; e < n; ++e)
      for (Index k = 0; k < kPerEdge; ++k) {
        const double t = double(k) / double(kPerEdge);
        P.row(e * kPerEdge + k) = (1.0 - t) * r.polygon.row(e) + t * r.polygon.row((e + 1) % n);
      }
    const Points Q = pose.empty() ? P : deformPoints(session.field->weightsAt(P), P, session.cage.C, pose);
    cv::polylines(m, polygonPoints(Q), true, scalar(style.rigid), style.thickness + 1, cv::LINE_AA, kShift);
  }
}

void drawDeformedLines(Image& image, const Session& session, std::span<const StructureLine> lines, const Pose& pose,
                       const OverlayStyle& style) {
  image.validate();
  if (lines.empty() || !session.hasField()) return;
  cv::Mat m = wrap(image);
  constexpr Index kPoints = 65;
  for (const StructureLine& l : lines) {
    Points P(kPoints, 2);
    for (Index k = 0; k < kPoints; ++k) {
      const double t = double(k) / double(kPoints - 1);
      P.row(k) = ((1.0 - t) * l.a + t * l.b).transpose();
    }
    const Points Q = pose.empty() ? P : deformPoints(session.field->weightsAt(P), P, session.cage.C, pose);
    cv::polylines(m, polygonPoints(Q), false, scalar(style.line), style.thickness + 1, cv::LINE_AA, kShift);
  }
}

void drawSamples(Image& image, const SampleSet& samples, const OverlayStyle& style) {
  image.validate();
  cv::Mat m = wrap(image);
  for (Index s = 0; s < samples.size(); ++s) {
    const SampleKind k = s < Index(samples.kind.size()) ? samples.kind[std::size_t(s)] : SampleKind::Interior;
    const int r = k == SampleKind::Control ? style.sampleRadius + 2 : style.sampleRadius;
    cv::circle(m, toPoint(samples.X(s, 0), samples.X(s, 1)), r << kShift, scalar(sampleColor(k)), cv::FILLED,
               cv::LINE_AA, kShift);
  }
}

}  // namespace kc::app
