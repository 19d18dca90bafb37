#pragma once
// The time loop of every scene. Scenes declare stages (a named advance with its own stable step)
// and callbacks (output, observers, progress); they do not write loops.
//
// Each macro step has the size
//   dt = min( stable steps of the stages that are not sub-cycled, coupling_interval,
//             time left to the next event ),
// and every stage advances over [t, t + dt] in order; a sub-cycled stage splits dt into
// ceil(dt / its stable step) equal sub-steps. Events (callback times and the end time) are hit
// exactly: time is start + k * interval, never an accumulated sum, and the steps before an event
// are evened out so that no sliver of a step is left. Callbacks at t = start run before any step.

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "libsph/core/types.hpp"

namespace sph {

struct StepInfo {
  Real time = 0;         ///< time reached
  Real time_step = 0;    ///< size of the macro step that reached it (0 before the first step)
  std::size_t step = 0;  ///< macro steps taken so far
  Real start_time = 0;
  Real end_time = 0;
};

struct Stage {
  std::string name;
  std::function<Real()> stable_time_step;         ///< largest stable step now
  std::function<void(Real time, Real dt)> advance;  ///< advance from time by dt
  bool sub_cycled = false;
};

class TimeStepper {
 public:
  TimeStepper(Real start_time, Real end_time);

  void add_stage(Stage stage);
  /// Limits the macro step (the interval at which sub-cycled stages synchronise); 0 = no limit.
  void set_coupling_interval(Real interval);
  /// callback(info) at start, start + interval, ..., and at the end time (once). With
  /// hit_exactly (outputs) the steps are shortened to land on those times; without (observers that
  /// sample a time series) the callback runs at the first step at or after each of them.
  void add_periodic_callback(Real interval, std::function<void(const StepInfo&)> callback, bool hit_exactly = true);
  /// callback(info) after every macro step.
  void add_step_callback(std::function<void(const StepInfo&)> callback);

  /// Ends the run after the current step (from a step callback): the periodic callbacks then fire
  /// once more at the time reached, as they do at the end time.
  void stop_after_this_step() { stop_requested_ = true; }
  /// The end time, or the time at which the run was stopped.
  Real end_time() const { return end_time_; }

  /// Runs from the start to the end time; returns the number of macro steps. Throws
  /// std::runtime_error if a stage's stable step is not positive and finite (time-step collapse).
  std::size_t run();

 private:
  struct Periodic {
    Real interval;
    std::size_t next_index;  ///< next event is start + next_index * interval
    Real last_fired;
    bool hit_exactly;
    std::function<void(const StepInfo&)> callback;
  };
  Real next_event_time() const;

  Real start_time_, end_time_;
  Real coupling_interval_ = 0;
  std::vector<Stage> stages_;
  std::vector<Periodic> periodic_;
  std::vector<std::function<void(const StepInfo&)>> step_callbacks_;
  bool stop_requested_ = false;
};

}  // namespace sph
