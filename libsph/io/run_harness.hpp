#pragma once
// The run harness every scene uses: particle output, time series, progress, timing, memory and the
// last state on failure, attached to a TimeStepper as callbacks (libsph/core/time_stepper.hpp).
//
//   sph::TimeStepper stepper(0, end_time);
//   stepper.add_stage(...);                            // the physics
//   sph::RunHarness run(stepper, report, {output_dir, "scene", quiet});
//   run.add_body(body, output_interval, prepare);      // <body>.pvd + <body>_NNNNN.vtu
//   run.add_relation("body", relation);                // its memory in report.json
//   run.add_time_series("observers.csv", columns, interval, row);
//   run.run();
//
// What it writes into the report: steps, simulated_time, particles {body: count}, memory_bytes
// {<body>_fields, <relation>_relation}, results.seconds {every timed section, output_and_sampling,
// time_loop} and results.peak_rss_mb. On a NumericalFailure it finishes the progress line, writes
// every body once more as it stands at the failure (a solid has restored its last good state), sets
// simulated_time to the last completed step, and passes the error on; the time series keep every
// row recorded so far.
//
// Distributed runs (libsph/core/distribution.hpp): every rank runs the harness (its samplers and
// writers gather from all ranks), rank 0 alone writes files and shows progress; a distributed body
// is gathered to rank 0 and written whole, in global-id order, as a serial run writes it.
//
// Checkpoints (libsph/io/checkpoint.hpp), when Options::checkpoint is enabled: after every macro step
// whose events have fired, the harness writes <output>/checkpoint.bin if a checkpoint interval has
// passed, and also stops the run there (RunInterrupted, after closing the time series) when an
// interruption was requested (signal, interrupt time). The state saved is the stepper's, the
// harness's own (timers, next checkpoint), every body added (all of its fields and its output list),
// every time series (its rows) and what the scene adds with add_state (its other changing
// members). With Options::checkpoint.resume, run() loads all of it and continues from there.

#include <chrono>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "libsph/core/distribution.hpp"
#include "libsph/core/neighbour_relation.hpp"
#include "libsph/core/particles.hpp"
#include "libsph/core/section_timers.hpp"
#include "libsph/core/state_archive.hpp"
#include "libsph/core/time_stepper.hpp"
#include "libsph/io/checkpoint.hpp"
#include "libsph/io/particle_output.hpp"
#include "libsph/io/run_report.hpp"
#include "libsph/io/time_series.hpp"

namespace sph {

/// What a scene's observers accumulate over a run outside the bodies: named scalars (extremes, sums,
/// the last sample, a time of an event) and named series (recorded crossings, beat times), kept in
/// checkpoints as one component (RunHarness::keep). A name's reference stays valid for the record's
/// life; declare every name before the run (a resumed run loads what it declared).
class RunRecord {
 public:
  /// The scalar `name` (`initial` at its first use).
  double& value(const std::string& name, double initial = 0) { return values_.try_emplace(name, initial).first->second; }
  /// The series `name` (empty at its first use).
  std::vector<double>& series(const std::string& name) { return series_[name]; }
  void checkpoint(StateArchive& archive) {
    for (auto& [name, v] : values_) archive.io(name, v);
    for (auto& [name, v] : series_) archive.io(name, v);
  }

 private:
  std::map<std::string, double> values_;
  std::map<std::string, std::vector<double>> series_;
};

class RunHarness {
 public:
  struct Options {
    std::filesystem::path output_dir;  ///< exists; every file goes here
    std::string label;                 ///< shown in the progress line
    bool quiet = false;
    CheckpointPlan checkpoint = {};    ///< disabled unless the scene saves its whole state
  };
  /// Row of a time series after its time column.
  using Row = std::function<std::vector<double>(const StepInfo&)>;

  /// The stepper, the report and everything added must outlive the harness.
  RunHarness(TimeStepper& stepper, RunReport& report, Options options);
  ~RunHarness();
  RunHarness(const RunHarness&) = delete;
  RunHarness& operator=(const RunHarness&) = delete;

  /// Writes `body` as <name>.pvd with <name>_NNNNN.vtu at the start, every `output_interval` (hit
  /// exactly) and at the end; 0 writes the first and last state only. prepare(time) runs before
  /// each write (e.g. the output fields of a solid). Counts the body and its fields in the report.
  template <int Dim>
  void add_body(ParticleSet<Dim>& body, Real output_interval, std::function<void(double time)> prepare = {});
  /// Counts the relation's memory in the report as <name>_relation.
  template <int Dim>
  void add_relation(const std::string& name, const NeighbourList<Dim>& relation) {
    report_.memory_bytes.set(name + "_relation", relation.bytes());
  }
  /// A CSV time series `file` with the columns "time" and `columns`: a row at the start, at the
  /// first step at or after every `interval`, and at the end.
  void add_time_series(const std::string& file, std::vector<std::string> columns, Real interval, Row row);

  /// State of the scene beyond its bodies and series, saved and loaded under `name` by `state`
  /// (the same function for both directions, see libsph/core/state_archive.hpp).
  void add_state(const std::string& name, std::function<void(StateArchive&)> state);
  /// A component that declares what it changes over the run outside the particle fields: a system, a
  /// recorder, an observer or a coupling with a member checkpoint(StateArchive&) (saving and loading
  /// with the same code); kept under `name`. It must outlive the harness. One line per component:
  /// scenes list no state by hand.
  template <class Component>
    requires requires(Component& c, StateArchive& a) { c.checkpoint(a); }
  void keep(const std::string& name, Component& component) {
    add_state(name, [&component](StateArchive& a) { component.checkpoint(a); });
  }
  /// A particle set that is not written as output but changes during the run (all its fields are saved).
  template <int Dim>
  void add_state(ParticleSet<Dim>& body) {
    add_state("body/" + body.name(), [&body](StateArchive& a) { body.checkpoint(a); });
  }

  /// Time spent in named parts (timed phases of the stages, sampling, output).
  SectionTimers& timers() { return timers_; }
  /// Runs the stepper (once); returns the number of macro steps (see above for the report and failures).
  std::size_t run();
  /// Wall time of the time loop of run() [s] (resumed: with the time before the checkpoint).
  double time_loop_seconds() const { return time_loop_seconds_; }

 private:
  void write_bodies(double time);
  /// Writes results.distribution.<body> (collective): owned particles per rank (min, max), ghosts
  /// (total, largest per rank, as a fraction of the owned ones), neighbour ranks (largest).
  void report_partition(const std::string& body, std::size_t owned, std::size_t ghosts, std::size_t neighbours);
  /// Writes results.distribution.traffic (collective, several ranks only): what the time loop sent
  /// since `before` per macro step (output and sampling included): halo exchanges, messages and
  /// bytes (the busiest rank's and all ranks'), collective operations.
  void report_traffic(const Communicator::Traffic& before);
  void save_or_load(StateArchive& archive);
  /// After a step: writes a checkpoint when one is due or asked for; true to stop the run there.
  bool checkpoint_after_step(const StepInfo& s);

  TimeStepper& stepper_;
  RunReport& report_;
  Options options_;
  SectionTimers timers_;
  std::vector<std::function<void(double)>> writers_;
  std::vector<std::unique_ptr<TimeSeriesCsv>> series_;  ///< null on ranks other than 0
  bool writes_files_ = Communicator::world().is_root();
  std::vector<std::pair<std::string, std::function<void(StateArchive&)>>> states_;
  std::size_t next_checkpoint_ = 1;
  bool fixed_layout_ = true;  ///< no body's particles migrate between ranks (a checkpoint can restore them)
  double time_loop_before_ = 0;
  std::chrono::steady_clock::time_point loop_start_;  ///< wall time of the time loop before the checkpoint resumed from  ///< the next periodic checkpoint is at start + next_checkpoint_ * interval
  double time_loop_seconds_ = 0;
  double last_completed_;
  std::unique_ptr<class Progress> progress_;
};

template <int Dim>
void RunHarness::add_body(ParticleSet<Dim>& body, Real output_interval, std::function<void(double)> prepare) {
  auto output = std::make_shared<ParticleOutput<Dim>>(options_.output_dir, body.name());
  auto whole = std::make_shared<ParticleSet<Dim>>();  // rank 0's gathered copy of a distributed body
  auto write = [this, &body, output, whole, prepare = std::move(prepare)](double time) {
    timers_.measure("output_and_sampling", [&] {
      if (prepare) prepare(time);
      if (!body.partition()) {  // a body every rank holds whole (the walls of a distributed fluid)
        if (writes_files_) output->write(body, time);
        return;
      }
      if (distributed_output_in_pieces()) {
        output->write_piece(body, time);
        return;
      }
      gather_particles(body, *whole);
      if (writes_files_) output->write(*whole, time);
    });
  };
  writers_.push_back(write);
  add_state("body/" + body.name(), [&body, output](StateArchive& a) {
    body.checkpoint(a);
    output->checkpoint(a);
  });
  const Real interval = output_interval > 0 ? output_interval : stepper_.end_time() - stepper_.start_time();
  if (interval > 0) stepper_.add_periodic_callback(interval, [write](const StepInfo& s) { write(double(s.time)); });
  else write(double(stepper_.start_time()));
  report_.particles.set(body.name(), body.partition() ? body.partition()->n_global : body.n_particles());
  if (const auto* p = body.partition()) {
    fixed_layout_ = fixed_layout_ && !p->moves;
    std::size_t neighbours = 0, halo = 0;
    for (const auto& list : p->receive) {
      neighbours += !list.empty();
      halo += list.size();
    }
    report_partition(body.name(), p->n_owned, halo, neighbours);
  }
  report_.memory_bytes.set(body.name() + "_fields", body.bytes_per_particle() * body.n_particles());
}

}  // namespace sph
