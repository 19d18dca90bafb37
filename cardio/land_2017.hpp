#pragma once
// Calcium- and stretch-driven active tension of human ventricular myocytes: the contraction model
// of Land, Park-Holohan, Smith, dos Remedios, Kentish & Niederer 2017, "A model of cardiac
// contraction based on novel measurements of tension development in human cardiomyocytes",
// J. Mol. Cell. Cardiol. 106:68-83 (doi:10.1016/j.yjmcc.2017.03.008), its equations of the
// appendix and the human parameter set of its Table 2 (the values below, as also used by the
// CardioMechanics and simcardems implementations of the model).
//
// Six states per cell: troponin C bound to calcium (CaTRPN), blocked tropomyosin (B), weakly and
// strongly bound crossbridges (XW, XS; unbound XU = 1 - B - XW - XS) and the mean distortions of the
// weak and strong crossbridges (zeta_w, zeta_s). Inputs: the free cytosolic calcium Ca_i [uM], the
// fibre stretch lambda and its rate dlambda/dt [1/ms]. Units: t [ms], tension [kPa].
//   lambda_c   = min(lambda, 1.2)
//   Ca50       = Ca50_ref + beta_1 (lambda_c - 1)                       (length-dependent sensitivity)
//   dCaTRPN/dt = k_TRPN ((Ca_i / Ca50)^n_TRPN (1 - CaTRPN) - CaTRPN)
//   dB/dt      = k_b min(100, CaTRPN^(-n_TM/2)) XU - k_u CaTRPN^(n_TM/2) B
//   dXW/dt     = k_uw XU - k_wu XW - k_ws XW - gamma_wu XW
//   dXS/dt     = k_ws XW - k_su XS - gamma_su XS
//   dzeta_s/dt = A dlambda/dt - c_s zeta_s,   dzeta_w/dt = A dlambda/dt - c_w zeta_w
//   gamma_wu = gamma_w |zeta_w|,  gamma_su = gamma_s (zeta_s if zeta_s > 0; -zeta_s - 1 if zeta_s < -1; else 0)
//   k_wu = k_uw (1/r_w - 1) - k_ws,  k_su = k_ws r_w (1/r_s - 1),
//   k_b = k_u TRPN50^n_TM / (1 - r_s - (1 - r_s) r_w),
//   A = A_eff r_s / ((1 - r_s) r_w + r_s),
//   c_s = phi k_ws (1 - r_s) r_w / r_s,  c_w = phi k_uw (1 - r_w) / r_w
//   h(lambda)  = max(0, 1 + beta_0 (lambda_c + min(lambda_c, 0.87) - 1.87))   (filament overlap)
//   T_a        = h(lambda) T_ref / r_s ((zeta_s + 1) XS + zeta_w XW).
// The rates are chosen so that a fully activated fibre at lambda = 1 and rest holds XS = r_s (1 - B)
// and T_a -> T_ref (1 - B), B small: T_ref is the maximal isometric tension.
//
// Step: each state obeys dy/dt = a - b y with a, b >= 0 when the others are frozen; the states are
// advanced one after another (CaTRPN, B, XW, XS, zeta_w, zeta_s) by the exact solution of that
// linear equation over dt, y <- a/b + (y - a/b) exp(-b dt) (the Rush-Larsen form of the cell
// models), which is stable and keeps every fraction in [0, 1] at any step.

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace cardio {

class Land2017 {
 public:
  /// Land et al. 2017, Table 2 (human, 37 C).
  struct Parameters {
    double T_ref = 120;        ///< maximal isometric tension [kPa]
    double Ca50_ref = 0.805;   ///< Ca_i of half troponin activation at lambda = 1 [uM]
    double k_TRPN = 0.1;       ///< troponin C calcium binding rate [1/ms]
    double n_TRPN = 2;         ///< cooperativity of troponin C binding
    double TRPN50 = 0.35;      ///< CaTRPN of half tropomyosin unblocking
    double n_TM = 5;           ///< cooperativity of tropomyosin unblocking
    double k_u = 1;            ///< tropomyosin unblocking rate [1/ms]
    double k_uw = 0.182;       ///< unbound to weak rate [1/ms]
    double k_ws = 0.012;       ///< weak to strong rate [1/ms]
    double r_w = 0.5;          ///< steady-state weak fraction of the cycling crossbridges
    double r_s = 0.25;         ///< steady-state strong fraction
    double gamma_s = 0.0085;   ///< strain-dependent detachment of the strong crossbridges
    double gamma_w = 0.615;    ///< strain-dependent detachment of the weak crossbridges
    double phi = 2.23;         ///< scaling of the distortion decay rates
    double A_eff = 25;         ///< effective distortion per unit stretch
    double beta_0 = 2.3;       ///< length dependence of the filament overlap
    double beta_1 = -2.4;      ///< length dependence of the calcium sensitivity [uM]

    /// Throws std::invalid_argument naming the bad parameter.
    void check() const {
      auto require = [](bool ok, const char* what) {
        if (!ok) throw std::invalid_argument(std::string("Land 2017 tension: ") + what);
      };
      for (double v : {T_ref, Ca50_ref, k_TRPN, n_TRPN, TRPN50, n_TM, k_u, k_uw, k_ws, phi, A_eff})
        require(std::isfinite(v) && v > 0, "T_ref, Ca50_ref, the rates, the cooperativities, phi and A_eff must be positive");
      require(r_w > 0 && r_w < 1 && r_s > 0 && r_s < 1, "r_w and r_s must lie in (0, 1)");
      require(gamma_s >= 0 && gamma_w >= 0 && std::isfinite(beta_0) && std::isfinite(beta_1),
              "gamma_s and gamma_w must be >= 0 and beta_0, beta_1 finite");
      require(k_uw * (1 / r_w - 1) - k_ws >= 0, "k_uw (1/r_w - 1) must be at least k_ws (a negative k_wu)");
    }
  };
  enum Index : std::size_t { CaTRPN, B, XW, XS, zeta_w, zeta_s };
  static constexpr std::size_t n_states = 6;
  using State = std::array<double, n_states>;

  Land2017() : Land2017(Parameters()) {}
  explicit Land2017(const Parameters& p) : p_(p) {
    p_.check();
    k_wu_ = p.k_uw * (1 / p.r_w - 1) - p.k_ws;
    k_su_ = p.k_ws * p.r_w * (1 / p.r_s - 1);
    k_b_ = p.k_u * std::pow(p.TRPN50, p.n_TM) / (1 - p.r_s - (1 - p.r_s) * p.r_w);
    A_ = p.A_eff * p.r_s / ((1 - p.r_s) * p.r_w + p.r_s);
    c_s_ = p.phi * p.k_ws * (1 - p.r_s) * p.r_w / p.r_s;
    c_w_ = p.phi * p.k_uw * (1 - p.r_w) / p.r_w;
  }
  const Parameters& parameters() const { return p_; }

  /// The steady state at constant Ca_i [uM] and lambda (no motion): the fixed point of the
  /// equations above, reached by stepping with the exact linear updates until it stops changing.
  State steady_state(double calcium, double lambda = 1) const {
    State y{0, 1, 0, 0, 0, 0};
    for (int k = 0; k < 200000; ++k) {
      const State before = y;
      step(y, calcium, lambda, 0, 1.0);
      double change = 0;
      for (std::size_t i = 0; i < n_states; ++i) change = std::max(change, std::abs(y[i] - before[i]));
      if (change < 1e-15) break;
    }
    return y;
  }

  /// Active tension [kPa] of state y at stretch lambda.
  double tension(const State& y, double lambda) const {
    return overlap(lambda) * p_.T_ref / p_.r_s * ((y[zeta_s] + 1) * y[XS] + y[zeta_w] * y[XW]);
  }
  /// dT_a/dlambda of an instantaneous stretch change: the distortions jump by A dlambda, so
  /// k = h(lambda) T_ref / r_s A (XS + XW) (the overlap factor's own slope left out).
  double stretch_stiffness(const State& y, double lambda) const {
    return overlap(lambda) * p_.T_ref / p_.r_s * A_ * (y[XS] + y[XW]);
  }
  /// h(lambda), the filament-overlap factor.
  double overlap(double lambda) const {
    const double l = std::min(lambda, 1.2);
    return std::max(0.0, 1 + p_.beta_0 * (l + std::min(l, 0.87) - 1.87));
  }

  /// dy/dt at Ca_i [uM], lambda and dlambda/dt [1/ms] (for the CVODE reference).
  State rates(const State& y, double calcium, double lambda, double dlambda) const {
    State f{};
    for (std::size_t k = 0; k < n_states; ++k) {
      const auto [a, b] = production_loss(k, y, calcium, lambda, dlambda);
      f[k] = a - b * y[k];
    }
    return f;
  }

  /// Advances y over dt [ms] at constant Ca_i [uM], lambda and dlambda/dt (see above).
  void step(State& y, double calcium, double lambda, double dlambda, double dt) const {
    for (std::size_t k = 0; k < n_states; ++k) {
      const auto [a, b] = production_loss(k, y, calcium, lambda, dlambda);
      y[k] = b > 0 ? a / b + (y[k] - a / b) * std::exp(-b * dt) : y[k] + a * dt;
    }
  }

 private:
  /// dy_k/dt = a - b y_k with the other states frozen.
  std::pair<double, double> production_loss(std::size_t k, const State& y, double calcium, double lambda,
                                            double dlambda) const {
    const double l = std::min(lambda, 1.2);
    switch (k) {
      case CaTRPN: {
        const double Ca50 = std::max(p_.Ca50_ref + p_.beta_1 * (l - 1), 1e-6);
        const double r = std::pow(std::max(calcium, 0.0) / Ca50, p_.n_TRPN);
        return {p_.k_TRPN * r, p_.k_TRPN * (r + 1)};
      }
      case B: {
        const double c = std::max(y[CaTRPN], 1e-300);
        const double unblock = k_b_ * std::min(100.0, std::pow(c, -p_.n_TM / 2));
        return {unblock * (1 - y[XW] - y[XS]), unblock + p_.k_u * std::pow(c, p_.n_TM / 2)};
      }
      case XW:
        return {p_.k_uw * (1 - y[B] - y[XS]), p_.k_uw + k_wu_ + p_.k_ws + p_.gamma_w * std::abs(y[zeta_w])};
      case XS: {
        const double z = y[zeta_s];
        const double gamma_su = p_.gamma_s * (z > 0 ? z : z < -1 ? -z - 1 : 0.0);
        return {p_.k_ws * y[XW], k_su_ + gamma_su};
      }
      case zeta_w: return {A_ * dlambda, c_w_};
      default: return {A_ * dlambda, c_s_};
    }
  }

  Parameters p_;
  double k_wu_, k_su_, k_b_, A_, c_s_, c_w_;
};

}  // namespace cardio
