#include "kc/core/kernel/gaussian_kernel.h"

#include <numbers>
#include <stdexcept>

namespace kc {

GaussianKernel GaussianKernel::forSpacing(double sigma, double T) {
  if (!(sigma > 0.0) || !std::isfinite(sigma)) throw std::invalid_argument("Gaussian kernel: sigma must be positive and finite");
  if (!(T > 0.0) || !std::isfinite(T)) throw std::invalid_argument("Gaussian kernel: sample spacing must be positive and finite");
  GaussianKernel k;
  k.sigma = sigma;
  // Continuous limit of (3.30): Σ_j G_σ(x − x_j) ≈ (1/T²) ∫ G_σ = 2πσ²/T².
  k.scale = T * T / (2.0 * std::numbers::pi * sigma * sigma);
  return k;
}

double GaussianKernel::widthAt(const Vec2& x, Vec2& gradient) const {
  if (!variable()) {
    gradient.setZero();
    return sigma;
  }
  const double f = sigma / width->hMax();
  const double h = width->profile(x, &gradient);
  gradient *= f;
  return f * h;
}

Eigen::VectorXd GaussianKernel::widthsAt(const Points& X) const {
  if (!variable()) return Eigen::VectorXd::Constant(X.rows(), sigma);
  return (sigma / width->hMax()) * width->profileAt(X);
}

}  // namespace kc
