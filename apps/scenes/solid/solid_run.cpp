#include "apps/scenes/solid/solid_run.hpp"

#include <algorithm>
#include <cmath>
#include <variant>


namespace cardiosph {

void declare_solid_numerics(sph::Parameters& p, SolidSceneNumerics& n, const std::string& time_unit) {
  declare_parameters(p, n.discretisation, time_unit);
  sph::declare_parameters(p, n.solid, time_unit);
}

void declare_quasi_static(sph::Parameters& p, std::string& solver, sph::RelaxationSettings& settings) {
  p.add_choice("solver", solver, {"quasi_static", "dynamic"},
               "quasi_static: damped relaxation stopped on the residual (end_time is then the most pseudo-time allowed; "
               "not converged by then: the run fails with the residual); dynamic: damped dynamics to end_time");
  sph::declare_parameters(p, settings);
}

void declare_clamp(sph::Parameters& p, std::string& clamp) {
  p.add_choice("clamp", clamp, {"reflection", "fixed"},
               "hold of the face x = 0: reflection (the held particles next to the face take the odd reflection "
               "of the displacement of their mirror images) or fixed (held particles at rest)");
}

template <int Dim>
void hold_face_x0(sph::ElasticSolid<Dim>& solid, const std::string& clamp) {
  const auto held = select_particles<Dim>(solid.particles(), [](const sph::Vec<Dim>& X) { return X[0] < 0; });
  if (clamp == "reflection") solid.clamp_by_reflection(held, sph::Vec<Dim>::Zero(), sph::Vec<Dim>::UnitX());
  else solid.clamp(held);
}

void check_whole_spacings(double extent, double spacing, const std::string& name) {
  const double cells = extent / spacing;
  if (std::abs(cells - std::round(cells)) > 1e-6 * cells || std::round(cells) < 1)
    throw sph::ParameterError("parameter '" + name + "' = " + std::to_string(extent) +
                              " must be a whole number of particle spacings (" + std::to_string(spacing) + ")");
}

template <int Dim>
SolidRunSummary run_solid(sph::ElasticSolid<Dim>& solid, const sph::NeighbourList<Dim>& relation,
                          const SolidRunPlan& plan, RunContext& ctx, sph::QuasiStaticRelaxation<Dim>* relaxation) {
  auto& body = solid.particles();
  sph::TimeStepper stepper(0, static_cast<sph::Real>(plan.end_time));
  sph::Stage step = relaxation ? relaxation->stage("solid") : solid.stage("solid");
  if (plan.before_step) step.phases.insert(step.phases.begin(), sph::Phase{"scene", plan.before_step, {}});
  for (const auto& [name, load] : plan.loads) step.fill(solid.loads_slot(), name, load);
  stepper.add_stage(std::move(step));
  if (plan.every_step) stepper.add_step_callback(plan.every_step);
  if (relaxation)
    stepper.add_step_callback([&](const sph::StepInfo& s) {
      if (s.time >= plan.converge_after && relaxation->check_due() && relaxation->check(static_cast<sph::Real>(s.time)).converged)
        stepper.stop_after_this_step();
    });

  sph::RunHarness run(stepper, ctx.report, {ctx.output_dir, plan.scene, ctx.quiet, ctx.checkpoint});
  run.add_body(body, static_cast<sph::Real>(plan.output_interval), [&](double) { solid.update_output_fields(); });
  run.add_relation(body.name(), relation);

  SolidRunSummary summary;
  sph::RunRecord record;
  double& min_jacobian = record.value("min_jacobian", 1);
  double& max_jacobian = record.value("max_jacobian", 1);
  double& max_energy = record.value("max_energy");
  std::vector<double>& energy_samples = record.series("energy_samples");
  const auto sample_interval = static_cast<sph::Real>(plan.sample_interval > 0 ? plan.sample_interval : plan.end_time / 100);
  run.add_time_series(body.name() + "_energy.csv", {"kinetic", "strain", "total", "min_J", "max_J"}, sample_interval,
                      [&](const sph::StepInfo&) {
                        const auto e = solid.energies();  // also leaves F at the current positions
                        min_jacobian = std::min<double>(min_jacobian, e.min_jacobian);
                        max_jacobian = std::max<double>(max_jacobian, e.max_jacobian);
                        energy_samples.push_back(e.total());
                        max_energy = std::max(max_energy, e.total());
                        return std::vector<double>{e.kinetic, e.strain, e.total(), double(e.min_jacobian),
                                                   double(e.max_jacobian)};
                      });
  plan.attach(run, sample_interval);
  run.keep("solid/" + body.name(), solid);
  if (relaxation) run.keep("relaxation/" + body.name(), *relaxation);
  run.keep("solid_run", record);

  ctx.report.results["initial_time_step"] = solid.stable_time_step();
  summary.steps = run.run();
  if (!energy_samples.empty()) {
    summary.initial_energy = energy_samples.front();
    const double scale = std::max(summary.initial_energy, max_energy);
    for (const double e : energy_samples)
      summary.max_energy_drift = std::max(summary.max_energy_drift, std::abs(e - summary.initial_energy) / scale);
  }
  summary.min_jacobian = min_jacobian;
  summary.max_jacobian = max_jacobian;
  ctx.report.results["min_jacobian"] = summary.min_jacobian;
  ctx.report.results["max_jacobian"] = summary.max_jacobian;
  if (relaxation) {
    const auto& status = relaxation->check(stepper.end_time());
    summary.converged = status.converged;
    ctx.report.results["residual_relative"] = status.residual;
    ctx.report.results["converged"] = status.converged;
    ctx.report.results["relaxation_steps"] = status.steps;
  }
  return summary;
}

template <int Dim>
std::vector<sph::Vec<Dim>> material_point_positions(const sph::PointProbes<Dim>& probes, sph::ElasticSolid<Dim>& solid) {
  solid.update_deformation_gradient();
  const auto& body = solid.particles();
  // A distributed body: the probes lie on the whole set, sampled from its gathered positions and F.
  std::vector<sph::Vec<Dim>> whole_x;
  std::vector<sph::Mat<Dim>> whole_F;
  const auto x_all = sph::gather_all(body, std::span<const sph::Vec<Dim>>(body.position), whole_x);
  const auto F_all = sph::gather_all(body, std::span<const sph::Mat<Dim>>(body.field(solid.deformation_gradient_field())), whole_F);
  std::vector<sph::Vec<Dim>> x(probes.size());
  for (std::size_t p = 0; p < probes.size(); ++p)
    x[p] = probes.template sample_with_gradient<sph::Vec<Dim>, sph::Mat<Dim>>(p, x_all, F_all);
  return x;
}

template <int Dim>
std::vector<sph::Index> select_particles(const sph::ParticleSet<Dim>& body,
                                         const std::function<bool(const sph::Vec<Dim>&)>& inside) {
  std::vector<sph::Index> selected;
  for (std::size_t i = 0; i < body.n_particles(); ++i)
    if (inside(body.position[i])) selected.push_back(static_cast<sph::Index>(i));
  return selected;
}

template SolidRunSummary run_solid<2>(sph::ElasticSolid<2>&, const sph::NeighbourList<2>&, const SolidRunPlan&, RunContext&,
                                      sph::QuasiStaticRelaxation<2>*);
template SolidRunSummary run_solid<3>(sph::ElasticSolid<3>&, const sph::NeighbourList<3>&, const SolidRunPlan&, RunContext&,
                                      sph::QuasiStaticRelaxation<3>*);
template std::vector<sph::Vec<2>> material_point_positions<2>(const sph::PointProbes<2>&, sph::ElasticSolid<2>&);
template std::vector<sph::Vec<3>> material_point_positions<3>(const sph::PointProbes<3>&, sph::ElasticSolid<3>&);
template std::vector<sph::Index> select_particles<2>(const sph::ParticleSet<2>&, const std::function<bool(const sph::Vec<2>&)>&);
template std::vector<sph::Index> select_particles<3>(const sph::ParticleSet<3>&, const std::function<bool(const sph::Vec<3>&)>&);

template void hold_face_x0<2>(sph::ElasticSolid<2>&, const std::string&);
template void hold_face_x0<3>(sph::ElasticSolid<3>&, const std::string&);

}  // namespace cardiosph
