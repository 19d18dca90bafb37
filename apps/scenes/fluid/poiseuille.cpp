// Plane Poiseuille flow: a channel 0 < y < H between no-slip walls, periodic along x, driven from
// rest by the body force g along x (rho = 1, nu = eta). The steady profile is
//   u(y) = g / (2 nu) y (H - y),   u_max = g H^2 / (8 nu),
// reached on the time scale H^2 / (pi^2 nu) of the slowest mode (Morris, Fox & Zhu 1997, sec. 4.1).
// errors.profile_l2_relative: L2 error of u at the particles at the end against the parabola,
// relative to its L2 norm; results.time_to_steady_state: the first time the mean speed is within
// 1 % of the steady mean (2/3 u_max).

#include <cmath>
#include <memory>
#include <vector>

#include "apps/scenes/fluid/fluid_scenes.hpp"
#include "geometry/lattice.hpp"

namespace cardiosph {
namespace {

using sph::Real;
using Vec2 = sph::Vec<2>;

class PoiseuilleScene final : public Scene {
 public:
  explicit PoiseuilleScene(PoiseuilleParameters p) : p_(std::move(p)) {}

  void declare(sph::Parameters& p) override {
    p.add("resolution", p_.resolution, "-", "particles across the channel height", sph::Range::closed(4, 4000));
    p.add("end_time", p_.end_time, "-", "simulated time", sph::Range::positive());
    p.add("height", p_.height, "-", "channel height H", sph::Range::positive());
    p.add("length", p_.length, "-", "periodic length of the channel", sph::Range::positive());
    p.add("viscosity", p_.viscosity, "-", "dynamic viscosity (rho = 1)", sph::Range::positive());
    p.add("body_force", p_.body_force, "-", "driving acceleration g along x", sph::Range::positive());
    p.add("sound_speed", p_.sound_speed, "-", "artificial sound speed c0", sph::Range::positive());
    declare_fluid_numerics(p, p_.numerics, "-");
  }

  double dp() const { return p_.height / static_cast<double>(p_.resolution); }
  double peak_speed() const { return p_.body_force * p_.height * p_.height / (8 * p_.viscosity); }

  void check() const override {
    check_mach_number(peak_speed(), p_.sound_speed);
    const double columns = p_.length / dp();
    if (std::abs(columns - std::round(columns)) > 1e-6 * columns)
      throw sph::ParameterError("parameter 'length' = " + std::to_string(p_.length) +
                                " must be a whole number of particle spacings (" + std::to_string(dp()) + ")");
  }

  bool checkpoints() const override { return true; }
  void run(RunContext& ctx) override {
    const Real dp = static_cast<Real>(this->dp());
    const Real L = static_cast<Real>(p_.length), H = static_cast<Real>(p_.height);
    auto water = geometry::lattice_box<2>("fluid", Vec2::Zero(), Vec2(L, H), dp);
    auto wall_set = box_walls<2>("walls", Vec2::Zero(), Vec2(L, H), dp, wall_layers(p_.numerics.discretisation), {true, false});
    sph::FluidWall<2> walls(wall_set.particles, wall_set.normals, sph::WallSlip::no_slip);
    auto settings = fluid_settings<2>(p_.numerics, dp, 1.0, p_.sound_speed, p_.viscosity,
                                      Vec2(static_cast<Real>(p_.body_force), 0), peak_speed());
    settings.periodic.lower = Vec2::Zero();
    settings.periodic.upper = Vec2(L, H);
    settings.periodic.periodic = {true, false};
    settings.domain_lower = Vec2::Zero();
    settings.domain_upper = Vec2(L, H);
    sph::WeaklyCompressibleFluid<2> fluid(water, settings);
    fluid.add_wall(walls);

    const double nu = p_.viscosity, g = p_.body_force;
    auto exact = [&](double y) { return g / (2 * nu) * y * (p_.height - y); };
    const double steady_mean = 2.0 / 3.0 * peak_speed();
    auto mean_speed = [&] {
      const auto v = water.field(fluid.velocity_field());  // fetched anew: the fluid re-sorts its particles
      double sum = 0;
      for (const auto& vi : v) sum += vi[0];
      return sum / double(v.size());
    };
    // What the observer keeps: the first time the mean speed is within 1 % of its steady value.
    sph::RunRecord steady;
    double& steady_time = steady.value("steady_time", std::nan(""));
    FluidRunPlan plan("poiseuille", p_.end_time, p_.numerics.discretisation.output_interval);
    plan.observer_columns = {"mean_speed", "steady_mean_speed"};
    plan.observers = [&](const sph::StepInfo& s) {
      const double mean = mean_speed();
      if (std::isnan(steady_time) && std::abs(mean - steady_mean) < 0.01 * steady_mean) steady_time = s.time;
      return std::vector<double>{mean, steady_mean};
    };
    plan.keep("steady", steady);
    run_fluid<2>(fluid, {&walls}, plan, ctx);

    const auto v = water.field(fluid.velocity_field());
    double error2 = 0, norm2 = 0;
    for (std::size_t i = 0; i < water.n_particles(); ++i) {
      const double u = exact(water.position[i][1]);
      error2 += (v[i][0] - u) * (v[i][0] - u) + double(v[i][1]) * v[i][1];
      norm2 += u * u;
    }
    auto& report = ctx.report;
    report.reference = "steady plane Poiseuille profile u = g y (H - y) / (2 nu)";
    report.errors["profile_l2_relative"] = std::sqrt(error2 / norm2);
    report.results["time_to_steady_state"] = steady_time;
    report.results["mean_speed"] = mean_speed();
    report.results["reference_mean_speed"] = steady_mean;
    report.results["reynolds"] = peak_speed() * p_.height / nu;
  }

 private:
  PoiseuilleParameters p_;
};

}  // namespace

std::unique_ptr<Scene> make_poiseuille_scene(PoiseuilleParameters parameters) {
  return std::make_unique<PoiseuilleScene>(std::move(parameters));
}

}  // namespace cardiosph
