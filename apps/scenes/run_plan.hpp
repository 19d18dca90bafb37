#pragma once
// What every family's run of a scene is given (run_solid, run_monodomain, run_fluid): the scene's
// name, its times, its observers and the components it keeps in checkpoints. A family's plan adds
// only what its systems need (loads of a solid, the stop on full activation, the bodies around a
// fluid); the run function declares the systems' stages on a sph::TimeStepper and attaches the plan
// to the sph::RunHarness with attach().

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "libsph/core/state_archive.hpp"
#include "libsph/core/time_stepper.hpp"
#include "libsph/io/run_harness.hpp"

namespace cardiosph {

struct RunPlan {
  RunPlan() = default;
  RunPlan(std::string scene_name, double end, double output) : scene(std::move(scene_name)), end_time(end), output_interval(output) {}

  std::string scene;                          ///< name shown in the progress line
  double end_time = 0;
  double output_interval = 0;                 ///< 0: first and last state only
  double sample_interval = 0;                 ///< observers and series (0: the family's default)
  std::vector<std::string> observer_columns;  ///< columns of observers.csv after time (none: no file)
  sph::RunHarness::Row observers;             ///< their values at a sample time
  std::function<void(const sph::StepInfo&)> every_step;  ///< after every macro step (may be empty)

  /// Keeps `component` in the checkpoints under "scene/<name>": a recorder, an observer or a
  /// sph::RunRecord of what the scene's callbacks change outside the bodies, whose member
  /// checkpoint(sph::StateArchive&) saves and loads all of it; it must outlive the run. Checkpoints
  /// are taken only in scenes whose Scene::checkpoints() is true: those keep all they change.
  template <class Component>
  void keep(std::string name, Component& component) {
    kept.emplace_back(std::move(name), [&component](sph::StateArchive& a) { component.checkpoint(a); });
  }
  std::vector<std::pair<std::string, std::function<void(sph::StateArchive&)>>> kept;

  /// observers.csv every `interval` (if the plan has columns) and the kept components.
  void attach(sph::RunHarness& run, sph::Real interval) const {
    if (!observer_columns.empty()) run.add_time_series("observers.csv", observer_columns, interval, observers);
    for (const auto& [name, state] : kept) run.add_state("scene/" + name, state);
  }
};

}  // namespace cardiosph
