#pragma once
// The interface every cell (reaction) model follows, checked by the concept `ReactionModel`.
//
// A model is a small value type with its parameters. Its state is y = (V, y_1, ..., y_{n-1}) with
// the transmembrane potential V first. Every model speaks in milliseconds and in the voltage unit of
// its parameters (millivolts for the physical models; a dimensionless model is wrapped with its
// scaling, e.g. V_mV = 100 u - 80 and t_ms = 12.9 t for Aliev-Panfilov).
//
// The right-hand side is given in production/loss form, per state variable:
//   dy_k/dt = q_k(y) - p_k(y) y_k,   p_k >= 0,
// which is what the quasi-steady-state (QSS) update of reaction-by-reaction splitting needs
// (Wang et al. 2019, Combust. Flame 205:41; Zhang et al. 2021, CMAME 381:113847):
//   y_k(t + dt) = q_k / p_k + (y_k - q_k / p_k) exp(-p_k dt),
// exact for a linear equation and unconditionally stable. For a Hodgkin-Huxley gate, q = y_inf / tau
// and p = 1 / tau, and the update is the Rush-Larsen step.
//
// `stimulus` is an applied rate of change of V (I_stim / C_m, in voltage unit per ms); it enters the
// production term of V only.
//
// A model M provides:
//   static constexpr std::size_t n_states;
//   using State = std::array<double, n_states>;
//   static constexpr std::array<std::string_view, n_states> state_names;   (state_names[0] is V)
//   State initial_state() const;                                             the resting state
//   ProductionLoss production_loss(std::size_t k, const State& y, double stimulus) const;
//   State rates(const State& y, double stimulus) const;                      dy/dt, all at once
//   VoltageRange valid_voltage() const;    V outside this range means the state is not physiological
//
// Models compute in double whatever the build's Real is: gating and concentration variables span
// many orders of magnitude.

#include <array>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <string_view>
#include <type_traits>

#include "libsph/reaction/lanes.hpp"

namespace sph {

/// dy/dt = production - loss * y for one state variable, with loss >= 0; T is double for one cell
/// or Lanes for several (lanes.hpp).
template <class T>
struct BasicProductionLoss {
  T production{};
  T loss{};
};
using ProductionLoss = BasicProductionLoss<double>;

/// The range of V [voltage unit of the model] in which the model's equations are meaningful.
struct VoltageRange {
  double lower = 0;
  double upper = 0;
};

template <class M>
concept ReactionModel = requires(const M& model, const typename M::State& y, double stimulus, std::size_t k) {
  requires std::same_as<typename M::State, std::array<double, M::n_states>>;
  requires M::n_states >= 1;
  { M::state_names[0] } -> std::convertible_to<std::string_view>;
  { model.initial_state() } -> std::same_as<typename M::State>;
  { model.production_loss(k, y, stimulus) } -> std::same_as<ProductionLoss>;
  { model.rates(y, stimulus) } -> std::same_as<typename M::State>;
  { model.valid_voltage() } -> std::same_as<VoltageRange>;
};

/// The QSS (exponential) update of one variable over dt with frozen production q and loss p, with
/// the exponential computed once so that several variables or sweeps sharing (q, p, dt) reuse it:
/// QssStep(r, dt).apply(y) equals qss_update(y, r, dt) bit for bit.
///
/// For small p dt, y + (q - p y) (1 - exp(-p dt)) / p with expm1 keeps its digits (it tends to the
/// forward-Euler step); for large p dt, the equilibrium form keeps the relative accuracy of the
/// small remainder (y - q/p) exp(-p dt). For lanes, each lane takes the form its own p dt selects.
template <class T>
struct BasicQssStep {
  BasicQssStep(BasicProductionLoss<T> r, double dt) : rate(r) {
    if constexpr (std::same_as<T, double>) {
      const double pdt = r.loss * dt;
      relaxed = pdt > 0.5;
      if (relaxed) {
        equilibrium = r.production / r.loss;
        decay = std::exp(-pdt);
      } else {
        factor = r.loss > 0 ? -std::expm1(-pdt) / r.loss : dt;
      }
    } else {
      const T pdt = r.loss * dt;
      relaxed = pdt > 0.5;
      // Each form is evaluated only if a lane takes it (Eigen's select() is not vectorised).
      if (relaxed.any()) {
        equilibrium = r.production / r.loss;  // not finite where p = 0: those lanes are not relaxed
        decay = (-pdt).exp();
      }
      if (!relaxed.all()) {
        factor = pick((r.loss > 0).eval(), [&]() -> T { return -exp_minus_one(-pdt) / r.loss; },
                      [&]() -> T { return T::Constant(dt); });
      }
    }
  }
  T apply(const T& y) const {
    if constexpr (std::same_as<T, double>) {
      if (relaxed) return equilibrium + (y - equilibrium) * decay;
      return y + (rate.production - rate.loss * y) * factor;
    } else {
      return pick(
          relaxed, [&]() -> T { return equilibrium + (y - equilibrium) * decay; },
          [&]() -> T { return y + (rate.production - rate.loss * y) * factor; });
    }
  }

  BasicProductionLoss<T> rate;
  std::conditional_t<std::same_as<T, double>, bool, Eigen::Array<bool, lane_count, 1>> relaxed{};
  T equilibrium{}, decay{}, factor{};
};
using QssStep = BasicQssStep<double>;

inline double qss_update(double y, ProductionLoss r, double dt) { return QssStep(r, dt).apply(y); }

/// A loss that came out negative (outside the model's usual range, e.g. a recovery variable below 0)
/// is moved into the production term, so that the QSS update stays well defined; q - p y is unchanged.
inline ProductionLoss with_nonnegative_loss(ProductionLoss r, double y) {
  if (r.loss >= 0) return r;
  return {r.production - r.loss * y, 0};
}
inline BasicProductionLoss<Lanes> with_nonnegative_loss(const BasicProductionLoss<Lanes>& r, const Lanes& y) {
  const Eigen::Array<bool, lane_count, 1> negative = r.loss < 0;
  if (!negative.any()) return r;
  return {negative.select(r.production - r.loss * y, r.production), negative.select(0.0, r.loss)};
}

/// The scaling that turns a dimensionless model (potential u, time tau) into physical units:
/// V = voltage_scale u + voltage_offset and t = time_scale tau. With du/dtau = q_u - p_u u,
///   dV/dt = (voltage_scale q_u + p_u voltage_offset) / time_scale - (p_u / time_scale) V,
/// and every other variable's production and loss are divided by time_scale.
struct DimensionlessScaling {
  double voltage_scale = 1;   ///< voltage unit per unit of u
  double voltage_offset = 0;  ///< V at u = 0
  double time_scale = 1;      ///< ms per unit of tau

  double to_u(double V) const { return (V - voltage_offset) / voltage_scale; }
  Lanes to_u(const Lanes& V) const { return (V - voltage_offset) / voltage_scale; }
  double to_V(double u) const { return voltage_scale * u + voltage_offset; }
  /// A stimulus dV/dt as du/dtau.
  double stimulus_to_u(double stimulus) const { return stimulus * time_scale / voltage_scale; }
  Lanes stimulus_to_u(const Lanes& stimulus) const { return stimulus * time_scale / voltage_scale; }
  template <class T>
  BasicProductionLoss<T> potential(const BasicProductionLoss<T>& u_rate) const {
    return {(voltage_scale * u_rate.production + u_rate.loss * voltage_offset) / time_scale, u_rate.loss / time_scale};
  }
  template <class T>
  BasicProductionLoss<T> other(const BasicProductionLoss<T>& rate) const {
    return {rate.production / time_scale, rate.loss / time_scale};
  }
};

}  // namespace sph
