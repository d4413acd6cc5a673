#pragma once
// A reference peer for the benchmarks: the grid-based rigid moving-least-squares image warp
// (Schaefer, McPhail, Warren 2006, "Image deformation using moving least squares", section 2.3),
// the way point-based MLS warping tools run it: the backward map (from the posed points to the rest
// points) is evaluated at the nodes of a grid of `gridSize` pixels, interpolated bilinearly at the
// pixels, and the picture is resampled with cv::remap. Weights w_i = 1/|p_i − v|^(2α).
//
// In complex numbers the rigid MLS map is f(v) = (v − p*)·S/|S| + q*, with p*, q* the weighted
// centroids and S = Σ_i w_i conj(p̂_i) q̂_i (p̂ = p − p*, q̂ = q − q*): the normalized similarity
// of section 2.2, which is the rigid map of 2.3 written with complex numbers.
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <complex>
#include <vector>

namespace kc::bench {

using Complex = std::complex<double>;

/// Rigid MLS at v with handles p → q.
inline Complex rigidMls(const std::vector<Complex>& p, const std::vector<Complex>& q, Complex v, double alpha) {
  double sw = 0.0;
  Complex ps = 0.0, qs = 0.0;
  std::vector<double> w(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double d2 = std::norm(p[i] - v);
    if (d2 < 1e-12) return q[i];
    w[i] = 1.0 / std::pow(d2, alpha);
    sw += w[i];
    ps += w[i] * p[i];
    qs += w[i] * q[i];
  }
  ps /= sw;
  qs /= sw;
  Complex s = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) s += w[i] * std::conj(p[i] - ps) * (q[i] - qs);
  const double n = std::abs(s);
  return n > 0.0 ? (v - ps) * (s / n) + qs : v - ps + qs;
}

/// The picture warped so that the points `from` move to `to` (rest and posed positions, pixels).
inline cv::Mat rigidMlsWarp(const cv::Mat& image, const std::vector<Complex>& from, const std::vector<Complex>& to,
                            int gridSize = 5, double alpha = 1.0) {
  const int w = image.cols, h = image.rows;
  const int gx = (w - 1) / gridSize + 2, gy = (h - 1) / gridSize + 2;
  cv::Mat nodeX(gy, gx, CV_32F), nodeY(gy, gx, CV_32F);
  for (int j = 0; j < gy; ++j)
    for (int i = 0; i < gx; ++i) {
      const Complex s = rigidMls(to, from, Complex(i * gridSize, j * gridSize), alpha);  // output node → source
      nodeX.at<float>(j, i) = float(s.real());
      nodeY.at<float>(j, i) = float(s.imag());
    }
  cv::Mat mapX(h, w, CV_32F), mapY(h, w, CV_32F);
  for (int y = 0; y < h; ++y) {
    const int j = y / gridSize;
    const float fy = float(y - j * gridSize) / float(gridSize);
    for (int x = 0; x < w; ++x) {
      const int i = x / gridSize;
      const float fx = float(x - i * gridSize) / float(gridSize);
      const auto lerp = [&](const cv::Mat& m) {
        const float a = m.at<float>(j, i) * (1 - fx) + m.at<float>(j, i + 1) * fx;
        const float b = m.at<float>(j + 1, i) * (1 - fx) + m.at<float>(j + 1, i + 1) * fx;
        return a * (1 - fy) + b * fy;
      };
      mapX.at<float>(y, x) = lerp(nodeX);
      mapY.at<float>(y, x) = lerp(nodeY);
    }
  }
  cv::Mat out;
  cv::remap(image, out, mapX, mapY, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
  return out;
}

}  // namespace kc::bench
