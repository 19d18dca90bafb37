#include "apps/scenes/electrophysiology/ep_run.hpp"

#include <chrono>
#include <sstream>

#include "libsph/core/numerical_failure.hpp"
#include "libsph/core/time_stepper.hpp"
#include "libsph/io/particle_output.hpp"
#include "libsph/io/progress.hpp"
#include "libsph/io/time_series.hpp"

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

  std::vector<std::string> columns{"time"};
  for (std::size_t p = 0; p < probes.size(); ++p)
    columns.push_back((p < plan.probe_names.size() ? plan.probe_names[p] : "P" + std::to_string(p)) + "_potential");
  sph::TimeSeriesCsv observers(ctx.output_dir / "observers.csv", columns);
  auto record = [&](double t) {
    std::vector<double> row{t};
    traces.time.push_back(t);
    for (std::size_t p = 0; p < probes.size(); ++p) {
      row.push_back(probes.sample(p, V));
      traces.potential[p].push_back(row.back());
    }
    observers.record(row);
  };

  sph::ParticleOutput<Dim> output(ctx.output_dir, plan.body);
  sph::TimeStepper stepper(0, static_cast<sph::Real>(plan.end_time));
  stepper.add_stage({"monodomain", [&] { return monodomain.time_step(); },
                     [&](sph::Real t, sph::Real dt) { monodomain.advance(t, dt); }, false});
  const double output_interval = plan.output_interval > 0 ? plan.output_interval : plan.end_time;
  stepper.add_periodic_callback(static_cast<sph::Real>(output_interval),
                                [&](const sph::StepInfo& s) { output.write(body, s.time); });
  const double sample = plan.sample_interval > 0 ? plan.sample_interval : plan.end_time / 1000;
  stepper.add_periodic_callback(static_cast<sph::Real>(sample), [&](const sph::StepInfo& s) { record(s.time); }, false);
  double time_reached = 0;
  sph::Progress progress(plan.scene, ctx.quiet);
  stepper.add_step_callback([&](const sph::StepInfo& s) {
    time_reached = s.time;
    if (plan.every_step) plan.every_step(s);
    progress.update(s);
    if (plan.stop_when_all_activated && monodomain.all_activated()) stepper.stop_after_this_step();
  });

  auto& report = ctx.report;
  report.particles[plan.body] = body.n_particles();
  report.memory_bytes[plan.body + "_fields"] = body.bytes_per_particle() * body.n_particles();
  report.memory_bytes[plan.body + "_relation"] = relation.bytes();
  report.results["time_step"] = monodomain.time_step();
  report.results["diffusion_time_step_limit"] = monodomain.diffusion_time_step();
  const auto start = std::chrono::steady_clock::now();
  try {
    report.steps = stepper.run();
  } catch (const sph::NumericalFailure&) {
    progress.finish();
    report.simulated_time = time_reached;
    output.write(body, time_reached);  // the state at the failure, for inspection
    throw;
  }
  progress.finish();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  report.simulated_time = stepper.end_time();
  const auto& timing = monodomain.timings();
  report.results["reaction_seconds"] = timing.reaction;
  report.results["diffusion_seconds"] = timing.diffusion;
  report.results["diffusion_substeps"] = monodomain.diffusion_substeps();
  if (seconds > 0 && report.steps > 0)
    report.results["particle_steps_per_second"] = double(report.steps) * double(body.n_particles()) / seconds;
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
