// Water at rest in a closed tank under gravity (rho 1, g 1), started from the hydrostatic state
// and run long: the bottom pressure against rho g H (the two bottom layers of the middle half
// carried to the floor hydrostatically, time-averaged over the second half of the run), the largest spurious speed over
// that half relative to sqrt(g H), and the drift of the free surface (mean height of the top
// layer) relative to the particle spacing.

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "apps/scenes/fluid/fluid_scenes.hpp"
#include "geometry/lattice.hpp"

namespace cardiosph {
namespace {

using sph::Real;
using Vec2 = sph::Vec<2>;

class HydrostaticTankScene final : public Scene {
 public:
  explicit HydrostaticTankScene(HydrostaticTankParameters p) : p_(std::move(p)) {}

  void declare(sph::Parameters& p) override {
    p.add("resolution", p_.resolution, "-", "particles across the water height", sph::Range::closed(4, 2000));
    p.add("end_time", p_.end_time, "-", "simulated time", sph::Range::positive());
    p.add("water_height", p_.water_height, "-", "depth H of the water", sph::Range::positive());
    p.add("tank_width", p_.tank_width, "-", "inner width of the tank (filled)", sph::Range::positive());
    p.add("tank_height", p_.tank_height, "-", "inner height of the tank", sph::Range::positive());
    p.add("density", p_.density, "-", "reference density", sph::Range::positive());
    p.add("gravity", p_.gravity, "-", "gravitational acceleration", sph::Range::positive());
    p.add("sound_speed", p_.sound_speed, "-", "artificial sound speed c0", sph::Range::positive());
    p.add("viscosity", p_.viscosity, "-", "dynamic viscosity", sph::Range::non_negative());
    declare_fluid_numerics(p, p_.numerics, "-");
  }

  double dp() const { return p_.water_height / static_cast<double>(p_.resolution); }
  double reference_speed() const { return std::sqrt(p_.gravity * p_.water_height); }

  void check() const override {
    check_mach_number(reference_speed(), p_.sound_speed);
    const double columns = p_.tank_width / dp();
    if (std::abs(columns - std::round(columns)) > 1e-6 * columns || columns < 4)
      throw sph::ParameterError("parameter 'tank_width' = " + std::to_string(p_.tank_width) +
                                " must be a whole number (at least 4) of particle spacings (" + std::to_string(dp()) + ")");
    if (p_.water_height > p_.tank_height)
      throw sph::ParameterError("parameter 'water_height' = " + std::to_string(p_.water_height) +
                                " exceeds the tank height " + std::to_string(p_.tank_height));
  }

  bool checkpoints() const override { return true; }
  void run(RunContext& ctx) override {
    const Real dp = static_cast<Real>(this->dp());
    const Real W = static_cast<Real>(p_.tank_width), H = static_cast<Real>(p_.water_height);
    auto water = geometry::lattice_box<2>("water", Vec2::Zero(), Vec2(W, H), dp);
    auto wall_set = box_walls<2>("tank", Vec2::Zero(), Vec2(W, static_cast<Real>(p_.tank_height)), dp,
                                 wall_layers(p_.numerics.discretisation));
    sph::FluidWall<2> tank(wall_set.particles, wall_set.normals, sph::WallSlip::no_slip);
    auto settings = fluid_settings<2>(p_.numerics, dp, p_.density, p_.sound_speed, p_.viscosity,
                                      Vec2(0, -static_cast<Real>(p_.gravity)), reference_speed());
    settings.domain_lower = Vec2::Zero();
    settings.domain_upper = Vec2(W, static_cast<Real>(p_.tank_height));
    sph::WeaklyCompressibleFluid<2> fluid(water, settings);
    fluid.add_wall(tank);
    set_hydrostatic_state<2>(fluid, p_.water_height, p_.gravity);

    // Floor pressure: the particles of the two bottom layers in the middle half of the width, each
    // carried down to the floor hydrostatically, p_i + rho0 g y_i, and averaged.
    auto floor_pressure = [&] {
      const auto p = water.field(fluid.pressure_field());
      double sum = 0;
      std::size_t n = 0;
      for (std::size_t i = 0; i < water.n_particles(); ++i) {
        const auto& x = water.position[i];
        if (x[1] < 2 * dp && std::abs(x[0] - W / 2) < W / 4) {
          sum += p[i] + p_.density * p_.gravity * x[1];
          ++n;
        }
      }
      return n ? sum / double(n) : std::nan("");
    };
    const double reference_pressure = p_.density * p_.gravity * p_.water_height;
    const double speed_scale = reference_speed();
    auto surface_height = [&] {
      // mean height of the particles in the top layer (within one spacing of the highest)
      Real top = 0;
      for (const auto& x : water.position) top = std::max(top, x[1]);
      double sum = 0;
      std::size_t n = 0;
      for (const auto& x : water.position)
        if (x[1] > top - dp) {
          sum += x[1];
          ++n;
        }
      return sum / double(n);
    };
    const double initial_surface = surface_height();
    // What the observer keeps: the floor pressure summed and the largest speed over the second half
    // of the run, and the largest drift of the surface.
    sph::RunRecord rest;
    double &pressure_sum = rest.value("pressure_sum"), &max_speed_late = rest.value("max_speed_late"),
           &max_drift = rest.value("max_drift"), &late_samples = rest.value("late_samples");

    FluidRunPlan plan("hydrostatic-tank", p_.end_time, p_.numerics.discretisation.output_interval);
    plan.observer_columns = {"bottom_pressure", "max_speed", "surface_height"};
    plan.observers = [&](const sph::StepInfo& s) {
      const double pressure = floor_pressure();
      const double speed = fluid.max_speed();
      const double surface = surface_height();
      max_drift = std::max(max_drift, std::abs(surface - initial_surface));
      if (s.time >= p_.end_time / 2) {
        pressure_sum += pressure;
        ++late_samples;
        max_speed_late = std::max(max_speed_late, speed);
      }
      return std::vector<double>{pressure, speed, surface};
    };
    plan.keep("rest", rest);
    run_fluid<2>(fluid, {&tank}, plan, ctx);

    const double bottom = pressure_sum / std::max(late_samples, 1.0);
    auto& report = ctx.report;
    report.reference = "hydrostatic pressure rho g H at the floor; fluid at rest";
    report.errors["bottom_pressure_relative"] = std::abs(bottom - reference_pressure) / reference_pressure;
    report.errors["spurious_speed_relative"] = max_speed_late / speed_scale;
    report.results["bottom_pressure"] = bottom;
    report.results["reference_bottom_pressure"] = reference_pressure;
    report.results["surface_drift_over_spacing"] = max_drift / double(dp);
  }

 private:
  HydrostaticTankParameters p_;
};

}  // namespace

std::unique_ptr<Scene> make_hydrostatic_tank_scene(HydrostaticTankParameters parameters) {
  return std::make_unique<HydrostaticTankScene>(std::move(parameters));
}

}  // namespace cardiosph
