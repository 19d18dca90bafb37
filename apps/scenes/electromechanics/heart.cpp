// `cardiosph heart`: excitation-contraction of a ventricular mesh on one particle set, beating
// against a circulation.
//
// Geometry: the cached heart-geometry stage (particles, surface labels, LDRB fibres). Physics
// (docs/electromechanics.md, "A physiological beat"): monodomain with ten Tusscher-Panfilov 2006
// (or Aliev-Panfilov) cells, conduction D_l along the fibre and D_t across, pulled back through F
// (cardio/electromechanics.hpp); Land et al. 2017 tension from the cells' calcium and the fibre
// stretch (or Nash-Panfilov from the potential; cardio/active_tension.hpp); Holzapfel-Ogden
// passive law plus the active stress T_a f0 (x) f0; pericardial and base springs (or a clamped
// base; cardio/boundary_springs.hpp). Cavity volumes from the labelled endocardia moved with the
// tissue, and their pressure on the wall (cardio/cavities.hpp); the cavity pressure from the 0D
// circulation (cardio/circulation_coupling.hpp: closed loop or Windkessel, after a preload) or
// constant, ramped or none. The run ends when the stroke volumes settle.
//
// The parts: the parameters (heart_parameters.hpp), the systems on one particle set
// (heart_model.hpp), what is recorded (heart_output.hpp). Every coupling is an interaction
// (libsph/core/interaction.hpp), declared below as a phase of a stage:
//   electromechanics  (cardio/electromechanics.hpp) EP steps | active tension | mechanics sub-steps,
//                     each  active stress | half drift | stress | [loads on 'heart'] | kick and drift,
//                     the loads slot filled with  solid <- cavities (cavity pressure), then
//                     solid <- springs (epicardium, base), at the mid-step of each sub-step;
//   circulation       circulation <- cavities | cavity pressure <- circulation, after each coupling step.
//
// Outputs: heart_*.vtu / heart.pvd (potential, activation time, T_a, displacement, J, fibre stretch,
// von Mises stress, labels, fibres), cavities.csv (volumes, pressures, energies, J range, peak T_a),
// observers.csv (potential, T_a and displacement at three particles), circulation.csv and
// pv_loop.png (with the circulation), report.json (per-beat PV measures, healthy ranges, timings).
#include <algorithm>
#include <chrono>
#include <iostream>
#include <optional>

#include "apps/scenes/electromechanics/em_scenes.hpp"
#include "apps/scenes/electromechanics/heart_output.hpp"
#include "apps/scenes/electrophysiology/ep_run.hpp"
#include "cardio/electromechanics.hpp"
#include "libsph/core/distribution.hpp"
#include "libsph/io/parameters.hpp"

namespace cardiosph {
namespace {

class HeartScene final : public Scene {
 public:
  HeartScene() : p_(heart_defaults()) {}
  void declare(sph::Parameters& p) override { declare_heart_parameters(p, p_); }
  void check() const override { check_heart_parameters(p_); }
  void run(RunContext& ctx) override;
  bool checkpoints() const override { return true; }
  bool distributes() const override { return true; }

 private:
  HeartParameters p_;
};

// The scene as a short program: geometry, systems, coupling, run, report.
void HeartScene::run(RunContext& ctx) {
  const auto wall_start = std::chrono::steady_clock::now();
  auto log = [&](const std::string& line) {
    if (!ctx.quiet) std::cout << line << '\n' << std::flush;
  };

  // 1. Geometry: the cached stage (particles, surface labels, LDRB fibres).
  const auto gs = p_.geometry.resolved(preset_spacing(p_.preset));
  if (gs.fibres == "none") throw sph::ParameterError("parameter 'fibres' = none: the heart needs fibre directions");
  const auto g = cardio::prepare_heart_geometry(gs, p_.geometry.cache_folder(), log);
  const auto& comm = sph::Communicator::world();

  // 2. Systems: solid, monodomain, active tension, cavities and springs on one particle set.
  HeartModel heart(p_, g, gs);
  auto& body = *heart.body;
  auto& solid = *heart.solid;
  auto& monodomain = *heart.monodomain;
  auto& cavities = *heart.cavities;
  const bool circulation_mode = p_.cavity_pressure.mode == cardio::CavityPressureMode::circulation;
  if (circulation_mode) cardio::CirculationCoupling::require_cavities(cavities);

  // 3. Coupling: the electromechanical stage and its conduction update (cardio/electromechanics.hpp);
  // in the solid's loads slot the cavity pressure, then the springs.
  const double end_time = p_.end_time > 0 ? p_.end_time : beat_origin(p_) + double(p_.beats) * p_.cycle_length;
  sph::TimeStepper stepper(0, Real(end_time));
  sph::RunHarness run(stepper, ctx.report, {ctx.output_dir, "heart", ctx.quiet, ctx.checkpoint});
  cardio::add_electromechanics<3>(stepper, monodomain, *heart.tension, solid, p_.coupling, run.timers());
  if (cavities.loaded())
    stepper.fill(solid.loads_slot(), "cavity pressure", sph::coupling(solid, cavities, sph::same_particles));
  if (heart.springs && !heart.springs->springs().empty())
    stepper.fill(solid.loads_slot(), "boundary springs", sph::coupling(solid, *heart.springs, sph::same_particles));

  // 4. Outputs and run.
  run.add_body(body, Real(p_.numerics.discretisation.output_interval), [&](double) {
    solid.update_output_fields();
    monodomain.update_conduction_velocity();
  });
  run.add_relation("heart", *heart.relation);
  // What changes besides the particle fields (checkpoints; the relation is in the reference configuration).
  run.add_state("heart", [&](sph::StateArchive& a) {
    auto solid_part = a.part("solid"), monodomain_part = a.part("monodomain"), tension = a.part("tension");
    auto cavities_part = a.part("cavities");
    solid.checkpoint(solid_part);
    monodomain.checkpoint(monodomain_part);
    heart.tension->checkpoint(tension);
    cavities.checkpoint(cavities_part);
  });
  HeartRecorder recorder(heart, run, stepper, p_);
  std::optional<EcgRecorder> ecg;
  if (p_.ecg.mode != "none") {
    EcgRecorder::Source source{[&] { return std::span<const Real>(body.field(monodomain.potential_field())); },
                               [&] { return std::span<const sph::Mat<3>>(monodomain.diffusion_tensor()); },
                               [&] { return std::span<const Vec3>(body.position); },
                               [&] { return std::span<const sph::Mat<3>>(body.field(solid.deformation_gradient_field())); }};
    ecg.emplace(p_.ecg, heart_electrodes(heart, g, p_.ecg), p_.ecg.mode == "twelve_lead", *heart.relation, heart.X,
                body.volume, heart.dp, source, run, &body);
  }
  // The circulation (cardio/circulation_coupling.hpp): a stage after the electromechanical one,
  // and the beats it measures.
  std::optional<cardio::CirculationCoupling> circulation;
  std::optional<HeartBeats> beats;
  if (circulation_mode) {
    circulation.emplace(p_.circulation, p_.cycle_length, p_.cavity_pressure, beat_origin(p_), cavities);
    cardio::add_circulation_coupling(stepper, *circulation, cavities);
    beats.emplace(*circulation, stepper, run, p_, ctx.quiet);
  }
  auto& r = ctx.report;
  r.results["initial_mechanics_time_step_ms"] = solid.stable_time_step();
  r.results["diffusion_time_step_limit_ms"] = monodomain.diffusion_time_step();
  run.run();

  // 5. Report.
  recorder.report(r);
  // The first beat's QRS (within 150 ms of its stimulus: ventricular activation takes 60-80 ms), T
  // wave and QT interval.
  if (ecg) ecg->finish(ctx.output_dir, r, EcgRecorder::Beat{beat_origin(p_), p_.cycle_length, 150});
  if (monodomain.maps()) r.results["maps"] = ep_map_summary(monodomain);
  // The whole heart's activation (and APD) by global id, on every rank; files from rank 0.
  std::vector<Real> whole_activation, whole_apd;
  const auto activation = sph::gather_all(body, std::span<const Real>(body.field(monodomain.activation_field())), whole_activation);
  const auto* maps = monodomain.maps();
  const auto apd = maps ? sph::gather_all(body, std::span<const Real>(body.field(maps->apd_field())), whole_apd) : std::span<const Real>();
  if (comm.is_root()) write_activation_map(ctx.output_dir, heart, activation, apd, beat_origin(p_));
  if (beats) {
    beats->report(r);
    beats->plot(ctx.output_dir);
    if (!p_.reference_run.empty()) compare_with_reference(r, reference_beats(p_.reference_run), p_.reference_run);
  }
  for (const auto& c : calibrated_parameters())
    r.results["calibration"].push_back({{"parameter", c.key},
                                        {"value", c.value(p_)},
                                        {"calibrated", c.calibrated},
                                        {"target", c.target},
                                        {"tuned_on", c.tuned_on}});
  r.results["particle_spacing_mm"] = heart.dp;
  r.results["geometry_from_cache"] = g.from_cache;
  r.results["label_method"] = g.label_method;
  r.results["fibre_method"] = g.fibre_method;
  if (g.tets) r.results["tetrahedra"] = g.tets;
  r.results["fixed_base_particles"] = heart.base.size();
  r.results["stimulated_particles"] = heart.stimulated;
  for (const auto& site : heart.early)
    r.results["early_activation_sites"].push_back(
        {{"position_mm", {site.position[0], site.position[1], site.position[2]}}, {"time_ms", site.time}});
  // The cell groups, with the median APD of each (the gradient across the wall with layers).
  for (std::size_t k = 0; k < heart.cell_groups.names.size(); ++k) {
    auto& group = r.results["cell_groups"][heart.cell_groups.names[k]];
    group["particles"] = heart.cell_groups.counts[k];
    if (!maps) continue;
    std::vector<double> values;
    for (std::size_t i = 0; i < heart.n(); ++i)
      if ((heart.cell_groups.group.empty() || heart.cell_groups.group[i] == k) && apd[i] > 0) values.push_back(apd[i]);
    if (values.empty()) continue;
    std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(values.size() / 2), values.end());
    group[maps->apd_name() + "_median_ms"] = values[values.size() / 2];
  }
  r.results["stimulus_centre_mm"] = {heart.stimulus_centre[0], heart.stimulus_centre[1], heart.stimulus_centre[2]};
  r.results["diffusivity_mm2_per_ms"] = {heart.D_fibre, heart.D_cross};
  r.results["max_activation_ms"] = monodomain.latest_activation();
  if (monodomain.all_activated()) {
    // The first beat's activation spread: latest minus earliest activation time (healthy human
    // ventricles: 60-80 ms, Durrer et al. 1970).
    const auto [first, last] = std::minmax_element(activation.begin(), activation.end());
    r.results["total_activation_ms"] = double(*last - *first);
  }
  r.results["activated_fraction"] =
      double(std::count_if(activation.begin(), activation.end(), [](Real a) { return a >= 0; })) / double(heart.n());
  const auto& timers = run.timers();
  r.results["seconds"]["geometry"] = g.seconds;
  r.results["seconds"]["reaction"] = monodomain.timings().reaction;
  r.results["seconds"]["diffusion"] = monodomain.timings().diffusion;
  const std::size_t mechanics_substeps = timers.calls("mechanics");
  r.results["mechanics_substeps"] = mechanics_substeps;
  r.results["conduction_updates"] = timers.calls("conduction_update");
  r.results["diffusion_substeps"] = monodomain.diffusion_substeps();
  r.results["reaction_steps_taken"] = monodomain.reaction_steps_taken();
  r.results["ep_steps"] = monodomain.steps();
  if (mechanics_substeps > 0)
    r.results["mechanics_microseconds_per_particle_step"] =
        1e6 * timers.seconds("mechanics") / (double(mechanics_substeps) * double(heart.n()));
  const double beats_run = std::max(1e-9, (double(stepper.end_time()) - beat_origin(p_)) / p_.cycle_length);
  r.results["seconds_per_beat"] = run.time_loop_seconds() / beats_run;
  r.results["total_seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
}

}  // namespace

std::unique_ptr<Scene> make_heart_scene() { return std::make_unique<HeartScene>(); }

}  // namespace cardiosph
