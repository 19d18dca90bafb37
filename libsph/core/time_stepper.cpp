#include "libsph/core/time_stepper.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace sph {
namespace {

// A quotient that is a whole number up to round-off must not cost an extra step.
constexpr Real rounding = Real(16) * std::numeric_limits<Real>::epsilon();

Real checked_stable_step(const Stage& stage, Real time) {
  const Real s = stage.stable_time_step();
  if (!(s > 0) || !std::isfinite(s)) {
    std::ostringstream msg;
    msg << "time-step collapse in stage '" << stage.name << "' at time " << time << ": stable step " << s;
    throw std::runtime_error(msg.str());
  }
  return s;
}

/// Number of equal steps of at most `stable` that cover `remaining`.
Real step_count(Real remaining, Real stable) {
  return std::max(Real(1), std::ceil(remaining / stable * (Real(1) - rounding)));
}

}  // namespace

Stage& Stage::then(std::string phase_name, StepAction action) {
  phases.push_back({std::move(phase_name), std::move(action), {}});
  return *this;
}

Stage& Stage::sub_cycle(Stage nested) {
  Phase phase{nested.name, {}, {}};
  phase.nested.push_back(std::move(nested));
  phases.push_back(std::move(phase));
  return *this;
}

Stage& Stage::slot(std::string slot_name) {
  Phase phase{std::move(slot_name), {}, {}};
  phase.slot = true;
  phases.push_back(std::move(phase));
  return *this;
}

namespace {
/// The slot `name` in `stage` or a stage nested in it (depth-first): its stage and position, or null.
std::pair<Stage*, std::size_t> find_slot(Stage& stage, const std::string& name) {
  for (std::size_t k = 0; k < stage.phases.size(); ++k) {
    Phase& phase = stage.phases[k];
    if (phase.slot && phase.name == name) return {&stage, k};
    if (!phase.nested.empty())
      if (auto found = find_slot(phase.nested.front(), name); found.first) return found;
  }
  return {nullptr, 0};
}

Stage& slot_owner(Stage& stage, const std::string& name, std::size_t& position) {
  const auto [owner, k] = find_slot(stage, name);
  if (!owner) throw std::invalid_argument("stage '" + stage.name + "' has no slot '" + name + "'");
  position = k;
  return *owner;
}
}  // namespace

Stage& Stage::fill(const std::string& slot_name, std::string phase_name, StepAction action) {
  if (!action) throw std::invalid_argument("slot '" + slot_name + "': empty action '" + phase_name + "'");
  std::size_t k = 0;
  Stage& owner = slot_owner(*this, slot_name, k);
  owner.phases.insert(owner.phases.begin() + static_cast<std::ptrdiff_t>(k), Phase{std::move(phase_name), std::move(action), {}});
  return *this;
}

Stage& Stage::fill(const std::string& slot_name, Stage nested) {
  std::size_t k = 0;
  Stage& owner = slot_owner(*this, slot_name, k);
  Phase phase{nested.name, {}, {}};
  phase.nested.push_back(std::move(nested));
  owner.phases.insert(owner.phases.begin() + static_cast<std::ptrdiff_t>(k), std::move(phase));
  return *this;
}

bool Stage::has_slot(const std::string& slot_name) const {
  return find_slot(const_cast<Stage&>(*this), slot_name).first != nullptr;
}

void Stage::run_step(Real time, Real dt) const {
  for (const auto& phase : phases) {
    if (phase.slot) continue;
    if (phase.nested.empty()) {
      phase.action(time, dt);
      continue;
    }
    const Stage& inner = phase.nested.front();
    if (!inner.stable_time_step) {
      inner.run_step(time, dt);
      continue;
    }
    // Sub-steps re-sized before each one from the stable step now; the last ends exactly at time + dt.
    const Real end = time + dt;
    Real s = time;
    for (;;) {
      const Real remaining = end - s;
      const Real n = step_count(remaining, checked_stable_step(inner, s));
      if (n <= 1) {
        inner.run_step(s, remaining);
        break;
      }
      const Real sub = remaining / n;
      inner.run_step(s, sub);
      s += sub;
    }
  }
}

Stage make_stage(std::string name, std::function<Real()> stable_time_step, StepAction advance) {
  Stage stage{name, std::move(stable_time_step), {}};
  stage.then(std::move(name), std::move(advance));
  return stage;
}

TimeStepper::TimeStepper(Real start_time, Real end_time) : start_time_(start_time), end_time_(end_time) {
  if (!(end_time >= start_time)) throw std::invalid_argument("time stepper: end time before start time");
}

void TimeStepper::add_stage(Stage stage) { stages_.push_back(std::move(stage)); }

void TimeStepper::fill(const std::string& slot_name, std::string phase_name, StepAction action) {
  for (auto& stage : stages_)
    if (stage.has_slot(slot_name)) {
      stage.fill(slot_name, std::move(phase_name), std::move(action));
      return;
    }
  throw std::invalid_argument("time stepper: no stage has a slot '" + slot_name + "'");
}

void TimeStepper::set_coupling_interval(Real interval) { coupling_interval_ = interval; }

void TimeStepper::add_event(std::string name, EventTimes times, std::function<void(const StepInfo&)> action) {
  if (!(times.interval > 0) || !std::isfinite(times.interval))
    throw std::invalid_argument("time stepper: the interval of '" + name + "' must be positive");
  if (!(times.offset >= 0) || !std::isfinite(times.offset))
    throw std::invalid_argument("time stepper: the offset of '" + name + "' must be >= 0");
  const std::size_t first = times.at_start ? 0 : 1;
  periodic_.push_back({std::move(name), times, first, -std::numeric_limits<Real>::infinity(), std::move(action)});
}

void TimeStepper::add_periodic_callback(Real interval, std::function<void(const StepInfo&)> callback, bool hit_exactly) {
  add_event("callback", {interval, hit_exactly, true, true}, std::move(callback));
}

void TimeStepper::add_step_callback(std::function<void(const StepInfo&)> callback) {
  step_callbacks_.push_back(std::move(callback));
}

Real TimeStepper::event_time(const Periodic& p, std::size_t k) const {
  return start_time_ + p.times.offset + static_cast<Real>(k) * p.times.interval;
}

Real TimeStepper::next_event_time() const {
  Real next = end_time_;
  for (const auto& p : periodic_)
    if (p.times.hit_exactly) next = std::min(next, event_time(p, p.next_index));
  return next;
}

void TimeStepper::checkpoint(StateArchive& archive) {
  archive.io("time", info_.time);
  archive.io("time_step", info_.time_step);
  archive.io("step", info_.step);
  archive.io("end_time", end_time_);
  archive.io("stop_requested", stop_requested_);
  std::size_t n_events = periodic_.size();
  archive.io("events", n_events);
  if (n_events != periodic_.size())
    throw StateError("the state has " + std::to_string(n_events) + " events of the time stepper, the run declares " +
                     std::to_string(periodic_.size()));
  for (std::size_t k = 0; k < periodic_.size(); ++k) {
    auto event = archive.part("event" + std::to_string(k));
    event.io("next_index", periodic_[k].next_index);
    event.io("last_fired", periodic_[k].last_fired);
  }
  if (archive.loading()) {
    info_.start_time = start_time_;
    info_.end_time = end_time_;
    resumed_ = true;
  }
}

std::size_t TimeStepper::run() {
  if (!resumed_) info_ = StepInfo{start_time_, 0, 0, start_time_, end_time_};
  StepInfo& info = info_;
  interrupted_ = false;
  // Fires what is due at time t: events whose time has been reached (a sampling event within a
  // billionth of its interval counts as reached, so an accumulated time one rounding short of the
  // grid does not delay it a step), and at the end time every event that asks for it once more.
  auto fire_due = [&](Real t) {
    const bool at_end = t >= end_time_;
    for (auto& p : periodic_) {
      const Real tolerance = p.times.hit_exactly ? Real(0) : Real(1e-9) * p.times.interval;
      const bool due = event_time(p, p.next_index) <= t + tolerance;
      if (due || (at_end && p.times.at_end && p.last_fired < end_time_)) {
        p.callback(info);
        p.last_fired = t;
        while (event_time(p, p.next_index) <= t + tolerance) ++p.next_index;
      }
    }
  };
  if (!resumed_) fire_due(start_time_);

  Real quantum = 0;  // the smallest step quantum of the top-level stages
  for (const auto& stage : stages_)
    if (stage.step_quantum > 0) quantum = quantum > 0 ? std::min(quantum, stage.step_quantum) : stage.step_quantum;

  Real t = info.time;
  while (t < end_time_) {
    const Real event = next_event_time();
    Real stable = std::numeric_limits<Real>::infinity();
    for (const auto& stage : stages_)
      if (stage.stable_time_step) stable = std::min(stable, checked_stable_step(stage, t));
    if (coupling_interval_ > 0) stable = std::min(stable, coupling_interval_);
    // Even out the steps up to the next event: n = ceil(remaining / stable) equal steps; or, when the
    // event lies a whole number of quanta ahead, steps of as many whole quanta as are stable.
    const Real remaining = event - t;
    Real dt = remaining;
    if (std::isfinite(stable) && remaining > stable) {
      const Real quanta = quantum > 0 ? remaining / quantum : Real(0.5);
      if (std::abs(quanta - std::round(quanta)) < Real(1e-6))
        dt = std::max(Real(1), std::floor(stable / quantum * (1 + rounding))) * quantum;
      else
        dt = remaining / step_count(remaining, stable);
    }
    const bool reaches_event = dt >= remaining;
    for (const auto& stage : stages_) stage.run_step(t, dt);
    t = reaches_event ? event : t + dt;
    info.time = t;
    info.time_step = dt;
    ++info.step;
    for (const auto& callback : step_callbacks_) callback(info);
    if (stop_requested_ && t < end_time_) end_time_ = info.end_time = t;
    fire_due(t);
    if (interruption_check_ && t < end_time_ && interruption_check_(info)) {
      interrupted_ = true;
      break;
    }
  }
  resumed_ = false;
  return info.step;
}

}  // namespace sph
