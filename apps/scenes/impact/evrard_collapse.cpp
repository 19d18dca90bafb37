// Evrard's adiabatic collapse (Evrard 1988, MNRAS 235:911): a cold gas sphere of mass M = 1 and radius
// R = 1 with rho(r) = M / (2 pi R^2 r), gamma = 5/3 and u = 0.05 G M / R, at rest, released under its
// own gravity (G = 1; time in units of sqrt(R^3 / (G M))). It falls in, bounces at t of about 1.1 with a
// shock running out, and settles into a virialised core with an expanding envelope. The test of
// self-gravity with hydrodynamics: kinetic, thermal and potential energy against time, and their sum.
//
// Particles of equal mass: a cubic lattice in the unit ball, each stretched radially from r to
// r^(3/2), which turns the uniform enclosed mass r^3 into r^2, that of rho ~ 1/r. Smoothing lengths
// follow the density (h = 1.2 (m / rho)^(1/3)), neighbours come from the k-d tree, gravity from the
// Barnes-Hut tree with the M4-matched softening.
//
// errors.energy_conservation_relative: the largest |E(t) - E(0)| / |E(0)| over the run (E the sum
// of kinetic, thermal and potential energy); the energies are in energy.csv and energy.png, and
// results holds their extremes.

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "apps/plot.hpp"
#include "apps/scenes/impact/impact_parameters.hpp"
#include "apps/scenes/impact/impact_scenes.hpp"
#include "geometry/lattice.hpp"
#include "libsph/core/time_stepper.hpp"
#include "libsph/impact/updated_lagrangian.hpp"
#include "libsph/io/run_harness.hpp"

namespace cardiosph {
namespace {

using sph::Real;
using Vec3 = sph::Vec<3>;

class EvrardCollapseScene final : public Scene {
 public:
  explicit EvrardCollapseScene(EvrardCollapseParameters p) : p_(std::move(p)) {}

  void declare(sph::Parameters& p) override {
    p.add("particles", p_.particles, "-", "about how many particles fill the sphere", sph::Range::closed(500, 10000000));
    p.add("internal_energy", p_.internal_energy, "G M / R", "initial specific internal energy", sph::Range::positive());
    p.add("gamma", p_.gamma, "-", "ratio of specific heats", {1, 10, true, false});
    p.add("theta", p_.theta, "-", "Barnes-Hut opening angle (0 < theta <= 1)", {0, 1, true, false});
    p.add("gravitational_softening", p_.gravitational_softening, "R", "one M4 softening length for all particles (0: each particle's h)",
          sph::Range::non_negative());
    p.add("smoothing_length_factor", p_.smoothing_length_factor, "-", "eta of h = eta (m / rho)^(1/3)", sph::Range::closed(0.8, 2.0));
    declare_artificial_viscosity(p, p_.alpha, p_.beta);
    declare_run_length(p, p_.end_time, p_.output_interval, "sqrt(R^3/GM)");
  }

  bool checkpoints() const override { return true; }  // the energy extremes are kept as state

  void run(RunContext& ctx) override {
    const Real dx = Real(std::cbrt(4.0 / 3.0 * M_PI / double(p_.particles)));
    const double cells = std::ceil(1.0 / dx);
    const Real half = Real(cells) * dx;
    auto gas = geometry::lattice_where<3>("gas", Vec3(-half, -half, -half), Vec3(half, half, half), dx,
                                          [](const Vec3& x) { return x.squaredNorm() < 1; });
    const std::size_t n = gas.n_particles();
    const Real m = Real(1) / Real(n);
    for (std::size_t i = 0; i < n; ++i) {
      auto& x = gas.position[i];
      x *= std::sqrt(x.norm());  // r -> r^(3/2)
      const Real r = std::max(x.norm(), Real(0.5) * dx * dx);
      gas.volume[i] = m * 2 * Real(M_PI) * r;  // m / rho, rho = 1 / (2 pi r)
    }
    sph::UpdatedLagrangianBody<3>::Settings settings;
    settings.equation_of_state = sph::IdealGas{p_.gamma};
    settings.smoothing_length = Real(p_.smoothing_length_factor) * dx;
    settings.smoothing_length_factor = Real(p_.smoothing_length_factor);
    settings.alpha = Real(p_.alpha);
    settings.beta = Real(p_.beta);
    settings.gravity = sph::GravitySettings{};
    settings.gravity->theta = Real(p_.theta);
    settings.gravitational_softening = Real(p_.gravitational_softening);
    sph::UpdatedLagrangianBody<3> body(gas, settings);
    auto rho = gas.field(body.density_field());
    auto e = gas.field(body.energy_field());
    for (std::size_t i = 0; i < n; ++i) {
      rho[i] = m / gas.volume[i];
      e[i] = Real(p_.internal_energy);
    }
    body.initialise();

    sph::TimeStepper stepper(0, static_cast<Real>(p_.end_time));
    stepper.add_stage(body.stage("self-gravitating gas"));
    sph::RunHarness run(stepper, ctx.report, {ctx.output_dir, "evrard-collapse", ctx.quiet, ctx.checkpoint});
    run.add_body(gas, static_cast<Real>(p_.output_interval));
    run.add_relation("gas", body.relation());
    const auto initial = body.energies();
    // The worst energy error and the extremes are kept as state, so that a resumed run reports the same.
    run.add_time_series("energy.csv", {"kinetic", "thermal", "potential", "total"}, static_cast<Real>(p_.end_time / 300),
                        [&](const sph::StepInfo& step) {
                          const auto en = body.energies();
                          worst_ = std::max(worst_, std::abs(en.total() - initial.total()) / std::abs(initial.total()));
                          if (en.internal > peak_thermal_) {
                            peak_thermal_ = en.internal;
                            peak_thermal_time_ = step.time;
                          }
                          if (en.potential < lowest_potential_) {
                            lowest_potential_ = en.potential;
                            lowest_potential_time_ = step.time;
                          }
                          peak_kinetic_ = std::max(peak_kinetic_, en.kinetic);
                          return std::vector<double>{en.kinetic, en.internal, en.potential, en.total()};
                        });
    run.keep("body", body);
    run.add_state("extremes", [&](sph::StateArchive& a) {
      a.io("worst", worst_);
      a.io("peak_thermal", peak_thermal_);
      a.io("peak_thermal_time", peak_thermal_time_);
      a.io("lowest_potential", lowest_potential_);
      a.io("lowest_potential_time", lowest_potential_time_);
      a.io("peak_kinetic", peak_kinetic_);
    });
    run.run();
    plot_csv(ctx.output_dir, {"energy.csv", "energy.png", "Evrard collapse: energies", "time [sqrt(R^3 / G M)]", "energy [G M^2 / R]",
                              {{1, 2, "kinetic", ""}, {1, 3, "thermal", ""}, {1, 4, "potential", ""}, {1, 5, "total", ""}},
                              false, "lines"});

    auto& report = ctx.report;
    report.reference = "Evrard 1988 (MNRAS 235:911): energy conservation; energy curves against the published ones (docs/impact.md)";
    report.errors["energy_conservation_relative"] = worst_;
    report.results["initial_potential_energy"] = initial.potential;  // -2/3 G M^2 / R for the continuum
    report.results["peak_thermal_energy"] = peak_thermal_;
    report.results["peak_thermal_time"] = peak_thermal_time_;
    report.results["lowest_potential_energy"] = lowest_potential_;
    report.results["lowest_potential_time"] = lowest_potential_time_;
    report.results["peak_kinetic_energy"] = peak_kinetic_;
    const auto final_energies = body.energies();
    report.results["final_kinetic_energy"] = final_energies.kinetic;
    report.results["final_thermal_energy"] = final_energies.internal;
    report.results["final_potential_energy"] = final_energies.potential;
  }

 private:
  EvrardCollapseParameters p_;
  double worst_ = 0, peak_thermal_ = 0, peak_thermal_time_ = 0, lowest_potential_ = 0, lowest_potential_time_ = 0, peak_kinetic_ = 0;
};

}  // namespace

std::unique_ptr<Scene> make_evrard_collapse_scene(EvrardCollapseParameters parameters) {
  return std::make_unique<EvrardCollapseScene>(std::move(parameters));
}

}  // namespace cardiosph
