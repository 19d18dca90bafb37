#pragma once
// The exact self-similar solution of the Sedov-Taylor point explosion (the "standard" case): energy E
// released at r = 0, t = 0 in a uniform cold ideal gas (density rho0, pressure 0, p = (gamma - 1) rho e)
// in geometry j = 1 (planar), 2 (cylindrical) or 3 (spherical). Sources: Sedov 1959, "Similarity and
// dimensional methods in mechanics", ch. IV; Landau & Lifshitz, "Fluid mechanics", sec. 106 (j = 3);
// Kamm 2000, LA-UR-00-6055, and Kamm & Timmes 2007, LA-UR-07-2849 (the closed form for any j, written
// here for a uniform background, omega = 0); Book 1991, NRL memo 6400-91-6400.
//
// Shock: R(t) = xi0 (E t^2 / rho0)^(1/(j+2)), U = dR/dt = 2 R / ((j + 2) t). Behind it (Rankine-Hugoniot,
// strong shock): rho2 = (gamma+1)/(gamma-1) rho0, u2 = 2 U/(gamma+1), p2 = 2 rho0 U^2/(gamma+1).
// Inside, lambda = r / R and u = v r / t, with v running from v0 = 2/((j+2) gamma) at the centre to
// v2 = 4/((j+2)(gamma+1)) at the shock. With
//   x1 = a v,  x2 = b (c v - 1),  x3 = d (1 - e v),  x4 = b (1 - (j+2) v / 2),
//   a = (j+2)(gamma+1)/4, b = (gamma+1)/(gamma-1), c = (j+2) gamma/2, e = (2 + j (gamma-1))/2,
//   d = (j+2)(gamma+1) / ((j+2)(gamma+1) - 2 (2 + j (gamma-1)))       (all x_i = 1 at the shock)
// and the exponents
//   a0 = 2/(j+2), a2 = -(gamma-1)/(2 (gamma-1) + j), a3 = j/(2 (gamma-1) + j), a5 = -2/(2 - gamma),
//   a1 = (j+2) gamma/(2 + j (gamma-1)) [2 j (2-gamma)/(gamma (j+2)^2) - a2], a4 = (j+2) a1/(2 - gamma),
// the solution is
//   lambda = x1^-a0 x2^-a2 x3^-a1,  rho/rho2 = x2^a3 x3^a4 x4^a5,  p/p2 = x1^(j a0) x3^(a4 - 2 a1) x4^(1 + a5).
// (For j = 3 these are Landau & Lifshitz's (106.11)-(106.13), with their V = 5 v / 2.)
//
// Energy convention: E = S_j int_0^R (rho u^2/2 + p/(gamma-1)) r^(j-1) dr with S_3 = 4 pi (the total
// energy), S_2 = 2 pi (energy per unit length of the line source), S_1 = 2 (energy per unit area of the
// plane source, counting both sides x > 0 and x < 0). Then E = alpha rho0 R^(j+2)/t^2 and xi0 = alpha^(-1/(j+2)),
//   alpha = S_j int_0^1 [b g v^2 lambda^(j+1)/2 + 8 h lambda^(j-1)/((gamma^2 - 1)(j+2)^2)] dlambda,
// evaluated as an integral over v by tanh-sinh quadrature. Kamm & Timmes (and ExactPack) count only
// x > 0 in the planar case (S_1 = 1): their planar alpha is half of this one.
//
// Valid for the standard case: gamma > 1, gamma != 2 (gamma = 2 needs a limiting form, not implemented)
// and, for j = 3, gamma < 7 (larger gammas give the singular and vacuum cases, not implemented).

namespace sph {

class SedovSolution {
 public:
  struct State {
    double density = 0, velocity = 0, pressure = 0;
  };

  /// geometry: 1 planar, 2 cylindrical, 3 spherical. Throws std::invalid_argument, naming the input,
  /// for a geometry not in {1, 2, 3}, gamma <= 1, |gamma - 2| < 1e-6, gamma >= 7 with j = 3, or a
  /// non-positive (or non-finite) energy or density.
  SedovSolution(int geometry, double gamma, double energy, double density);

  int geometry() const { return j_; }
  double gamma() const { return gamma_; }
  double energy() const { return energy_; }
  double background_density() const { return rho0_; }
  /// E = alpha rho0 R^(j+2) / t^2 (the energy convention above).
  double alpha() const { return alpha_; }
  /// R(t) = xi0 (E t^2 / rho0)^(1/(j+2)).
  double xi0() const { return xi0_; }
  double shock_radius(double t) const;
  double shock_speed(double t) const;
  /// The state at distance r >= 0 from the source (|x| for planar) at time t > 0: the self-similar
  /// profile for r <= R(t) (r = R gives the post-shock state), the undisturbed gas (rho0, 0, 0) beyond.
  /// The velocity is radial (for planar: along +x for x > 0). Throws std::invalid_argument for r < 0 or t <= 0.
  State sample(double r, double t) const;

 private:
  struct Similarity {
    double log_lambda, dlog_lambda_dw, v, log_g, log_h;
  };
  // The similarity functions at v = v0 + w, w = exp(log_w) (w is carried separately: near the centre it
  // is far below the rounding of v0).
  Similarity similarity(double log_w) const;
  // The log w with lambda(w) = exp(log_lambda), log_lambda < 0.
  double solve_log_w(double log_lambda) const;

  int j_;
  double gamma_, energy_, rho0_;
  double a_, b_, c_, d_, e_, a0_, a1_, a2_, a3_, a4_, a5_, v0_, v2_;
  double alpha_ = 0, xi0_ = 0;
};

}  // namespace sph
