#include "apps/scenes/electrophysiology/ep_run.hpp"

#include "libsph/core/time_stepper.hpp"
#include "libsph/io/run_harness.hpp"

namespace cardiosph {

void declare_ep_numerics(sph::Parameters& p, EpNumerics& n, const std::string& time_unit) {
  p.add("smoothing_length_ratio", n.smoothing_length_ratio, "-", "smoothing length over particle spacing h/dp",
        sph::Range::closed(1.0, 2.5));
  p.add_choice("kernel", n.kernel, {"wendland_c2", "cubic_spline", "wendland_c4"}, "smoothing kernel");
  p.add_choice("correction", n.correction, {"moment", "gradient", "none"},
               "correction of the diffusion operator (moment: exact on quadratics; gradient: kernel-correction matrix)");
  p.add_choice("scheme", n.scheme, {"rbr_qss", "rush_larsen", "forward_euler"},
               "cell integrator: reaction-by-reaction Strang splitting with QSS updates, generalised Rush-Larsen, "
               "or explicit Euler");
  p.add("time_step", n.time_step, time_unit, "splitting step (reaction half step, diffusion, reaction half step)",
        sph::Range::positive());
  p.add_choice("diffusion_integrator", n.diffusion_integrator, {"forward_euler", "heun"},
               "explicit integrator of the diffusion sub-steps");
  p.add("diffusion_cfl", n.diffusion_cfl, "-", "diffusion sub-step as a fraction of its stability limit",
        {0, 1, true, false});
  p.add("output_interval", n.output_interval, time_unit, "time between particle outputs (0: first and last state only)",
        sph::Range::non_negative());
}

template <int Dim>
void apply_ep_numerics(const EpNumerics& n, typename cardio::Monodomain<Dim>::Settings& s) {
  s.scheme = sph::reaction_scheme_from_string(n.scheme);
  s.time_step = static_cast<sph::Real>(n.time_step);
  s.correction = n.correction == "moment"     ? sph::DiffusionCorrection::moment
                 : n.correction == "gradient" ? sph::DiffusionCorrection::gradient
                                              : sph::DiffusionCorrection::none;
  s.diffusion_integrator =
      n.diffusion_integrator == "heun" ? sph::DiffusionIntegrator::heun : sph::DiffusionIntegrator::forward_euler;
  s.diffusion_cfl = static_cast<sph::Real>(n.diffusion_cfl);
}

template <int Dim>
EpTraces run_monodomain(cardio::Monodomain<Dim>& monodomain, sph::ParticleSet<Dim>& body,
                        const sph::NeighbourList<Dim>& relation, const sph::PointProbes<Dim>& probes,
                        const EpRunPlan& plan, RunContext& ctx) {
  const auto V = body.field(monodomain.potential_field());
  EpTraces traces;
  traces.potential.resize(probes.size());

  sph::TimeStepper stepper(0, static_cast<sph::Real>(plan.end_time));
  stepper.add_stage(monodomain.stage("monodomain"));
  stepper.add_step_callback([&](const sph::StepInfo& s) {
    if (plan.every_step) plan.every_step(s);
    if (plan.stop_when_all_activated && monodomain.all_activated()) stepper.stop_after_this_step();
  });
  sph::RunHarness run(stepper, ctx.report, {ctx.output_dir, plan.scene, ctx.quiet});
  run.add_body(body, static_cast<sph::Real>(plan.output_interval));
  run.add_relation(plan.body, relation);
  std::vector<std::string> columns;
  for (std::size_t p = 0; p < probes.size(); ++p)
    columns.push_back((p < plan.probe_names.size() ? plan.probe_names[p] : "P" + std::to_string(p)) + "_potential");
  const double sample = plan.sample_interval > 0 ? plan.sample_interval : plan.end_time / 1000;
  run.add_time_series("observers.csv", columns, static_cast<sph::Real>(sample), [&](const sph::StepInfo& s) {
    std::vector<double> row;
    traces.time.push_back(s.time);
    for (std::size_t p = 0; p < probes.size(); ++p) {
      row.push_back(probes.sample(p, V));
      traces.potential[p].push_back(row.back());
    }
    return row;
  });

  auto& report = ctx.report;
  report.results["time_step"] = monodomain.time_step();
  report.results["diffusion_time_step_limit"] = monodomain.diffusion_time_step();
  run.run();
  const auto& timing = monodomain.timings();
  report.results["reaction_seconds"] = timing.reaction;
  report.results["diffusion_seconds"] = timing.diffusion;
  report.results["diffusion_substeps"] = monodomain.diffusion_substeps();
  if (run.time_loop_seconds() > 0 && report.steps > 0)
    report.results["particle_steps_per_second"] = double(report.steps) * double(body.n_particles()) / run.time_loop_seconds();
  return traces;
}

std::vector<double> upward_crossings(const std::vector<double>& time, const std::vector<double>& value, double level) {
  std::vector<double> crossings;
  for (std::size_t i = 1; i < time.size(); ++i)
    if (value[i - 1] < level && value[i] >= level)
      crossings.push_back(time[i - 1] + (level - value[i - 1]) / (value[i] - value[i - 1]) * (time[i] - time[i - 1]));
  return crossings;
}

template void apply_ep_numerics<2>(const EpNumerics&, cardio::Monodomain<2>::Settings&);
template void apply_ep_numerics<3>(const EpNumerics&, cardio::Monodomain<3>::Settings&);
template EpTraces run_monodomain<2>(cardio::Monodomain<2>&, sph::ParticleSet<2>&, const sph::NeighbourList<2>&,
                                    const sph::PointProbes<2>&, const EpRunPlan&, RunContext&);
template EpTraces run_monodomain<3>(cardio::Monodomain<3>&, sph::ParticleSet<3>&, const sph::NeighbourList<3>&,
                                    const sph::PointProbes<3>&, const EpRunPlan&, RunContext&);

}  // namespace cardiosph
