#pragma once
// Aliev-Panfilov model (Aliev & Panfilov 1996, Chaos Solitons Fractals 7:293, eqs. 1-2), in
// dimensionless potential u and time tau:
//   du/dtau = -k u (u - a)(u - 1) - u v + I
//   dv/dtau = eps(u, v) (-v - k u (u - b - 1)),   eps(u, v) = eps0 + mu1 v / (u + mu2).
// The original paper uses b = a = 0.15. The electromechanical variant of Nash & Panfilov 2004
// (Prog. Biophys. Mol. Biol. 85:501) takes a = 0.01, b = 0.15 (`nash_panfilov_2004()`); its active
// tension is an equation of the electromechanics layer, not a state of this model.
// Physical units through `DimensionlessScaling`: by default V = 100 u - 80 mV and t = 12.9 tau ms.
//
// Production/loss form (p >= 0 for v >= 0, u + mu2 > 0):
//   u: q = k (a + 1) u^2 + I,   p = k a + k u^2 + v
//   v: q = -eps k u (u - b - 1), p = eps

#include <algorithm>
#include <string_view>

#include "libsph/reaction/reaction_model.hpp"

namespace sph {

class AlievPanfilov {
 public:
  struct Parameters {
    double k = 8;          ///< excitation strength
    double a = 0.15;       ///< excitation threshold (u equation)
    double b = 0.15;       ///< threshold in the recovery equation
    double epsilon0 = 0.002;
    double mu1 = 0.2;
    double mu2 = 0.3;
    DimensionlessScaling scaling{100, -80, 12.9};  ///< mV per u, mV at u = 0, ms per tau
  };
  static constexpr std::size_t n_states = 2;
  using State = std::array<double, n_states>;
  static constexpr std::array<std::string_view, n_states> state_names{"transmembrane_potential", "recovery"};

  AlievPanfilov() = default;
  explicit AlievPanfilov(Parameters parameters) : p_(parameters) {}
  /// a = 0.01, b = 0.15: the parameters of the electromechanical model of Nash & Panfilov 2004.
  static AlievPanfilov nash_panfilov_2004() {
    Parameters p;
    p.a = 0.01;
    return AlievPanfilov(p);
  }
  const Parameters& parameters() const { return p_; }

  State initial_state() const { return {p_.scaling.to_V(0), 0}; }

  ProductionLoss production_loss(std::size_t k, const State& y, double stimulus) const {
    return production_loss_of<double>(k, y, stimulus);
  }
  /// The same for one cell (T = double) or several (T = Lanes, lanes.hpp).
  template <class T>
  BasicProductionLoss<T> production_loss_of(std::size_t k, const std::array<T, n_states>& y, const T& stimulus) const {
    const T u = p_.scaling.to_u(y[0]);
    const T& v = y[1];
    if (k == 0) {
      const BasicProductionLoss<T> r{p_.k * (p_.a + 1) * u * u + p_.scaling.stimulus_to_u(stimulus),
                                     p_.k * p_.a + p_.k * u * u + v};
      return p_.scaling.potential(with_nonnegative_loss(r, u));
    }
    const T eps = epsilon(u, v);
    const BasicProductionLoss<T> r{-eps * p_.k * u * (u - p_.b - 1), eps};
    return p_.scaling.other(with_nonnegative_loss(r, v));
  }

  State rates(const State& y, double stimulus) const {
    const double u = p_.scaling.to_u(y[0]), v = y[1];
    const double du = -p_.k * u * (u - p_.a) * (u - 1) - u * v + p_.scaling.stimulus_to_u(stimulus);
    const double dv = epsilon(u, v) * (-v - p_.k * u * (u - p_.b - 1));
    return {p_.scaling.voltage_scale * du / p_.scaling.time_scale, dv / p_.scaling.time_scale};
  }

  /// u in [-1, 3]: beyond, the cubic has run away from the action potential it models.
  VoltageRange valid_voltage() const { return range_of_u(-1, 3); }

 private:
  template <class T>
  T epsilon(const T& u, const T& v) const {
    return p_.epsilon0 + p_.mu1 * v / (u + p_.mu2);
  }
  VoltageRange range_of_u(double lo, double hi) const {
    const double a = p_.scaling.to_V(lo), b = p_.scaling.to_V(hi);
    return {std::min(a, b), std::max(a, b)};
  }
  Parameters p_;
};

}  // namespace sph
