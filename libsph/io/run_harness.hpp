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

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "libsph/core/neighbour_relation.hpp"
#include "libsph/core/particles.hpp"
#include "libsph/core/section_timers.hpp"
#include "libsph/core/time_stepper.hpp"
#include "libsph/io/particle_output.hpp"
#include "libsph/io/run_report.hpp"
#include "libsph/io/time_series.hpp"

namespace sph {

class RunHarness {
 public:
  struct Options {
    std::filesystem::path output_dir;  ///< exists; every file goes here
    std::string label;                 ///< shown in the progress line
    bool quiet = false;
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
    report_.memory_bytes[name + "_relation"] = relation.bytes();
  }
  /// A CSV time series `file` with the columns "time" and `columns`: a row at the start, at the
  /// first step at or after every `interval`, and at the end.
  void add_time_series(const std::string& file, std::vector<std::string> columns, Real interval, Row row);

  /// Time spent in named parts (timed phases of the stages, sampling, output).
  SectionTimers& timers() { return timers_; }
  /// Runs the stepper (once); returns the number of macro steps (see above for the report and failures).
  std::size_t run();
  /// Wall time of the time loop of run() [s].
  double time_loop_seconds() const { return time_loop_seconds_; }

 private:
  void write_bodies(double time);

  TimeStepper& stepper_;
  RunReport& report_;
  Options options_;
  SectionTimers timers_;
  std::vector<std::function<void(double)>> writers_;
  std::vector<std::unique_ptr<TimeSeriesCsv>> series_;
  double time_loop_seconds_ = 0;
  double last_completed_;
  std::unique_ptr<class Progress> progress_;
};

template <int Dim>
void RunHarness::add_body(ParticleSet<Dim>& body, Real output_interval, std::function<void(double)> prepare) {
  auto output = std::make_shared<ParticleOutput<Dim>>(options_.output_dir, body.name());
  auto write = [this, &body, output, prepare = std::move(prepare)](double time) {
    timers_.measure("output_and_sampling", [&] {
      if (prepare) prepare(time);
      output->write(body, time);
    });
  };
  writers_.push_back(write);
  const Real interval = output_interval > 0 ? output_interval : stepper_.end_time() - stepper_.start_time();
  if (interval > 0) stepper_.add_periodic_callback(interval, [write](const StepInfo& s) { write(double(s.time)); });
  else write(double(stepper_.start_time()));
  report_.particles[body.name()] = body.n_particles();
  report_.memory_bytes[body.name() + "_fields"] = body.bytes_per_particle() * body.n_particles();
}

}  // namespace sph
