#include "libsph/core/time_stepper.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace sph {

TimeStepper::TimeStepper(Real start_time, Real end_time) : start_time_(start_time), end_time_(end_time) {
  if (!(end_time >= start_time)) throw std::invalid_argument("time stepper: end time before start time");
}

void TimeStepper::add_stage(Stage stage) { stages_.push_back(std::move(stage)); }

void TimeStepper::set_coupling_interval(Real interval) { coupling_interval_ = interval; }

void TimeStepper::add_periodic_callback(Real interval, std::function<void(const StepInfo&)> callback,
                                        bool hit_exactly) {
  if (!(interval > 0)) throw std::invalid_argument("time stepper: callback interval must be positive");
  periodic_.push_back({interval, 0, -std::numeric_limits<Real>::infinity(), hit_exactly, std::move(callback)});
}

void TimeStepper::add_step_callback(std::function<void(const StepInfo&)> callback) {
  step_callbacks_.push_back(std::move(callback));
}

Real TimeStepper::next_event_time() const {
  Real next = end_time_;
  for (const auto& p : periodic_)
    if (p.hit_exactly) next = std::min(next, start_time_ + static_cast<Real>(p.next_index) * p.interval);
  return next;
}

std::size_t TimeStepper::run() {
  // A quotient that is a whole number up to round-off must not cost an extra step.
  constexpr Real rounding = Real(16) * std::numeric_limits<Real>::epsilon();
  StepInfo info{start_time_, 0, 0, start_time_, end_time_};
  // Fires the callbacks whose event time has been reached; at the end time every callback fires
  // once more unless it already ran there, so the final state is always seen.
  auto fire_due = [&](Real t) {
    const bool at_end = t >= end_time_;
    for (auto& p : periodic_) {
      const Real event = start_time_ + static_cast<Real>(p.next_index) * p.interval;
      if (event <= t || (at_end && p.last_fired < end_time_)) {
        p.callback(info);
        p.last_fired = t;
        while (start_time_ + static_cast<Real>(p.next_index) * p.interval <= t) ++p.next_index;
      }
    }
  };
  fire_due(start_time_);

  Real t = start_time_;
  while (t < end_time_) {
    const Real event = next_event_time();
    Real stable = std::numeric_limits<Real>::infinity();
    for (const auto& stage : stages_) {
      const Real s = stage.stable_time_step();
      if (!(s > 0) || !std::isfinite(s)) {
        std::ostringstream msg;
        msg << "time-step collapse in stage '" << stage.name << "' at time " << t << ": stable step " << s;
        throw std::runtime_error(msg.str());
      }
      if (!stage.sub_cycled) stable = std::min(stable, s);
    }
    if (coupling_interval_ > 0) stable = std::min(stable, coupling_interval_);
    // Even out the steps up to the next event: n = ceil(remaining / stable) equal steps.
    const Real remaining = event - t;
    Real dt = remaining;
    if (std::isfinite(stable) && remaining > stable) {
      const Real n = std::ceil(remaining / stable * (Real(1) - rounding));
      dt = remaining / n;
    }
    const bool reaches_event = dt >= remaining;
    for (const auto& stage : stages_) {
      if (!stage.sub_cycled) {
        stage.advance(t, dt);
        continue;
      }
      const Real s = stage.stable_time_step();
      const auto n_sub = static_cast<std::size_t>(std::max(Real(1), std::ceil(dt / s * (Real(1) - rounding))));
      const Real sub = dt / static_cast<Real>(n_sub);
      for (std::size_t k = 0; k < n_sub; ++k) stage.advance(t + static_cast<Real>(k) * sub, sub);
    }
    t = reaches_event ? event : t + dt;
    info.time = t;
    info.time_step = dt;
    ++info.step;
    for (const auto& callback : step_callbacks_) callback(info);
    if (stop_requested_ && t < end_time_) end_time_ = info.end_time = t;
    fire_due(t);
  }
  return info.step;
}

}  // namespace sph
