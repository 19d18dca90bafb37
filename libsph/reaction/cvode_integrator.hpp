#pragma once
// SUNDIALS CVODE (variable-order BDF with Newton iterations and a dense direct solver) behind a
// small interface; the reference integrator against which the cheaper cell schemes are measured.
// No SUNDIALS type appears here: the solver lives in cvode_integrator.cpp.

#include <cstddef>
#include <functional>
#include <memory>
#include <span>

#include "libsph/reaction/reaction_model.hpp"
#include "libsph/reaction/stimulus.hpp"

namespace sph {

class CvodeIntegrator {
 public:
  using RightHandSide = std::function<void(double t, std::span<const double> y, std::span<double> dydt)>;
  struct Settings {
    double relative_tolerance = 1e-8;
    double absolute_tolerance = 1e-10;
    double max_step = 0;          ///< largest internal step [ms]; 0: no limit
    long max_steps = 1'000'000;   ///< internal steps allowed per advance_to call
  };

  CvodeIntegrator(std::size_t n_states, RightHandSide rhs, Settings settings);
  ~CvodeIntegrator();
  CvodeIntegrator(const CvodeIntegrator&) = delete;
  CvodeIntegrator& operator=(const CvodeIntegrator&) = delete;

  /// Starts (or restarts, e.g. after a discontinuity of the right-hand side) at (t, y).
  void reset(double t, std::span<const double> y);
  /// Integrates from the current time to t_out and writes the state there into y. Throws
  /// std::runtime_error with CVODE's message if the solver fails.
  void advance_to(double t_out, std::span<double> y);
  /// Internal steps taken since construction.
  long steps() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One cell under a stimulus protocol, solved by CVODE from the model's initial state: calls
/// record(t, y) at t = 0, sample, 2 sample, ... up to end_time. The solver restarts at every pulse
/// edge so that no step straddles a discontinuity.
template <ReactionModel M, class Record>
long solve_cell_with_cvode(const M& model, const StimulusProtocol& stimulus, double end_time, double sample,
                           Record&& record, CvodeIntegrator::Settings settings = {}) {
  using State = typename M::State;
  double current_stimulus = 0;
  CvodeIntegrator cvode(
      M::n_states,
      [&](double, std::span<const double> y, std::span<double> dydt) {
        State s;
        std::copy(y.begin(), y.end(), s.begin());
        const State f = model.rates(s, current_stimulus);
        std::copy(f.begin(), f.end(), dydt.begin());
      },
      settings);
  State y = model.initial_state();
  double t = 0;
  auto restart = [&] {
    current_stimulus = stimulus.average(t, 0);
    cvode.reset(t, y);
  };
  restart();
  record(t, y);
  const auto n_samples = static_cast<long>(std::llround(end_time / sample));
  for (long i = 1; i <= n_samples; ++i) {
    const double t_out = i == n_samples ? end_time : i * sample;
    for (double edge : stimulus.switching_times(t, t_out)) {
      cvode.advance_to(edge, y);
      t = edge;
      restart();
    }
    if (t < t_out) cvode.advance_to(t_out, y);
    t = t_out;
    record(t, y);
  }
  return cvode.steps();
}

}  // namespace sph
