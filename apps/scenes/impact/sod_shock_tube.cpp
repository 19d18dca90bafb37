// Sod's shock tube (Sod 1978, J. Comput. Phys. 27:1): an ideal gas (gamma = 1.4) at rest with
// rho, p = 1, 1 for x < 0 and 0.125, 0.1 for x > 0, released at t = 0. By t = 0.2 a rarefaction runs
// left, a contact and a shock right; the exact solution is the Riemann problem's
// (libsph/impact/exact_riemann.hpp). Particles on one lattice (spacing dx = 1 / resolution, masses
// rho dx^2) fill the tube [-L, L] in a slab of `rows` rows, periodic across (in 3D a bar of
// rows x rows, periodic across both sides, masses rho dx^3); the ends stay outside
// the waves until t = 0.2 for L = 1. The smoothing length is constant, h = 2 dx: the flow expands
// the gas along x only, and the layers of the expanded gas (density 0.426, 2.35 dx apart along x)
// must stay inside each other's support (with h = 1.2 dx they decouple and the contact keeps a
// spurious pressure jump: density L1 0.10 at resolutions 100 and 200 alike).
//
// errors.density_l1 = sum_i |rho_i - rho(x_i)| / sum_i rho(x_i) over the particles with |x| <= 1/2
// (the particles sample the line with equal spacing in the initial state; the same relative L1 for
// velocity, against the largest |u|, and for pressure). profile.csv holds x and the particle
// values with the exact ones; profile.png draws density, velocity and pressure against them.

#include <algorithm>
#include <cmath>
#include <utility>
#include <cstdio>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "apps/plot.hpp"
#include "apps/scenes/impact/impact_parameters.hpp"
#include "apps/scenes/impact/impact_scenes.hpp"
#include "geometry/lattice.hpp"
#include "libsph/core/time_stepper.hpp"
#include "libsph/impact/exact_riemann.hpp"
#include "libsph/impact/updated_lagrangian.hpp"
#include "libsph/io/atomic_file.hpp"
#include "libsph/io/run_harness.hpp"

namespace cardiosph {
namespace {

using sph::Real;

class SodShockTubeScene final : public Scene {
 public:
  explicit SodShockTubeScene(SodShockTubeParameters p) : p_(std::move(p)) {}

  void declare(sph::Parameters& p) override {
    p.add("resolution", p_.resolution, "-", "particles per unit length (dx = 1 / resolution, both sides)",
          sph::Range::closed(20, 20000));
    declare_run_length(p, p_.end_time, p_.output_interval, "-");
    p.add("tube_half_length", p_.tube_half_length, "-", "the tube is [-L, L]", sph::Range::positive());
    p.add("dimension", p_.dimension, "-", "2: a slab periodic across; 3: a square bar periodic across both sides",
          sph::Range::closed(2, 3));
    p.add("rows", p_.rows, "-", "particle rows across the periodic slab (at least the kernel support)",
          sph::Range::closed(3, 1000));
    p.add("gamma", p_.gamma, "-", "ratio of specific heats of the ideal gas", {1, 10, true, false});
    p.add("left_density", p_.left_density, "-", "density for x < 0", sph::Range::positive());
    p.add("left_pressure", p_.left_pressure, "-", "pressure for x < 0", sph::Range::positive());
    p.add("right_density", p_.right_density, "-", "density for x > 0", sph::Range::positive());
    p.add("right_pressure", p_.right_pressure, "-", "pressure for x > 0", sph::Range::positive());
    p.add("smoothing_length_ratio", p_.smoothing_length_ratio, "-", "h / dx (cubic spline M4 kernel)",
          sph::Range::closed(1.0, 2.5));
    declare_artificial_viscosity(p, p_.alpha, p_.beta);
    p.add("epsilon", p_.epsilon, "-", "artificial viscosity: the epsilon h^2 of phi_ij's denominator", sph::Range::positive());
  }

  void check() const override {
    if (double(p_.rows) < 2 * 2 * p_.smoothing_length_ratio)
      throw sph::ParameterError("parameter 'rows' = " + std::to_string(p_.rows) +
                                " is narrower than the kernel support across the slab (at least " +
                                std::to_string(int(std::ceil(4 * p_.smoothing_length_ratio))) + ")");
    // The exact solution exists (no vacuum) and the waves stay inside the tube.
    const sph::ExactRiemannSolution exact = solution();
    const double c_left = std::sqrt(p_.gamma * p_.left_pressure / p_.left_density);
    const double reach = p_.end_time * std::max(c_left, std::abs(exact.star_velocity()) + 2 * c_left);
    if (reach >= p_.tube_half_length)
      throw sph::ParameterError("parameter 'tube_half_length' = " + std::to_string(p_.tube_half_length) +
                                " is too short: the waves (and the ends' own expansion) travel about " + std::to_string(reach) +
                                " by end_time");
  }

  bool checkpoints() const override { return true; }  // nothing kept outside the body

  void run(RunContext& ctx) override {
    if (p_.dimension == 3)
      run_in<3>(ctx);
    else
      run_in<2>(ctx);
  }

 private:
  template <int Dim>
  void run_in(RunContext& ctx) {
    using Vec = sph::Vec<Dim>;
    const Real dx = Real(1) / static_cast<Real>(p_.resolution);
    const Real L = static_cast<Real>(p_.tube_half_length), W = dx * static_cast<Real>(p_.rows);
    // The tube along x; the slab W wide (and deep in 3D), periodic across.
    Vec lower = Vec::Zero(), upper = Vec::Constant(W);
    lower[0] = -L;
    upper[0] = L;
    auto gas = geometry::lattice_box<Dim>("gas", lower, upper, dx);
    typename sph::UpdatedLagrangianBody<Dim>::Settings settings;
    settings.equation_of_state = sph::IdealGas{p_.gamma};
    settings.smoothing_length = static_cast<Real>(p_.smoothing_length_ratio) * dx;
    settings.alpha = Real(p_.alpha);
    settings.beta = Real(p_.beta);
    settings.epsilon = Real(p_.epsilon);
    settings.periodic.lower = lower;
    settings.periodic.upper = upper;
    for (int d = 1; d < Dim; ++d) settings.periodic.periodic[d] = true;
    sph::UpdatedLagrangianBody<Dim> body(gas, settings);
    auto rho = gas.field(body.density_field());
    auto e = gas.field(body.energy_field());
    for (std::size_t i = 0; i < gas.n_particles(); ++i) {
      const bool left = gas.position[i][0] < 0;
      rho[i] = Real(left ? p_.left_density : p_.right_density);
      e[i] = Real((left ? p_.left_pressure : p_.right_pressure) / ((p_.gamma - 1) * rho[i]));
    }
    body.initialise();

    sph::TimeStepper stepper(0, static_cast<Real>(p_.end_time));
    stepper.add_stage(body.stage("hydrodynamics"));
    sph::RunHarness run(stepper, ctx.report, {ctx.output_dir, "sod-shock-tube", ctx.quiet, ctx.checkpoint});
    run.add_body(gas, static_cast<Real>(p_.output_interval));
    run.add_relation("gas", body.relation());
    const double initial_energy = body.energies().total();
    run.add_time_series("energy.csv", {"kinetic", "internal", "total"}, static_cast<Real>(p_.end_time / 100),
                        [&](const sph::StepInfo&) {
                          const auto en = body.energies();
                          return std::vector<double>{en.kinetic, en.internal, en.total()};
                        });
    run.keep("body", body);
    run.run();

    // Errors against the exact solution on [-1/2, 1/2].
    const auto exact = solution();
    const double t = p_.end_time;
    const auto v = gas.field(body.velocity_field());
    const auto p = gas.field(body.pressure_field());
    double d_rho = 0, n_rho = 0, d_u = 0, d_p = 0, n_p = 0, u_max = 0;
    std::vector<std::pair<double, std::string>> profile;  // one row of particles, sorted by x
    std::ostringstream csv;
    csv << "x,density,velocity,pressure,specific_internal_energy,exact_density,exact_velocity,exact_pressure,exact_energy\n";
    for (std::size_t i = 0; i < gas.n_particles(); ++i) {
      const double x = gas.position[i][0];
      const auto s = exact.sample(x / t);
      const double ex_e = s.pressure / ((p_.gamma - 1) * s.density);
      if (gas.position[i].template tail<Dim - 1>().maxCoeff() < dx) {  // one row for the profile
        char line[256];
        std::snprintf(line, sizeof line, "%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g\n", x, double(rho[i]), double(v[i][0]),
                      double(p[i]), double(e[i]), s.density, s.velocity, s.pressure, ex_e);
        profile.emplace_back(x, line);
      }
      if (std::abs(x) > 0.5) continue;
      d_rho += std::abs(rho[i] - s.density);
      n_rho += s.density;
      d_u += std::abs(v[i][0] - s.velocity);
      u_max = std::max(u_max, std::abs(s.velocity));
      d_p += std::abs(p[i] - s.pressure);
      n_p += s.pressure;
    }
    std::sort(profile.begin(), profile.end());
    for (const auto& row : profile) csv << row.second;
    std::size_t counted = 0;
    for (const auto& x : gas.position) counted += std::abs(double(x[0])) <= 0.5;
    sph::write_file_atomically(ctx.output_dir / "profile.csv", csv.str());
    plot_csv(ctx.output_dir, {"profile.csv", "profile.png", "Sod shock tube at t = " + std::to_string(t), "x", "",
                              {{1, 2, "density", ""}, {1, 6, "exact density", ""}, {1, 3, "velocity", ""},
                               {1, 7, "exact velocity", ""}, {1, 4, "pressure", ""}, {1, 8, "exact pressure", ""}},
                              false, "lines"});

    auto& report = ctx.report;
    report.reference = "exact Riemann solution (Toro 2009, ch. 4) of Sod's shock tube";
    report.errors["density_l1"] = d_rho / n_rho;
    report.errors["velocity_l1"] = d_u / (double(counted) * u_max);
    report.errors["pressure_l1"] = d_p / n_p;
    const auto en = body.energies();
    report.results["energy_change_relative"] = (en.total() - initial_energy) / initial_energy;
    report.results["star_pressure"] = exact.star_pressure();
    report.results["star_velocity"] = exact.star_velocity();
    report.results["particle_spacing"] = dx;
    report.results["smoothing_length"] = settings.smoothing_length;
  }

  sph::ExactRiemannSolution solution() const {
    return sph::ExactRiemannSolution({p_.left_density, 0, p_.left_pressure}, {p_.right_density, 0, p_.right_pressure}, p_.gamma);
  }

  SodShockTubeParameters p_;
};

}  // namespace

std::unique_ptr<Scene> make_sod_shock_tube_scene(SodShockTubeParameters parameters) {
  return std::make_unique<SodShockTubeScene>(std::move(parameters));
}

}  // namespace cardiosph
