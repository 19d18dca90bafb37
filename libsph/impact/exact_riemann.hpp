#pragma once
// The exact solution of the Riemann problem of the one-dimensional Euler equations for an ideal gas
// p = (gamma - 1) rho e (Toro 2009, "Riemann solvers and numerical methods for fluid dynamics",
// 3rd ed., chapter 4): the reference of the shock-tube scenes.
//
// The star pressure p* solves f_L(p) + f_R(p) + u_R - u_L = 0, where for side K
//   shock (p > p_K):        f_K = (p - p_K) sqrt(A_K / (p + B_K)),  A_K = 2 / ((gamma + 1) rho_K),
//                                                                    B_K = (gamma - 1) / (gamma + 1) p_K
//   rarefaction (p <= p_K): f_K = 2 c_K / (gamma - 1) ((p / p_K)^((gamma - 1) / (2 gamma)) - 1),
// solved by Newton's method from the two-rarefaction estimate; u* = (u_L + u_R + f_R(p*) - f_L(p*)) / 2.
// The solution is self-similar: sample(s) gives the state at x - x0 = s t.

namespace sph {

struct GasState {
  double density = 0, velocity = 0, pressure = 0;
};

class ExactRiemannSolution {
 public:
  /// Throws std::invalid_argument for a non-positive density or pressure, gamma <= 1, or data that
  /// create a vacuum (u_R - u_L >= 2 (c_L + c_R) / (gamma - 1)), naming the values.
  ExactRiemannSolution(GasState left, GasState right, double gamma);

  double star_pressure() const { return p_star_; }
  double star_velocity() const { return u_star_; }
  /// The density between the left wave and the contact, and between the contact and the right wave.
  double star_density_left() const { return star_density(left_, c_left_); }
  double star_density_right() const { return star_density(right_, c_right_); }
  /// The state at x - x0 = s t (s: the similarity variable).
  GasState sample(double s) const;
  /// Newton iterations taken for p*.
  int iterations() const { return iterations_; }

 private:
  double star_density(const GasState& side, double c) const;
  // f_K(p) and its derivative.
  void pressure_function(double p, const GasState& side, double c, double& f, double& df) const;

  GasState left_, right_;
  double gamma_, c_left_, c_right_;
  double p_star_ = 0, u_star_ = 0;
  int iterations_ = 0;
};

}  // namespace sph
