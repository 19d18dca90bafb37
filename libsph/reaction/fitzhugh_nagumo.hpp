#pragma once
// FitzHugh-Nagumo model (FitzHugh 1961, Biophys. J. 1:445), in dimensionless potential v and time tau:
//   dv/dtau = v - v^3 / 3 - w + I
//   dw/dtau = eps (v + beta - gamma w)
// with FitzHugh's constants eps = 0.08, beta = 0.7, gamma = 0.8 (rest at v = -1.199, w = -0.624).
// Physical units through `DimensionlessScaling`: by default V = 30 v - 45 mV (rest near -81 mV,
// peak near +15 mV) and t = 10 tau ms (an action potential of a few hundred ms); this scaling is a
// choice of this code, not part of the published model.
//
// Production/loss form: v: q = v - w + I, p = v^2 / 3;  w: q = eps (v + beta), p = eps gamma.

#include <algorithm>
#include <string_view>

#include "libsph/reaction/reaction_model.hpp"

namespace sph {

class FitzHughNagumo {
 public:
  struct Parameters {
    double epsilon = 0.08;
    double beta = 0.7;
    double gamma = 0.8;
    DimensionlessScaling scaling{30, -45, 10};  ///< mV per v, mV at v = 0, ms per tau
  };
  static constexpr std::size_t n_states = 2;
  using State = std::array<double, n_states>;
  static constexpr std::array<std::string_view, n_states> state_names{"transmembrane_potential", "recovery"};

  FitzHughNagumo() = default;
  explicit FitzHughNagumo(Parameters parameters) : p_(parameters) {}
  const Parameters& parameters() const { return p_; }

  /// The resting point: the real root of v - v^3/3 - (v + beta)/gamma = 0, by Newton's method.
  State initial_state() const {
    double v = -1.2;
    for (int i = 0; i < 50; ++i) {
      const double f = v - v * v * v / 3 - (v + p_.beta) / p_.gamma;
      const double df = 1 - v * v - 1 / p_.gamma;
      v -= f / df;
    }
    return {p_.scaling.to_V(v), (v + p_.beta) / p_.gamma};
  }

  ProductionLoss production_loss(std::size_t k, const State& y, double stimulus) const {
    return production_loss_of<double>(k, y, stimulus);
  }
  /// The same for one cell (T = double) or several (T = Lanes, lanes.hpp).
  template <class T>
  BasicProductionLoss<T> production_loss_of(std::size_t k, const std::array<T, n_states>& y, const T& stimulus) const {
    const T v = p_.scaling.to_u(y[0]);
    const T& w = y[1];
    if (k == 0) return p_.scaling.potential(BasicProductionLoss<T>{v - w + p_.scaling.stimulus_to_u(stimulus), v * v / 3});
    return p_.scaling.other(BasicProductionLoss<T>{p_.epsilon * (v + p_.beta), constant<T>(p_.epsilon * p_.gamma)});
  }

  State rates(const State& y, double stimulus) const {
    const double v = p_.scaling.to_u(y[0]), w = y[1];
    const double dv = v - v * v * v / 3 - w + p_.scaling.stimulus_to_u(stimulus);
    const double dw = p_.epsilon * (v + p_.beta - p_.gamma * w);
    return {p_.scaling.voltage_scale * dv / p_.scaling.time_scale, dw / p_.scaling.time_scale};
  }

  /// v in [-4, 4]: the action potential spans about [-2, 2].
  VoltageRange valid_voltage() const {
    const double a = p_.scaling.to_V(-4), b = p_.scaling.to_V(4);
    return {std::min(a, b), std::max(a, b)};
  }

 private:
  Parameters p_;
};

}  // namespace sph
