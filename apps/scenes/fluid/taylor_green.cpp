// The 2D Taylor-Green vortex in the periodic unit square (rho = U = L = 1, nu = 1 / Re):
//   u = -cos(2 pi x) sin(2 pi y) e^(-8 pi^2 t / Re),  v = sin(2 pi x) cos(2 pi y) e^(-8 pi^2 t / Re),
//   p = -1/4 (cos(4 pi x) + cos(4 pi y)) e^(-16 pi^2 t / Re),
// an exact solution of the incompressible Navier-Stokes equations. Its kinetic energy decays as
// E(t) = E(0) exp(-16 pi^2 t / Re). errors.decay_rate_relative compares the least-squares slope of
// ln E(t) over the run with 16 pi^2 / Re; errors.velocity_l2_relative is the L2 error of the
// velocity at the particles at the end, relative to the L2 norm of the exact field there.

#include <cmath>
#include <memory>
#include <vector>

#include "apps/scenes/fluid/fluid_scenes.hpp"
#include "geometry/lattice.hpp"

namespace cardiosph {
namespace {

using sph::Real;
using Vec2 = sph::Vec<2>;

class TaylorGreenScene final : public Scene {
 public:
  explicit TaylorGreenScene(TaylorGreenParameters p) : p_(std::move(p)) {}

  void declare(sph::Parameters& p) override {
    p.add("resolution", p_.resolution, "-", "particles across the unit period", sph::Range::closed(8, 4000));
    p.add("end_time", p_.end_time, "-", "simulated time (units of L / U)", sph::Range::positive());
    p.add("reynolds", p_.reynolds, "-", "Reynolds number U L / nu", sph::Range::positive());
    p.add("sound_speed", p_.sound_speed, "-", "artificial sound speed c0", sph::Range::positive());
    declare_fluid_numerics(p, p_.numerics, "-");
  }

  void check() const override { check_mach_number(1.0, p_.sound_speed); }

  bool checkpoints() const override { return true; }
  void run(RunContext& ctx) override {
    const Real dp = Real(1) / static_cast<Real>(p_.resolution);
    auto water = geometry::lattice_box<2>("fluid", Vec2::Zero(), Vec2(1, 1), dp);
    auto settings = fluid_settings<2>(p_.numerics, dp, 1.0, p_.sound_speed, 1.0 / p_.reynolds, Vec2::Zero(), 1.0);
    settings.periodic.lower = Vec2::Zero();
    settings.periodic.upper = Vec2(1, 1);
    settings.periodic.periodic = {true, true};
    sph::WeaklyCompressibleFluid<2> fluid(water, settings);
    const double k = 2 * M_PI;
    auto v = water.field(fluid.velocity_field());
    auto rho = water.field(fluid.density_field());
    auto m = water.field(fluid.mass_field());
    const auto& eos = fluid.settings().equation_of_state;
    for (std::size_t i = 0; i < water.n_particles(); ++i) {
      const double x = water.position[i][0], y = water.position[i][1];
      v[i] = Vec2(Real(-std::cos(k * x) * std::sin(k * y)), Real(std::sin(k * x) * std::cos(k * y)));
      rho[i] = eos.density(Real(-0.25 * (std::cos(2 * k * x) + std::cos(2 * k * y))));
      m[i] = rho[i] * water.volume[i];
    }
    fluid.update_pressure();

    const double rate = 16 * M_PI * M_PI / p_.reynolds;
    // What the observer keeps: the first kinetic energy and ln E at every sample.
    sph::RunRecord kinetic;
    double& initial_energy = kinetic.value("initial");
    auto &times = kinetic.series("times"), &log_energy = kinetic.series("log_energy");
    FluidRunPlan plan("taylor-green", p_.end_time, p_.numerics.discretisation.output_interval);
    plan.observer_columns = {"kinetic_energy", "exact_kinetic_energy"};
    plan.observers = [&](const sph::StepInfo& s) {
      const double e = fluid.energies().kinetic;
      if (times.empty()) initial_energy = e;
      times.push_back(s.time);
      log_energy.push_back(std::log(e));
      return std::vector<double>{e, initial_energy * std::exp(-rate * s.time)};
    };
    plan.keep("kinetic_energy", kinetic);
    run_fluid<2>(fluid, {}, plan, ctx);

    // Least-squares slope of ln E(t).
    double st = 0, se = 0, stt = 0, ste = 0;
    const double n = double(times.size());
    for (std::size_t i = 0; i < times.size(); ++i) {
      st += times[i];
      se += log_energy[i];
      stt += times[i] * times[i];
      ste += times[i] * log_energy[i];
    }
    const double slope = (n * ste - st * se) / (n * stt - st * st);
    const double decay = std::exp(-8 * M_PI * M_PI * p_.end_time / p_.reynolds);
    v = water.field(fluid.velocity_field());  // the fluid re-sorts its particles: fetch the field anew
    double error2 = 0, norm2 = 0;
    for (std::size_t i = 0; i < water.n_particles(); ++i) {
      const double x = water.position[i][0], y = water.position[i][1];
      const Vec2 exact(Real(-std::cos(k * x) * std::sin(k * y) * decay), Real(std::sin(k * x) * std::cos(k * y) * decay));
      error2 += (v[i] - exact).squaredNorm();
      norm2 += exact.squaredNorm();
    }
    auto& report = ctx.report;
    report.reference = "Taylor-Green vortex: E(t) = E(0) exp(-16 pi^2 t / Re), exact velocity field";
    report.errors["decay_rate_relative"] = std::abs(-slope - rate) / rate;
    report.errors["velocity_l2_relative"] = std::sqrt(error2 / norm2);
    report.results["decay_rate"] = -slope;
    report.results["reference_decay_rate"] = rate;
  }

 private:
  TaylorGreenParameters p_;
};

}  // namespace

std::unique_ptr<Scene> make_taylor_green_scene(TaylorGreenParameters parameters) {
  return std::make_unique<TaylorGreenScene>(std::move(parameters));
}

}  // namespace cardiosph
