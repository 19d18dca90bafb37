#pragma once
// The time loop of every scene. Scenes declare stages, events and callbacks; they do not write loops.
//
// A stage is one level of the loop: it takes steps no larger than its own stable step and, within
// each of its steps [t, t + dt], runs its phases in order. A phase is either an action over the
// whole step (`then`) or a nested stage (`sub_cycle`) that covers [t, t + dt] in sub-steps of its
// own. Nesting has no depth limit, so dual-criteria fluid stepping (an advection step holding
// acoustic steps, each holding solid sub-steps) or EP diffusion sub-steps inside a reaction step are
// declarations:
//
//   Stage advection{"advection", advection_step};
//   Stage acoustic{"acoustic", acoustic_step};
//   acoustic.then("first half", first_half).sub_cycle(solid_stage).then("second half", second_half);
//   advection.then("neighbours", rebuild).sub_cycle(std::move(acoustic));
//   stepper.add_stage(std::move(advection));
//
// Step sizes. The macro step of the stepper is
//   dt = min( stable steps of the top-level stages, coupling_interval, time left to the next event ),
// evened out before events so that no sliver of a step is left (or, for a stage with a step quantum,
// cut into whole quanta). A nested stage covering [t, t + dt]
// evaluates its stable step s before every sub-step and takes the next sub-step as
//   remaining / ceil(remaining / s),
// so its step follows the state (not fixed once per parent step), the sub-steps left are always
// equal, and the last ends exactly at t + dt. A stage without a stable step takes its parent's step.
//
// Slots. A system declares its step as a stage of named phases (docs/architecture.md has the table
// of every system) with empty, named slots where other systems act between its parts: the loads of
// an elastic solid between its stress and its kick, the forces on bodies in a fluid's step. A scene
// fills a slot with the couplings it declares (libsph/core/interaction.hpp):
//
//   sph::Stage mechanics = solid.stage("mechanics");          // ... | stress | [loads on 'wall'] | kick
//   mechanics.fill(solid.loads_slot(), "cavity pressure", sph::coupling(solid, cavities, sph::same_particles));
//
// A filled slot runs its phases in the order they were added; an empty one does nothing. `fill`
// searches the stage and its nested stages depth-first, and TimeStepper::fill its top-level stages,
// so a slot can be filled after its stage was handed on.
//
// Events and callbacks. Times are start + offset + k * interval, never an accumulated sum. An event with
// hit_exactly shortens the steps to land on its times; without, it runs at the first step at or
// after each of them (sampling). Periodic work of the physics (the conduction update, neighbour
// rebuilds, re-sorting) is an event, output and observers are callbacks: both run between macro
// steps, in the order they were added. By default they also run at the start (before any step) and
// once at the end time; `EventTimes` turns either off.

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "libsph/core/state_archive.hpp"
#include "libsph/core/types.hpp"

namespace sph {

struct StepInfo {
  Real time = 0;         ///< time reached
  Real time_step = 0;    ///< size of the macro step that reached it (0 before the first step)
  std::size_t step = 0;  ///< macro steps taken so far
  Real start_time = 0;
  Real end_time = 0;
};

/// An action over one step of its stage: advance from `time` by dt.
using StepAction = std::function<void(Real time, Real dt)>;

struct Stage;

/// One entry of a stage's step: an action, or a nested stage (exactly one of the two).
struct Phase {
  std::string name;
  StepAction action;
  std::vector<Stage> nested;  ///< empty, or the one nested stage
  bool slot = false;          ///< a named place for phases added later (`Stage::fill`); runs nothing
};

struct Stage {
  std::string name;
  std::function<Real()> stable_time_step;  ///< largest stable step now; empty: the parent's step
  std::vector<Phase> phases;
  /// > 0 (top-level stages): the stage's steps are whole multiples of this quantum, e.g. a coupling
  /// step of whole EP steps. Up to an event that lies a whole number of quanta ahead, the stepper then
  /// takes steps of floor(stable / quantum) quanta, the last one the rest, instead of evening them out.
  Real step_quantum = 0;

  /// Appends an action over the whole step.
  Stage& then(std::string phase_name, StepAction action);
  /// Appends a nested stage that sub-cycles over each step of this one at its own stable step.
  Stage& sub_cycle(Stage nested);
  /// Appends an empty slot named `slot_name` (see "Slots" above).
  Stage& slot(std::string slot_name);
  /// Adds an action (or a nested stage) at the end of the slot `slot_name` of this stage or of a
  /// stage nested in it (depth-first). Throws std::invalid_argument naming the slot and the stage if
  /// there is no such slot.
  Stage& fill(const std::string& slot_name, std::string phase_name, StepAction action);
  Stage& fill(const std::string& slot_name, Stage nested);
  /// True if this stage or a stage nested in it has the slot.
  bool has_slot(const std::string& slot_name) const;
  /// Runs this stage over [time, time + dt] (the phases once; nested stages in sub-steps).
  void run_step(Real time, Real dt) const;
};

/// A single-action stage: advance(t, dt) at steps of stable_time_step.
Stage make_stage(std::string name, std::function<Real()> stable_time_step, StepAction advance);

struct EventTimes {
  Real interval = 0;         ///< > 0
  bool hit_exactly = true;   ///< shorten steps to land on the times (else: first step at or after)
  bool at_start = true;      ///< also at the start time, before any step
  bool at_end = true;        ///< also once at the end time (or where the run stopped)
  Real offset = 0;           ///< the times are start + offset + k interval (at_start: the first of them)
};

class TimeStepper {
 public:
  TimeStepper(Real start_time, Real end_time);

  /// Adds a top-level stage: its stable step limits the macro step; it runs once per macro step.
  void add_stage(Stage stage);
  /// Stage::fill on the first top-level stage that has the slot; throws std::invalid_argument if none has.
  void fill(const std::string& slot_name, std::string phase_name, StepAction action);
  /// Limits the macro step (the interval at which the top-level stages synchronise); 0 = no limit.
  void set_coupling_interval(Real interval);
  /// Periodic work at the given times (see EventTimes); `name` goes into error messages.
  void add_event(std::string name, EventTimes times, std::function<void(const StepInfo&)> action);
  /// Output or sampling: callback(info) at start, start + interval, ..., and at the end time
  /// (once). With hit_exactly (outputs) the steps are shortened to land on those times; without
  /// (observers that sample a time series) the callback runs at the first step at or after each.
  void add_periodic_callback(Real interval, std::function<void(const StepInfo&)> callback, bool hit_exactly = true);
  /// callback(info) after every macro step.
  void add_step_callback(std::function<void(const StepInfo&)> callback);

  /// check(info) after every macro step, once the events due at its time have fired; returning
  /// true interrupts the run there: run() returns without the end-time events and interrupted()
  /// is true (checkpoints: the state is then complete up to that time).
  void set_interruption_check(std::function<bool(const StepInfo&)> check) { interruption_check_ = std::move(check); }
  bool interrupted() const { return interrupted_; }
  /// Saves or loads the time reached, the steps taken, the end time and every event's next time
  /// (checkpoints). Between macro steps only; after loading, run() continues from the loaded time
  /// without firing the start events again. The stages and events must be declared as when saved.
  void checkpoint(StateArchive& archive);

  /// Ends the run after the current step (from a step callback): the periodic callbacks then fire
  /// once more at the time reached, as they do at the end time.
  void stop_after_this_step() { stop_requested_ = true; }
  /// The end time, or the time at which the run was stopped.
  Real end_time() const { return end_time_; }
  Real start_time() const { return start_time_; }

  /// Runs from the start to the end time; returns the number of macro steps. Throws
  /// std::runtime_error if a stage's stable step is not positive and finite (time-step collapse).
  std::size_t run();

 private:
  struct Periodic {
    std::string name;
    EventTimes times;
    std::size_t next_index;  ///< next event is start + next_index * interval
    Real last_fired;
    std::function<void(const StepInfo&)> callback;
  };
  Real next_event_time() const;
  Real event_time(const Periodic& p, std::size_t k) const;

  Real start_time_, end_time_;
  Real coupling_interval_ = 0;
  std::vector<Stage> stages_;
  std::vector<Periodic> periodic_;
  std::vector<std::function<void(const StepInfo&)>> step_callbacks_;
  std::function<bool(const StepInfo&)> interruption_check_;
  bool stop_requested_ = false;
  bool interrupted_ = false;
  bool resumed_ = false;      ///< a loaded state: run() continues from info_
  StepInfo info_;             ///< the time reached and the steps taken
};

}  // namespace sph
