#pragma once
// Quasi-static solution of an elastic solid: damped relaxation in pseudo-time to the equilibrium of
// the loads, stopped on the residual instead of after a fixed time. See docs/solid.md.
//
// The steps are the solid's own damped dynamics (ElasticSolid::Settings::damping_rate, chosen from
// the first mode: c = 2 zeta omega1 damps the slowest mode critically at zeta = 1, and every other
// mode decays at least as fast). Every check_interval steps the l2 norm of the net nodal force over
// the unconstrained particles (ElasticSolid::equilibrium_residual) is compared with the l2 norm of
// the loads that drive the body (pressure, traction and force loads, body force, and the active
// stress's own forces): converged when net <= tolerance * load. A run that reaches its end without
// converging is reported with the residual and the steps (not_converged()), never passed off as an
// equilibrium.

#include <limits>
#include <string>

#include "libsph/solid/elastic_solid.hpp"

namespace sph {

class Parameters;

struct RelaxationSettings {
  Real tolerance = Real(1e-4);  ///< converged when |net force| <= tolerance |load|
  int check_interval = 50;      ///< steps between residual checks
};

/// Declares residual_tolerance and residual_check_interval.
void declare_parameters(Parameters& p, RelaxationSettings& settings);

template <int Dim>
class QuasiStaticRelaxation {
 public:
  /// The solid must be damped (damping_rate > 0).
  QuasiStaticRelaxation(ElasticSolid<Dim>& solid, RelaxationSettings settings);

  /// One step of the solid from `time` by dt.
  void advance(Real time, Real dt) {
    solid_.advance(time, dt);
    ++status_.steps;
  }
  /// The solid's stage (ElasticSolid::stage, its loads slot open) with the step counted.
  Stage stage(std::string name) {
    Stage step = solid_.stage(std::move(name));
    step.then("relaxation step", [this](Real, Real) { ++status_.steps; });
    return step;
  }
  Real stable_time_step() const { return solid_.stable_time_step(); }

  struct Status {
    double residual = std::numeric_limits<double>::infinity();  ///< |net force| / |load|
    double net = 0, load = 0;                                    ///< the two norms
    std::size_t steps = 0;                                       ///< steps taken so far
    bool converged = false;
  };
  /// Whether a residual check is due after the last step.
  bool check_due() const { return status_.steps % static_cast<std::size_t>(settings_.check_interval) == 0; }
  /// Checks the equilibrium at the loads of `time`.
  const Status& check(Real time);
  const Status& status() const { return status_; }
  /// Saves or loads the status (checkpoints): the steps taken decide when the next check is due.
  void checkpoint(StateArchive& archive) { archive.io("status", status_); }
  /// The message of a run that ended at `time` without converging.
  std::string not_converged(Real time) const;

 private:
  ElasticSolid<Dim>& solid_;
  RelaxationSettings settings_;
  Status status_;
};

extern template class QuasiStaticRelaxation<2>;
extern template class QuasiStaticRelaxation<3>;

}  // namespace sph
