#include "libsph/impact/exact_riemann.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sph {

ExactRiemannSolution::ExactRiemannSolution(GasState left, GasState right, double gamma)
    : left_(left), right_(right), gamma_(gamma) {
  if (!(gamma > 1)) throw std::invalid_argument("exact Riemann solution: gamma = " + std::to_string(gamma) + " must be > 1");
  for (const auto* side : {&left_, &right_})
    if (!(side->density > 0) || !(side->pressure > 0) || !std::isfinite(side->velocity))
      throw std::invalid_argument(std::string("exact Riemann solution: the ") + (side == &left_ ? "left" : "right") +
                                  " state (density " + std::to_string(side->density) + ", pressure " +
                                  std::to_string(side->pressure) + ") needs a positive density and pressure");
  c_left_ = std::sqrt(gamma * left.pressure / left.density);
  c_right_ = std::sqrt(gamma * right.pressure / right.density);
  const double du = right.velocity - left.velocity;
  if (2 * (c_left_ + c_right_) / (gamma - 1) <= du)
    throw std::invalid_argument("exact Riemann solution: the states separate at " + std::to_string(du) +
                                ", at least 2 (c_L + c_R) / (gamma - 1) = " +
                                std::to_string(2 * (c_left_ + c_right_) / (gamma - 1)) + ": a vacuum forms");

  // Start: the two-rarefaction estimate (exact when both waves are rarefactions).
  const double z = (gamma - 1) / (2 * gamma);
  double p = std::pow((c_left_ + c_right_ - (gamma - 1) / 2 * du) /
                          (c_left_ / std::pow(left.pressure, z) + c_right_ / std::pow(right.pressure, z)),
                      1 / z);
  for (iterations_ = 1; iterations_ <= 100; ++iterations_) {
    double fl, dfl, fr, dfr;
    pressure_function(p, left_, c_left_, fl, dfl);
    pressure_function(p, right_, c_right_, fr, dfr);
    const double next = std::max(p - (fl + fr + du) / (dfl + dfr), 1e-12 * p);
    const double change = 2 * std::abs(next - p) / (next + p);
    p = next;
    if (change < 1e-14) break;
  }
  if (iterations_ > 100) throw std::runtime_error("exact Riemann solution: Newton's method did not converge for p*");
  p_star_ = p;
  double fl, dfl, fr, dfr;
  pressure_function(p, left_, c_left_, fl, dfl);
  pressure_function(p, right_, c_right_, fr, dfr);
  u_star_ = 0.5 * (left.velocity + right.velocity) + 0.5 * (fr - fl);
}

void ExactRiemannSolution::pressure_function(double p, const GasState& side, double c, double& f, double& df) const {
  const double g = gamma_;
  if (p > side.pressure) {  // shock
    const double A = 2 / ((g + 1) * side.density), B = (g - 1) / (g + 1) * side.pressure;
    const double root = std::sqrt(A / (p + B));
    f = (p - side.pressure) * root;
    df = root * (1 - (p - side.pressure) / (2 * (B + p)));
  } else {  // rarefaction
    const double ratio = p / side.pressure;
    f = 2 * c / (g - 1) * (std::pow(ratio, (g - 1) / (2 * g)) - 1);
    df = 1 / (side.density * c) * std::pow(ratio, -(g + 1) / (2 * g));
  }
}

double ExactRiemannSolution::star_density(const GasState& side, double) const {
  const double g = gamma_, ratio = p_star_ / side.pressure;
  if (ratio > 1) {  // behind a shock (Rankine-Hugoniot)
    const double k = (g - 1) / (g + 1);
    return side.density * (ratio + k) / (k * ratio + 1);
  }
  return side.density * std::pow(ratio, 1 / g);  // isentropic across a rarefaction
}

GasState ExactRiemannSolution::sample(double s) const {
  const double g = gamma_;
  // Left of the contact: the left wave; right of it, the mirror image with u -> -u.
  const bool left_side = s <= u_star_;
  const GasState& K = left_side ? left_ : right_;
  const double c = left_side ? c_left_ : c_right_;
  const double sign = left_side ? 1 : -1;  // the left wave travels at u - c, the right one at u + c
  const double sk = sign * s, uk = sign * K.velocity, ustar = sign * u_star_;
  auto mirrored = [&](GasState state) {
    state.velocity *= sign;
    return state;
  };
  const double ratio = p_star_ / K.pressure;
  if (ratio > 1) {  // shock
    const double speed = uk - c * std::sqrt((g + 1) / (2 * g) * ratio + (g - 1) / (2 * g));
    if (sk <= speed) return K;
    return mirrored({star_density(K, c), ustar, p_star_});
  }
  // Rarefaction: head at u_K - c_K, tail at u* - c*.
  if (sk <= uk - c) return K;
  const double c_star = c * std::pow(ratio, (g - 1) / (2 * g));
  if (sk >= ustar - c_star) return mirrored({star_density(K, c), ustar, p_star_});
  const double u = 2 / (g + 1) * (c + (g - 1) / 2 * uk + sk);
  const double cf = 2 / (g + 1) * (c + (g - 1) / 2 * (uk - sk));
  return mirrored({K.density * std::pow(cf / c, 2 / (g - 1)), u, K.pressure * std::pow(cf / c, 2 * g / (g - 1))});
}

}  // namespace sph
