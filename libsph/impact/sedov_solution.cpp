#include "libsph/impact/sedov_solution.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

namespace sph {

SedovSolution::SedovSolution(int geometry, double gamma, double energy, double density)
    : j_(geometry), gamma_(gamma), energy_(energy), rho0_(density) {
  if (geometry < 1 || geometry > 3)
    throw std::invalid_argument("Sedov solution: geometry = " + std::to_string(geometry) +
                                " must be 1 (planar), 2 (cylindrical) or 3 (spherical)");
  if (!(gamma > 1) || !std::isfinite(gamma))
    throw std::invalid_argument("Sedov solution: gamma = " + std::to_string(gamma) + " must be > 1");
  if (std::abs(gamma - 2) < 1e-6)
    throw std::invalid_argument("Sedov solution: gamma = " + std::to_string(gamma) +
                                " is within 1e-6 of 2, a special case (limiting form) not implemented");
  if (geometry == 3 && !(gamma < 7))
    throw std::invalid_argument("Sedov solution: gamma = " + std::to_string(gamma) +
                                " must be < 7 in spherical geometry (singular and vacuum cases not implemented)");
  if (!(energy > 0) || !std::isfinite(energy))
    throw std::invalid_argument("Sedov solution: energy E = " + std::to_string(energy) + " must be > 0");
  if (!(density > 0) || !std::isfinite(density))
    throw std::invalid_argument("Sedov solution: density rho0 = " + std::to_string(density) + " must be > 0");

  const double g = gamma, j = geometry;
  a_ = (j + 2) * (g + 1) / 4;
  b_ = (g + 1) / (g - 1);
  c_ = (j + 2) * g / 2;
  e_ = (2 + j * (g - 1)) / 2;
  d_ = (j + 2) * (g + 1) / ((j + 2) * (g + 1) - 2 * (2 + j * (g - 1)));
  a0_ = 2 / (j + 2);
  a2_ = -(g - 1) / (2 * (g - 1) + j);
  a3_ = j / (2 * (g - 1) + j);
  a5_ = -2 / (2 - g);
  a1_ = (j + 2) * g / (2 + j * (g - 1)) * (2 * j * (2 - g) / (g * (j + 2) * (j + 2)) - a2_);
  a4_ = (j + 2) * a1_ / (2 - g);
  v0_ = 2 / ((j + 2) * g);
  v2_ = 4 / ((j + 2) * (g + 1));

  // alpha by tanh-sinh quadrature over w = v - v0 in (0, W]: w = W / (1 + exp(-pi sinh t)). The
  // integrand has an integrable algebraic singularity at w = 0 (dlambda/dw ~ w^(-a2 - 1)), which the
  // double-exponential map absorbs.
  const double W = v2_ - v0_, log_W = std::log(W);
  const double surface = j_ == 3 ? 4 * std::numbers::pi : j_ == 2 ? 2 * std::numbers::pi : 2.0;
  const double pressure_factor = 8 / ((g * g - 1) * (j + 2) * (j + 2));
  const double h = 1.0 / 64, t_max = 4.5;
  double sum = 0;
  for (int k = -static_cast<int>(t_max / h); k <= static_cast<int>(t_max / h); ++k) {
    const double t = k * h, y = std::numbers::pi * std::sinh(t);
    const double log_w = log_W - std::log1p(std::exp(-y));
    // dw/dt = W sigma (1 - sigma) pi cosh t, sigma = 1 / (1 + exp(-y)).
    const double sigma_complement = 1 / (1 + std::exp(y));  // 1 - sigma
    const double dw_dt = std::exp(log_w) * sigma_complement * std::numbers::pi * std::cosh(t);
    const Similarity s = similarity(log_w);
    const double lambda = std::exp(s.log_lambda), dlambda_dw = lambda * s.dlog_lambda_dw;
    const double kinetic = 0.5 * b_ * std::exp(s.log_g) * s.v * s.v * std::pow(lambda, j + 1);
    const double internal = pressure_factor * std::exp(s.log_h) * std::pow(lambda, j - 1);
    const double term = (kinetic + internal) * dlambda_dw * dw_dt;
    if (std::isfinite(term)) sum += term;
  }
  alpha_ = surface * h * sum;
  xi0_ = std::pow(alpha_, -1 / (j + 2));
}

SedovSolution::Similarity SedovSolution::similarity(double log_w) const {
  const double w = std::exp(log_w), v = v0_ + w;
  const double log_x1 = std::log(a_ * v);
  const double log_x2 = std::log(b_ * c_) + log_w;  // x2 = b (c v - 1) = b c w, since c v0 = 1
  const double log_x3 = std::log(d_ * (1 - e_ * v));
  const double log_x4 = std::log(b_ * (1 - 0.5 * (j_ + 2) * v));
  Similarity s;
  s.v = v;
  s.log_lambda = -a0_ * log_x1 - a2_ * log_x2 - a1_ * log_x3;
  s.dlog_lambda_dw = -a0_ / v - a2_ / w + a1_ * e_ / (1 - e_ * v);
  s.log_g = a3_ * log_x2 + a4_ * log_x3 + a5_ * log_x4;
  s.log_h = j_ * a0_ * log_x1 + (a4_ - 2 * a1_) * log_x3 + (1 + a5_) * log_x4;
  return s;
}

double SedovSolution::solve_log_w(double log_lambda) const {
  // log lambda increases with w from -inf (centre) to 0 (shock); near the centre it is ~ -a2 log w.
  double hi = std::log(v2_ - v0_), lo = hi - 1;
  for (double step = 1; similarity(lo).log_lambda > log_lambda; step *= 2) lo -= step;
  double u = 0.5 * (lo + hi);
  for (int iteration = 0; iteration < 200; ++iteration) {
    const Similarity s = similarity(u);
    const double f = s.log_lambda - log_lambda;
    if (f > 0) hi = u; else lo = u;
    if (std::abs(f) < 1e-15 * std::max(1.0, std::abs(log_lambda)) || hi - lo < 1e-15 * std::max(1.0, std::abs(u)))
      return u;
    const double slope = s.dlog_lambda_dw * std::exp(u);  // d log lambda / d log w
    double next = u - f / slope;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);  // Newton left the bracket: bisect
    u = next;
  }
  return u;
}

double SedovSolution::shock_radius(double t) const {
  return xi0_ * std::pow(energy_ * t * t / rho0_, 1.0 / (j_ + 2));
}

double SedovSolution::shock_speed(double t) const { return 2 * shock_radius(t) / ((j_ + 2) * t); }

SedovSolution::State SedovSolution::sample(double r, double t) const {
  if (!(t > 0)) throw std::invalid_argument("Sedov solution: time t = " + std::to_string(t) + " must be > 0");
  if (!(r >= 0)) throw std::invalid_argument("Sedov solution: radius r = " + std::to_string(r) + " must be >= 0");
  const double R = shock_radius(t);
  if (r > R) return {rho0_, 0, 0};
  const double U = shock_speed(t), p2 = 2 * rho0_ * U * U / (gamma_ + 1);
  const double log_w = r == R ? std::log(v2_ - v0_)
                       : r == 0 ? -std::numeric_limits<double>::infinity()
                                : solve_log_w(std::log(r / R));
  const Similarity s = similarity(log_w);
  return {rho0_ * b_ * std::exp(s.log_g), s.v * r / t, p2 * std::exp(s.log_h)};
}

}  // namespace sph
