#pragma once
// Time integration of one cell's state over a step dt with the stimulus held at its average over
// the step. Three schemes, all first-order accurate in the stiff limit and second order (Strang)
// for the splitting one:
//   forward_euler  y += dt f(y): the explicit reference scheme, stable only below the step limit
//                  set by the fastest time constant (explicit_euler_step_limit below).
//   rush_larsen    every variable takes the QSS (exponential) update from the same old state
//                  (Rush & Larsen 1978 for the gates, generalised to every variable through the
//                  production/loss form); unconditionally stable, first order.
//   rbr_qss        reaction-by-reaction Strang splitting: a forward sweep over the variables with
//                  dt/2 and a backward sweep with dt/2, each variable taking its QSS update with the
//                  latest values of the others (Wang et al. 2019, Combust. Flame 205:41, sec. 2;
//                  Zhang et al. 2021, CMAME 381:113847, sec. 3.2); unconditionally stable.

#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "libsph/reaction/reaction_model.hpp"

namespace sph {

enum class ReactionScheme { forward_euler, rush_larsen, rbr_qss };

inline std::string_view to_string(ReactionScheme s) {
  switch (s) {
    case ReactionScheme::forward_euler: return "forward_euler";
    case ReactionScheme::rush_larsen: return "rush_larsen";
    case ReactionScheme::rbr_qss: return "rbr_qss";
  }
  return "?";
}

/// The names of the schemes as parameters take them.
inline const std::vector<std::pair<std::string, ReactionScheme>>& reaction_scheme_names() {
  static const std::vector<std::pair<std::string, ReactionScheme>> names{{"rbr_qss", ReactionScheme::rbr_qss},
                                                                         {"rush_larsen", ReactionScheme::rush_larsen},
                                                                         {"forward_euler", ReactionScheme::forward_euler}};
  return names;
}

/// The rbr_qss step as written: a forward sweep over the variables with dt/2, then a backward one.
template <ReactionModel M>
void rbr_qss_sweeps(const M& model, typename M::State& y, double stimulus, double dt) {
  constexpr std::size_t n = M::n_states;
  const double half = 0.5 * dt;
  for (std::size_t k = 0; k < n; ++k) y[k] = qss_update(y[k], model.production_loss(k, y, stimulus), half);
  for (std::size_t k = n; k-- > 0;) y[k] = qss_update(y[k], model.production_loss(k, y, stimulus), half);
}

/// A model may do the rbr_qss step itself, skipping what the two sweeps share (terms whose inputs
/// the sweeps leave unchanged in between); it must give rbr_qss_sweeps' result bit for bit (tested
/// for each model that has one).
template <class M>
concept HasOwnRbrQssStep = requires(const M& model, typename M::State& y, double stimulus, double dt) {
  model.rbr_qss_step(y, stimulus, dt);
};

/// A model whose production and loss are written for any number type (production_loss_of<T>, with
/// T = double and T = Lanes) can take the rbr_qss step for lane_count cells at once (lanes.hpp).
template <class M>
concept HasLanesProductionLoss =
    requires(const M& model, const std::array<Lanes, M::n_states>& y, const Lanes& stimulus, std::size_t k) {
      { model.template production_loss_of<Lanes>(k, y, stimulus) } -> std::same_as<BasicProductionLoss<Lanes>>;
    };

/// A model may also have its own rbr_qss step for lanes (like HasOwnRbrQssStep for one cell).
template <class M>
concept HasOwnLanesRbrQssStep =
    requires(const M& model, std::array<Lanes, M::n_states>& y, const Lanes& stimulus, double dt) {
      model.rbr_qss_step(y, stimulus, dt);
    };

/// The particle loops of ReactionSystem advance such models eight cells at a time.
template <class M>
concept HasLanesRbrQssStep = HasOwnLanesRbrQssStep<M> || HasLanesProductionLoss<M>;

/// One rbr_qss step of lane_count cells: the model's own, or the generic sweeps on its
/// production_loss_of<Lanes>, the same sequence of operations as rbr_qss_sweeps in every lane.
template <class M>
  requires HasLanesRbrQssStep<M>
void rbr_qss_step_in_lanes(const M& model, std::array<Lanes, M::n_states>& y, const Lanes& stimulus, double dt) {
  if constexpr (HasOwnLanesRbrQssStep<M>) {
    model.rbr_qss_step(y, stimulus, dt);
  } else {
    constexpr std::size_t n = M::n_states;
    const double half = 0.5 * dt;
    const auto update = [&](std::size_t k) {
      y[k] = BasicQssStep<Lanes>(model.template production_loss_of<Lanes>(k, y, stimulus), half).apply(y[k]);
    };
    for (std::size_t k = 0; k < n; ++k) update(k);
    for (std::size_t k = n; k-- > 0;) update(k);
  }
}

template <ReactionModel M>
void advance_cell(const M& model, typename M::State& y, double stimulus, double dt, ReactionScheme scheme) {
  constexpr std::size_t n = M::n_states;
  switch (scheme) {
    case ReactionScheme::forward_euler: {
      const auto f = model.rates(y, stimulus);
      for (std::size_t k = 0; k < n; ++k) y[k] += dt * f[k];
      return;
    }
    case ReactionScheme::rush_larsen: {
      std::array<ProductionLoss, n> r;
      for (std::size_t k = 0; k < n; ++k) r[k] = model.production_loss(k, y, stimulus);
      for (std::size_t k = 0; k < n; ++k) y[k] = qss_update(y[k], r[k], dt);
      return;
    }
    case ReactionScheme::rbr_qss:
      if constexpr (HasOwnRbrQssStep<M>) model.rbr_qss_step(y, stimulus, dt);
      else rbr_qss_sweeps(model, y, stimulus, dt);
      return;
  }
}

/// Largest forward-Euler step that is linearly stable at state y: for every eigenvalue lambda of
/// the Jacobian with Re(lambda) < 0, |1 + dt lambda| <= 1 requires dt <= -2 Re(lambda) / |lambda|^2.
/// The Jacobian is taken by central differences. Returns infinity if no eigenvalue decays.
template <ReactionModel M>
double explicit_euler_step_limit(const M& model, const typename M::State& y, double stimulus = 0) {
  constexpr int n = static_cast<int>(M::n_states);
  Eigen::Matrix<double, n, n> jacobian;
  for (int j = 0; j < n; ++j) {
    auto plus = y, minus = y;
    const double delta = 1e-6 * std::max(std::abs(y[j]), 1e-3);
    plus[j] += delta;
    minus[j] -= delta;
    const auto fp = model.rates(plus, stimulus), fm = model.rates(minus, stimulus);
    for (int i = 0; i < n; ++i) jacobian(i, j) = (fp[i] - fm[i]) / (2 * delta);
  }
  const Eigen::EigenSolver<Eigen::Matrix<double, n, n>> solver(jacobian, false);
  double limit = std::numeric_limits<double>::infinity();
  for (int i = 0; i < n; ++i) {
    const auto lambda = solver.eigenvalues()[i];
    if (lambda.real() < 0) limit = std::min(limit, -2 * lambda.real() / std::norm(lambda));
  }
  return limit;
}

}  // namespace sph
