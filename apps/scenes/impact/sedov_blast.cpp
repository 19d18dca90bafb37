// Sedov-Taylor point explosion in 2D (cylindrical symmetry; Sedov 1959): an energy E per unit length
// released at the centre of a cold uniform gas (rho0 = 1, gamma = 1.4). The shock runs out as
// R(t) = xi0 (E t^2 / rho0)^(1/4) with xi0 = 1.0040 (libsph/impact/sedov_solution.hpp), and the
// profile behind it is self-similar.
//
// Particles on a square lattice over [-L, L]^2; the energy goes to the particles within
// `blast_radius` of the centre with kernel weights (a point source spread over a few h); the gas
// elsewhere holds a pressure 1e-6 of the mean blast pressure (cold). Smoothing lengths follow the
// density (h = eta sqrt(m / rho), neighbours by the k-d tree), which keeps the evacuated centre and
// the compressed shell resolved.
//
// Measured, against the exact solution:
//   errors.shock_radius_relative: the radius of the densest particles (the mean radius of the 1 %
//     densest) at end_time against R(end_time); shock.csv has it against time beside R(t);
//   errors.density_l1: relative L1 of density over the particles within 1.2 R at end_time;
//   profile.csv and profile.png: density, radial velocity and pressure of every particle against
//   radius, with the exact profile.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "apps/plot.hpp"
#include "apps/scenes/impact/impact_parameters.hpp"
#include "apps/scenes/impact/impact_scenes.hpp"
#include "geometry/lattice.hpp"
#include "libsph/core/time_stepper.hpp"
#include "libsph/impact/sedov_solution.hpp"
#include "libsph/impact/updated_lagrangian.hpp"
#include "libsph/io/atomic_file.hpp"
#include "libsph/io/run_harness.hpp"

namespace cardiosph {
namespace {

using sph::Real;
using Vec2 = sph::Vec<2>;

class SedovBlastScene final : public Scene {
 public:
  explicit SedovBlastScene(SedovBlastParameters p) : p_(std::move(p)) {}

  void declare(sph::Parameters& p) override {
    p.add("resolution", p_.resolution, "-", "particles per unit length", sph::Range::closed(20, 2000));
    p.add("half_width", p_.half_width, "-", "the gas fills [-L, L]^2", sph::Range::positive());
    p.add("energy", p_.energy, "-", "blast energy per unit length", sph::Range::positive());
    p.add("density", p_.density, "-", "density of the gas", sph::Range::positive());
    p.add("gamma", p_.gamma, "-", "ratio of specific heats", {1, 10, true, false});
    p.add("blast_radius", p_.blast_radius, "dx", "the energy goes to the particles within this many spacings of the centre",
          sph::Range::closed(0.5, 10));
    p.add("smoothing_length_factor", p_.smoothing_length_factor, "-", "eta of h = eta sqrt(m / rho)", sph::Range::closed(1.0, 2.5));
    declare_artificial_viscosity(p, p_.alpha, p_.beta);
    declare_run_length(p, p_.end_time, p_.output_interval, "-");
  }

  void check() const override {
    const sph::SedovSolution exact = solution();
    const double reach = 1.2 * exact.shock_radius(p_.end_time);
    if (reach >= p_.half_width)
      throw sph::ParameterError("parameter 'half_width' = " + std::to_string(p_.half_width) + " is too small: the shock reaches " +
                                std::to_string(exact.shock_radius(p_.end_time)) + " by end_time");
  }

  bool checkpoints() const override { return true; }  // nothing kept outside the body

  void run(RunContext& ctx) override {
    const Real dx = Real(1) / static_cast<Real>(p_.resolution);
    const Real L = dx * std::round(Real(p_.half_width) / dx);
    auto gas = geometry::lattice_box<2>("gas", Vec2(-L, -L), Vec2(L, L), dx);
    const std::size_t n = gas.n_particles();
    sph::UpdatedLagrangianBody<2>::Settings settings;
    settings.equation_of_state = sph::IdealGas{p_.gamma};
    settings.smoothing_length = Real(p_.smoothing_length_factor) * dx;
    settings.smoothing_length_factor = Real(p_.smoothing_length_factor);
    settings.density_summation = true;
    settings.alpha = Real(p_.alpha);
    settings.beta = Real(p_.beta);
    sph::UpdatedLagrangianBody<2> body(gas, settings);
    auto rho = gas.field(body.density_field());
    auto e = gas.field(body.energy_field());
    // The blast: kernel weights over the particles within blast_radius dx of the centre.
    const Real reach = Real(p_.blast_radius) * dx;
    std::vector<double> weight(n, 0.0);
    double total_weight = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double q = double(gas.position[i].norm() / reach);
      if (q < 1) total_weight += weight[i] = (1 - q) * (1 - q);
    }
    const double mass = p_.density * double(dx) * double(dx);
    const double blast_pressure = (p_.gamma - 1) * p_.energy / (M_PI * double(reach) * double(reach));
    const double cold = 1e-6 * blast_pressure / ((p_.gamma - 1) * p_.density);  // specific energy of the cold gas
    for (std::size_t i = 0; i < n; ++i) {
      rho[i] = Real(p_.density);
      e[i] = Real(cold + (weight[i] > 0 ? p_.energy * weight[i] / total_weight / mass : 0.0));
    }
    body.initialise();
    const auto exact = solution();

    auto shock_radius = [&] {
      // The mean radius of the densest 1 % of the particles: the shell just behind the shock.
      std::vector<std::pair<Real, Real>> by_density(n);
      for (std::size_t i = 0; i < n; ++i) by_density[i] = {rho[i], gas.position[i].norm()};
      const std::size_t top = std::max<std::size_t>(1, n / 100);
      std::partial_sort(by_density.begin(), by_density.begin() + std::ptrdiff_t(top), by_density.end(),
                        [](const auto& a, const auto& b) { return a.first > b.first || (a.first == b.first && a.second < b.second); });
      double sum = 0;
      for (std::size_t k = 0; k < top; ++k) sum += by_density[k].second;
      return sum / double(top);
    };

    sph::TimeStepper stepper(0, static_cast<Real>(p_.end_time));
    stepper.add_stage(body.stage("blast"));
    sph::RunHarness run(stepper, ctx.report, {ctx.output_dir, "sedov-blast", ctx.quiet, ctx.checkpoint});
    run.add_body(gas, static_cast<Real>(p_.output_interval));
    run.add_relation("gas", body.relation());
    const double initial_energy = body.energies().total();
    run.add_time_series("shock.csv", {"shock_radius", "exact_shock_radius", "kinetic", "internal"}, static_cast<Real>(p_.end_time / 50),
                        [&](const sph::StepInfo& step) {
                          const auto en = body.energies();
                          const double exact_radius = step.time > 0 ? exact.shock_radius(step.time) : 0.0;
                          return std::vector<double>{shock_radius(), exact_radius, en.kinetic, en.internal};
                        });
    run.keep("body", body);
    run.run();
    plot_csv(ctx.output_dir, {"shock.csv", "shock.png", "Sedov blast: shock radius", "time", "radius",
                              {{1, 2, "SPH (densest 1 %)", ""}, {1, 3, "exact", ""}}, false, "lines"});

    const double t = p_.end_time, R = exact.shock_radius(t);
    const auto v = gas.field(body.velocity_field());
    const auto p = gas.field(body.pressure_field());
    double d_rho = 0, n_rho = 0;
    std::vector<std::pair<double, std::string>> rows;
    for (std::size_t i = 0; i < n; ++i) {
      const double r = gas.position[i].norm();
      if (r > 1.2 * R) continue;
      const auto s = exact.sample(r, t);
      d_rho += std::abs(rho[i] - s.density);
      n_rho += s.density;
      const double u = r > 0 ? double(v[i].dot(gas.position[i])) / r : 0.0;
      char line[200];
      std::snprintf(line, sizeof line, "%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g\n", r, double(rho[i]), u, double(p[i]), s.density, s.velocity,
                    s.pressure);
      rows.emplace_back(r, line);
    }
    std::sort(rows.begin(), rows.end());
    std::ostringstream csv;
    csv << "radius,density,radial_velocity,pressure,exact_density,exact_velocity,exact_pressure\n";
    for (const auto& row : rows) csv << row.second;
    sph::write_file_atomically(ctx.output_dir / "profile.csv", csv.str());
    plot_csv(ctx.output_dir, {"profile.csv", "profile.png", "Sedov blast at t = " + std::to_string(t), "radius", "",
                              {{1, 2, "density", ""}, {1, 5, "exact density", ""}, {1, 4, "pressure", ""}, {1, 7, "exact pressure", ""}},
                              false, "points pt 7 ps 0.3"});

    auto& report = ctx.report;
    report.reference = "self-similar Sedov-Taylor solution (cylindrical; Sedov 1959, Kamm & Timmes 2007)";
    const double measured = shock_radius();
    report.errors["shock_radius_relative"] = (measured - R) / R;
    report.errors["density_l1"] = d_rho / n_rho;
    report.results["shock_radius"] = measured;
    report.results["exact_shock_radius"] = R;
    report.results["xi0"] = exact.xi0();
    report.results["energy_change_relative"] = (body.energies().total() - initial_energy) / initial_energy;
    report.results["particle_spacing"] = dx;
  }

 private:
  sph::SedovSolution solution() const { return sph::SedovSolution(2, p_.gamma, p_.energy, p_.density); }

  SedovBlastParameters p_;
};

}  // namespace

std::unique_ptr<Scene> make_sedov_blast_scene(SedovBlastParameters parameters) {
  return std::make_unique<SedovBlastScene>(std::move(parameters));
}

}  // namespace cardiosph
