#pragma once
// What the tissue electrophysiology scenes share: their numerical parameters, and the run of one
// monodomain body (time loop, particle output, observers, progress, report of the time spent in
// reaction and diffusion). On numerical failure the state at the failure is written for
// inspection, then the error is passed on (the run ends as failed, exit code 1).

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "apps/scenes/discretisation.hpp"
#include "apps/scenes/run_plan.hpp"
#include "apps/scenes/scene.hpp"
#include "cardio/monodomain.hpp"
#include "libsph/core/point_probes.hpp"
#include "libsph/core/time_stepper.hpp"
#include "libsph/io/run_harness.hpp"

namespace cardiosph {

/// Numerical settings shared by the tissue electrophysiology scenes: the discretisation, and the
/// monodomain's own choices bound directly (cardio::MonodomainNumerics).
struct EpSceneNumerics {
  Discretisation discretisation;
  cardio::MonodomainNumerics monodomain;
  /// Action potential maps at this repolarisation percentage (cardio/ep_maps.hpp); 0: none.
  double apd_percent = 0;
};

void declare_ep_numerics(sph::Parameters& p, EpSceneNumerics& n, const std::string& time_unit);

/// Declares apd_percent, the repolarisation percentage of the action potential maps (0: none).
void declare_apd_percent(sph::Parameters& p, double& percent);

/// The bidomain conductivities and the membrane of a tissue, for the monodomain (defaults: the
/// values of Niederer et al. 2011).
struct TissueProperties {
  double sigma_il = 0.17, sigma_it = 0.019, sigma_el = 0.62, sigma_et = 0.24;  ///< [S/m]
  double surface_to_volume = 140;  ///< chi [1/mm]
  double capacitance = 0.01;       ///< C_m [uF/mm^2]
  /// D along and across the fibres [mm^2/ms]: the harmonic means sigma_i sigma_e / (sigma_i + sigma_e)
  /// over chi C_m.
  std::pair<sph::Real, sph::Real> diffusivities() const;
  /// The applied dV/dt [mV/ms] of a stimulus current density [uA/mm^3]: I / (chi C_m).
  double stimulus_rate(double current) const { return current / (surface_to_volume * capacitance); }
};

/// Declares sigma_il, sigma_it, sigma_el, sigma_et, surface_to_volume and capacitance.
void declare_parameters(sph::Parameters& p, TissueProperties& t);

struct EpRunPlan : RunPlan {  // sample_interval 0: end_time / 1000; observers.csv is the probes' potential
  EpRunPlan(std::string scene_name, double end, double output, double sample, std::vector<std::string> probes) {
    scene = std::move(scene_name), end_time = end, output_interval = output, sample_interval = sample;
    probe_names = std::move(probes);
  }
  bool stop_when_all_activated = false;  ///< end the run once every particle has been activated
  std::vector<std::string> probe_names;  ///< one per probe, for the CSV header
  std::function<void(sph::RunHarness&)> before_run;     ///< adds further outputs (may be empty)
};

/// Sampled potential at the probes.
struct EpTraces {
  std::vector<double> time;
  std::vector<std::vector<double>> potential;  ///< [probe][sample]
  void checkpoint(sph::StateArchive& a) {
    a.io("time", time);
    for (std::size_t p = 0; p < potential.size(); ++p) a.io("potential" + std::to_string(p), potential[p]);
  }
};

/// Runs the monodomain from t = 0. Writes, named after the particle set, <body>_*.vtu + <body>.pvd,
/// and observers.csv (time and the potential at each probe) into ctx.output_dir; fills steps, particles, memory, simulated time
/// and the timings (reaction, diffusion, cell updates per second) in ctx.report.
template <int Dim>
EpTraces run_monodomain(cardio::Monodomain<Dim>& monodomain, sph::ParticleSet<Dim>& body,
                        const sph::NeighbourList<Dim>& relation, const sph::PointProbes<Dim>& probes,
                        const EpRunPlan& plan, RunContext& ctx);

/// The action potential maps of `monodomain` summarised for report.json: per map (APD, diastolic
/// interval, maximum upstroke velocity, conduction velocity) the number of particles with a value and
/// its minimum, 10th percentile, median, 90th percentile and maximum, and the time spent on the maps.
/// Updates the conduction velocity first. Null without maps.
template <int Dim>
nlohmann::json ep_map_summary(cardio::Monodomain<Dim>& monodomain);

/// Times at which a trace rises through `level` (linear interpolation between samples).
std::vector<double> upward_crossings(const std::vector<double>& time, const std::vector<double>& value, double level);

}  // namespace cardiosph
