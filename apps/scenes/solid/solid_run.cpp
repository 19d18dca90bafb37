#include "apps/scenes/solid/solid_run.hpp"

#include <algorithm>
#include <cmath>
#include <variant>

#include "libsph/core/numerical_failure.hpp"
#include "libsph/io/particle_output.hpp"
#include "libsph/io/progress.hpp"
#include "libsph/io/time_series.hpp"

namespace cardiosph {

void declare_solid_numerics(sph::Parameters& p, SolidNumerics& n, const std::string& time_unit) {
  p.add("smoothing_length_ratio", n.smoothing_length_ratio, "-", "smoothing length over particle spacing h/dp",
        sph::Range::closed(1.0, 2.5));
  p.add_choice("kernel", n.kernel, {"wendland_c2", "cubic_spline", "wendland_c4"}, "smoothing kernel");
  p.add("hourglass_coefficient", n.hourglass_coefficient, "-",
        "alpha of the hourglass penalty force (Ganzenmueller 2015); 0 turns it off", sph::Range::non_negative());
  p.add("cfl", n.cfl, "-", "time step as a fraction of the acoustic limit", {0, 1, true, false});
  p.add("time_step", n.time_step, time_unit, "fixed time step instead of the acoustic one (0: acoustic); no stability guarantee",
        sph::Range::non_negative());
  p.add("output_interval", n.output_interval, time_unit, "time between particle outputs (0: first and last state only)",
        sph::Range::non_negative());
}

void check_whole_spacings(double extent, double spacing, const std::string& name) {
  const double cells = extent / spacing;
  if (std::abs(cells - std::round(cells)) > 1e-6 * cells || std::round(cells) < 1)
    throw sph::ParameterError("parameter '" + name + "' = " + std::to_string(extent) +
                              " must be a whole number of particle spacings (" + std::to_string(spacing) + ")");
}

template <int Dim>
SolidRunSummary run_solid(sph::ElasticSolid<Dim>& solid, const sph::NeighbourList<Dim>& relation,
                          const SolidRunPlan& plan, RunContext& ctx) {
  auto& body = solid.particles();
  const auto end_time = static_cast<sph::Real>(plan.end_time);
  sph::TimeStepper stepper(0, end_time);
  stepper.add_stage({"solid", [&] { return solid.stable_time_step(); },
                     [&](sph::Real t, sph::Real dt) {
                       if (plan.before_step) plan.before_step(t, dt);
                       solid.advance(t, dt);
                     },
                     false});

  sph::ParticleOutput<Dim> output(ctx.output_dir, plan.body);
  auto write_state = [&](double t) {
    solid.update_output_fields();
    output.write(body, t);
  };
  const double output_interval = plan.output_interval > 0 ? plan.output_interval : plan.end_time;
  stepper.add_periodic_callback(static_cast<sph::Real>(output_interval), [&](const sph::StepInfo& s) { write_state(s.time); });

  SolidRunSummary summary;
  sph::TimeSeriesCsv energy_csv(ctx.output_dir / (plan.body + "_energy.csv"), {"time", "kinetic", "strain", "total", "min_J", "max_J"});
  double max_energy = 0;
  std::vector<double> energy_samples;
  const double sample_interval = plan.sample_interval > 0 ? plan.sample_interval : plan.end_time / 100;
  stepper.add_periodic_callback(
      static_cast<sph::Real>(sample_interval),
      [&](const sph::StepInfo& s) {
        const auto e = solid.energies();  // also leaves F at the current positions
        const double low = e.min_jacobian, high = e.max_jacobian;
        summary.min_jacobian = std::min<double>(summary.min_jacobian, low);
        summary.max_jacobian = std::max<double>(summary.max_jacobian, high);
        energy_csv.record({s.time, e.kinetic, e.strain, e.total(), double(low), double(high)});
        energy_samples.push_back(e.total());
        max_energy = std::max(max_energy, e.total());
        if (plan.sample) plan.sample(s);
      },
      false);

  double last_good_time = 0;
  sph::Progress progress(plan.scene, ctx.quiet);
  stepper.add_step_callback([&](const sph::StepInfo& s) {
    last_good_time = s.time;
    if (plan.every_step) plan.every_step(s);
    progress.update(s);
  });

  auto& report = ctx.report;
  report.simulated_time = plan.end_time;
  report.particles[plan.body] = body.n_particles();
  report.memory_bytes[plan.body + "_fields"] = body.bytes_per_particle() * body.n_particles();
  report.memory_bytes[plan.body + "_relation"] = relation.bytes();
  report.results["initial_time_step"] = solid.stable_time_step();
  try {
    summary.steps = stepper.run();
  } catch (const sph::NumericalFailure&) {
    progress.finish();
    write_state(last_good_time);  // the solid restored the last good state
    report.simulated_time = last_good_time;
    throw;
  }
  progress.finish();
  report.steps = summary.steps;
  if (!energy_samples.empty()) {
    summary.initial_energy = energy_samples.front();
    const double scale = std::max(summary.initial_energy, max_energy);
    for (const double e : energy_samples)
      summary.max_energy_drift = std::max(summary.max_energy_drift, std::abs(e - summary.initial_energy) / scale);
  }
  report.results["min_jacobian"] = summary.min_jacobian;
  report.results["max_jacobian"] = summary.max_jacobian;
  return summary;
}

template <int Dim>
std::vector<sph::Index> select_particles(const sph::ParticleSet<Dim>& body,
                                         const std::function<bool(const sph::Vec<Dim>&)>& inside) {
  std::vector<sph::Index> selected;
  for (std::size_t i = 0; i < body.n_particles(); ++i)
    if (inside(body.position[i])) selected.push_back(static_cast<sph::Index>(i));
  return selected;
}

template <int Dim>
sph::Vec<Dim> deformed_position_of(sph::ElasticSolid<Dim>& solid, const sph::AnyKernel<Dim>& kernel,
                                   sph::Real smoothing_length, const sph::Vec<Dim>& reference_point) {
  solid.update_output_fields();
  auto& body = solid.particles();
  const auto X = body.field(solid.reference_position_field());
  const auto F = body.field(solid.deformation_gradient_field());
  sph::Vec<Dim> weighted = sph::Vec<Dim>::Zero();
  double weight = 0;
  std::visit(
      [&](const auto& k) {
        for (std::size_t i = 0; i < body.n_particles(); ++i) {
          const sph::Real w = k.value((reference_point - X[i]).norm(), smoothing_length) * body.volume[i];
          if (w <= 0) continue;
          weighted += w * (body.position[i] + F[i] * (reference_point - X[i]));
          weight += w;
        }
      },
      kernel);
  if (weight <= 0) throw std::invalid_argument("observer point outside the body");
  return weighted / static_cast<sph::Real>(weight);
}

template SolidRunSummary run_solid<2>(sph::ElasticSolid<2>&, const sph::NeighbourList<2>&, const SolidRunPlan&, RunContext&);
template SolidRunSummary run_solid<3>(sph::ElasticSolid<3>&, const sph::NeighbourList<3>&, const SolidRunPlan&, RunContext&);
template std::vector<sph::Index> select_particles<2>(const sph::ParticleSet<2>&, const std::function<bool(const sph::Vec<2>&)>&);
template std::vector<sph::Index> select_particles<3>(const sph::ParticleSet<3>&, const std::function<bool(const sph::Vec<3>&)>&);
template sph::Vec<2> deformed_position_of<2>(sph::ElasticSolid<2>&, const sph::AnyKernel<2>&, sph::Real, const sph::Vec<2>&);
template sph::Vec<3> deformed_position_of<3>(sph::ElasticSolid<3>&, const sph::AnyKernel<3>&, sph::Real, const sph::Vec<3>&);

}  // namespace cardiosph
