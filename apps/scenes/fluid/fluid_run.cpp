#include "apps/scenes/fluid/fluid_run.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace cardiosph {

void declare_fluid_numerics(sph::Parameters& p, FluidSceneNumerics& n, const std::string& time_unit) {
  declare_parameters(p, n.discretisation, time_unit);
  sph::declare_parameters(p, n.fluid);
}

std::string check_mach_number(double reference_speed, double sound_speed) {
  const double mach = reference_speed / sound_speed;
  std::ostringstream s;
  s << "Mach number " << mach << " = reference speed " << reference_speed << " / sound_speed " << sound_speed;
  if (mach > 0.3)
    throw sph::ParameterError("parameter 'sound_speed' = " + std::to_string(sound_speed) + " is too small: " + s.str() +
                              " exceeds 0.3, where the weakly-compressible model no longer holds (use at least " +
                              std::to_string(reference_speed / 0.1) + " for Mach 0.1)");
  if (mach > 0.1) return s.str() + " is above 0.1: density varies by more than about 1 %";
  return {};
}

template <int Dim>
typename sph::WeaklyCompressibleFluid<Dim>::Settings fluid_settings(const FluidSceneNumerics& numerics, double dp,
                                                                    double density, double sound_speed,
                                                                    double viscosity, const sph::Vec<Dim>& body_force,
                                                                    double reference_speed) {
  typename sph::WeaklyCompressibleFluid<Dim>::Settings s;
  s.equation_of_state.reference_density = static_cast<sph::Real>(density);
  s.equation_of_state.sound_speed = static_cast<sph::Real>(sound_speed);
  s.viscosity = static_cast<sph::Real>(viscosity);
  s.body_force = body_force;
  s.reference_speed = static_cast<sph::Real>(reference_speed);
  s.particle_spacing = static_cast<sph::Real>(dp);
  s.smoothing_length = static_cast<sph::Real>(numerics.discretisation.smoothing_length_ratio * dp);
  s.kernel = sph::make_kernel<Dim>(numerics.discretisation.kernel);
  s.numerics = numerics.fluid;
  return s;
}

int wall_layers(const Discretisation& d) { return static_cast<int>(std::ceil(2 * d.smoothing_length_ratio - 1e-9)); }

template <int Dim>
geometry::WallParticles<Dim> box_walls(const std::string& name, const sph::Vec<Dim>& lower, const sph::Vec<Dim>& upper,
                                       sph::Real dp, int layers, std::array<bool, Dim> periodic) {
  geometry::Vec3 lo(-1e6, -1e6, -1e6), hi(1e6, 1e6, 1e6);
  sph::Vec<Dim> grid_lower, grid_upper;
  for (int d = 0; d < Dim; ++d) {
    if (periodic[d]) {
      grid_lower[d] = lower[d];
      grid_upper[d] = upper[d];
      continue;
    }
    lo[d] = lower[d];
    hi[d] = upper[d];
    grid_lower[d] = lower[d] - static_cast<sph::Real>(layers) * dp;
    // The far side rounded up to whole spacings: the tank need not be a whole number of them.
    const double cells = std::ceil((upper[d] - grid_lower[d]) / dp + static_cast<double>(layers) - 1e-9);
    grid_upper[d] = grid_lower[d] + static_cast<sph::Real>(cells) * dp;
  }
  const auto container = geometry::make_box(lo, hi);
  return geometry::wall_particles<Dim>(name, *container, grid_lower, grid_upper, dp, layers * dp);
}

template <int Dim>
FluidRunSummary run_fluid(sph::WeaklyCompressibleFluid<Dim>& fluid, std::vector<sph::FluidWall<Dim>*> walls,
                          const FluidRunPlan& plan, RunContext& ctx) {
  auto& body = fluid.particles();
  sph::TimeStepper stepper(0, static_cast<sph::Real>(plan.end_time));
  sph::RunHarness run(stepper, ctx.report, {ctx.output_dir, plan.scene, ctx.quiet, ctx.checkpoint});
  sph::Stage step = fluid.advection_stage(run.timers());
  if (plan.extend) plan.extend(run, step);
  stepper.add_stage(std::move(step));
  if (plan.every_step) stepper.add_step_callback(plan.every_step);
  run.add_body(body, static_cast<sph::Real>(plan.output_interval));
  for (auto* wall : walls) run.add_body(wall->particles(), 0);

  FluidRunSummary summary;
  const double c0 = fluid.settings().equation_of_state.sound_speed;
  // What the energy series keeps: the first and the largest energy, the largest rise and Mach number.
  sph::RunRecord record;
  double& samples = record.value("samples");
  double& initial_energy = record.value("initial_energy");
  double& largest_energy = record.value("largest_energy");
  double& max_energy_rise = record.value("max_energy_rise");
  double& max_mach = record.value("max_mach");
  const auto sample_interval = static_cast<sph::Real>(plan.sample_interval > 0 ? plan.sample_interval : plan.end_time / 200);
  run.add_time_series(body.name() + "_energy.csv", {"kinetic", "potential", "internal", "total", "max_speed"},
                      sample_interval, [&](const sph::StepInfo&) {
                        const auto e = fluid.energies();
                        const double speed = fluid.max_speed();
                        if (samples == 0) initial_energy = e.total();
                        samples += 1;
                        largest_energy = std::max(largest_energy, std::abs(e.total()));
                        const double scale = std::max({std::abs(initial_energy), largest_energy, 1e-300});
                        max_energy_rise = std::max(max_energy_rise, (e.total() - initial_energy) / scale);
                        max_mach = std::max(max_mach, speed / c0);
                        return std::vector<double>{e.kinetic, e.potential, e.internal, e.total(), speed};
                      });
  plan.attach(run, sample_interval);
  run.keep("fluid/" + body.name(), fluid);
  run.keep("fluid_run", record);
  ctx.report.results["sound_speed"] = c0;
  ctx.report.results["smoothing_length"] = fluid.settings().smoothing_length;
  ctx.report.results["particle_spacing"] = fluid.settings().particle_spacing;
  auto fill = [&] {
    summary.initial_energy = initial_energy;
    summary.max_energy_rise = max_energy_rise;
    summary.max_mach = max_mach;
    summary.advection_steps = fluid.advection_steps();
    summary.acoustic_steps = fluid.acoustic_steps();
    summary.time_loop_seconds = run.time_loop_seconds();
    ctx.report.results["advection_steps"] = summary.advection_steps;
    ctx.report.results["acoustic_steps"] = summary.acoustic_steps;
    ctx.report.results["neighbour_rebuilds"] = fluid.neighbour_rebuilds();
    if (summary.time_loop_seconds > 0)
      ctx.report.results["particle_steps_per_second"] =
          double(summary.acoustic_steps) * double(body.partition() ? body.partition()->n_global : body.n_particles()) /
          summary.time_loop_seconds;
    ctx.report.results["max_mach"] = summary.max_mach;
    ctx.report.results["max_energy_rise_relative"] = summary.max_energy_rise;
    ctx.report.results["fluid_bytes_per_particle"] = body.bytes_per_particle();
  };
  try {
    run.run();
  } catch (...) {
    fill();
    throw;
  }
  fill();
  run.add_relation(body.name(), fluid.inner_relation());
  for (std::size_t k = 0; k < std::min(fluid.n_walls(), walls.size()); ++k)
    run.add_relation(body.name() + "_to_" + walls[k]->particles().name(), fluid.wall_relation(k));
  return summary;
}

template <int Dim>
void set_hydrostatic_state(sph::WeaklyCompressibleFluid<Dim>& fluid, double surface, double g) {
  auto& body = fluid.particles();
  const auto& eos = fluid.settings().equation_of_state;
  auto rho = body.field(fluid.density_field());
  auto m = body.field(fluid.mass_field());
  for (std::size_t i = 0; i < body.n_particles(); ++i) {
    const double depth = std::max(0.0, surface - double(body.position[i][Dim - 1]));
    rho[i] = eos.density(static_cast<sph::Real>(eos.reference_density * g * depth));
    m[i] = rho[i] * body.volume[i];
  }
  fluid.update_pressure();
}

template sph::WeaklyCompressibleFluid<2>::Settings fluid_settings<2>(const FluidSceneNumerics&, double, double, double,
                                                                     double, const sph::Vec<2>&, double);
template sph::WeaklyCompressibleFluid<3>::Settings fluid_settings<3>(const FluidSceneNumerics&, double, double, double,
                                                                     double, const sph::Vec<3>&, double);
template geometry::WallParticles<2> box_walls<2>(const std::string&, const sph::Vec<2>&, const sph::Vec<2>&, sph::Real, int,
                                                 std::array<bool, 2>);
template geometry::WallParticles<3> box_walls<3>(const std::string&, const sph::Vec<3>&, const sph::Vec<3>&, sph::Real, int,
                                                 std::array<bool, 3>);
template FluidRunSummary run_fluid<2>(sph::WeaklyCompressibleFluid<2>&, std::vector<sph::FluidWall<2>*>, const FluidRunPlan&,
                                      RunContext&);
template FluidRunSummary run_fluid<3>(sph::WeaklyCompressibleFluid<3>&, std::vector<sph::FluidWall<3>*>, const FluidRunPlan&,
                                      RunContext&);
template void set_hydrostatic_state<2>(sph::WeaklyCompressibleFluid<2>&, double, double);
template void set_hydrostatic_state<3>(sph::WeaklyCompressibleFluid<3>&, double, double);

}  // namespace cardiosph
