// Two elastic rings colliding (Gray, Monaghan & Swift 2001, Comput. Methods Appl. Mech. Engrg.
// 190:6641, section 6.2): rings of inner radius 3 and outer radius 4 (their consistent units), E = 1e7,
// nu = 0.3975, rho0 = 1, each moving towards the other at 0.059 c0 with c0 = sqrt(K / rho0) the bulk
// sound speed. The rings interact through the SPH sums alone (one body, no contact algorithm). With the
// artificial stress they bounce and separate as two whole rings; without it, the tension behind the
// contact clumps the particles (the tensile instability, Swegle et al. 1995) and the rings tear.
// The scene runs either way (`artificial_stress`), so both can be shown.
//
// What is measured:
//   results.fragments: clusters of particles linked by gaps below 1.5 dx (two whole rings: 2);
//   results.clumped_fraction: the share of particles with a neighbour closer than dx / 2 (clumping);
//   results.rebound_velocity_ratio: the left ring's mean velocity along x at the end over its initial
//     one (-1: a perfectly elastic bounce; positive: the rings still move on into each other);
//   results.energy_change_relative: kinetic + internal energy at the end against the start.
// rings.csv has the two rings' mean velocities and the energies against time (rings.png draws the
// velocities); shape.csv and shape.png the particles at the end.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numeric>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "apps/plot.hpp"
#include "apps/scenes/impact/impact_parameters.hpp"
#include "apps/scenes/impact/impact_scenes.hpp"
#include "geometry/lattice.hpp"
#include "libsph/core/time_stepper.hpp"
#include "libsph/core/union_find.hpp"
#include "libsph/impact/updated_lagrangian.hpp"
#include "libsph/io/atomic_file.hpp"
#include "libsph/io/run_harness.hpp"

namespace cardiosph {
namespace {

using sph::Real;
using Vec2 = sph::Vec<2>;

// Clusters of particles closer than `link` to one another (union-find over the pairs of `relation`).
std::size_t count_clusters(const sph::InnerRelation<2>& relation, std::size_t n, Real link) {
  sph::UnionFind clusters(n);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = relation.offsets[i]; k < relation.offsets[i + 1]; ++k)
      if (relation.distance[k] < link) clusters.unite(i, relation.neighbour[k]);
  return clusters.n_sets();
}

class RubberRingsScene final : public Scene {
 public:
  explicit RubberRingsScene(RubberRingsParameters p) : p_(std::move(p)) {}

  void declare(sph::Parameters& p) override {
    p.add("resolution", p_.resolution, "-", "particles across a ring's wall (dx = wall / resolution)", sph::Range::closed(4, 200));
    p.add("inner_radius", p_.inner_radius, "-", "inner radius of each ring", sph::Range::positive());
    p.add("outer_radius", p_.outer_radius, "-", "outer radius of each ring", sph::Range::positive());
    p.add("gap", p_.gap, "-", "initial gap between the rings along x", sph::Range::non_negative());
    p.add("density", p_.density, "-", "reference density rho0", sph::Range::positive());
    p.add("youngs_modulus", p_.youngs_modulus, "-", "Young's modulus E", sph::Range::positive());
    p.add("poisson_ratio", p_.poisson_ratio, "-", "Poisson's ratio", {0, 0.5, false, true});
    p.add("speed", p_.speed, "c0", "each ring's speed towards the other, in units of c0 = sqrt(K / rho0)",
          sph::Range::positive());
    p.add("artificial_stress", p_.artificial_stress, "Gray, Monaghan & Swift's artificial stress (false shows the tensile instability)");
    p.add("artificial_stress_factor", p_.artificial_stress_factor, "-", "epsilon of R = -epsilon sigma_A / rho^2",
          sph::Range::non_negative());
    p.add("smoothing_length_ratio", p_.smoothing_length_ratio, "-", "h / dx (cubic spline M4 kernel)", sph::Range::closed(1.0, 2.5));
    declare_artificial_viscosity(p, p_.alpha, p_.beta);
    declare_run_length(p, p_.end_time, p_.output_interval, "-");
  }

  void check() const override {
    if (!(p_.inner_radius < p_.outer_radius))
      throw sph::ParameterError("parameter 'inner_radius' = " + std::to_string(p_.inner_radius) + " must be below 'outer_radius' = " +
                                std::to_string(p_.outer_radius));
  }

  bool checkpoints() const override { return true; }  // nothing kept outside the body

  void run(RunContext& ctx) override {
    const double wall = p_.outer_radius - p_.inner_radius;
    const Real dx = Real(wall / double(p_.resolution));
    const double ro = p_.outer_radius, ri = p_.inner_radius, offset = ro + 0.5 * p_.gap;
    // One lattice over both rings, so that the spacing is the same in the gap.
    const double half_width = offset + ro, cells_x = std::ceil(half_width / dx), cells_y = std::ceil(ro / dx);
    const Vec2 lower(Real(-cells_x * dx), Real(-cells_y * dx)), upper(Real(cells_x * dx), Real(cells_y * dx));
    auto in_ring = [&](const Vec2& x, double centre) {
      const double r = std::hypot(double(x[0]) - centre, double(x[1]));
      return r >= ri && r < ro;
    };
    auto rings = geometry::lattice_where<2>("rings", lower, upper, dx,
                                            [&](const Vec2& x) { return in_ring(x, -offset) || in_ring(x, offset); });
    const double nu = p_.poisson_ratio, E = p_.youngs_modulus;
    const double K = E / (3 * (1 - 2 * nu)), mu = E / (2 * (1 + nu)), c0 = std::sqrt(K / p_.density);
    sph::UpdatedLagrangianBody<2>::Settings settings;
    settings.equation_of_state = sph::LinearPressure{p_.density, c0};
    settings.smoothing_length = Real(p_.smoothing_length_ratio) * dx;
    settings.alpha = Real(p_.alpha);
    settings.beta = Real(p_.beta);
    settings.shear_modulus = Real(mu);
    settings.artificial_stress = p_.artificial_stress;
    settings.artificial_stress_factor = Real(p_.artificial_stress_factor);
    settings.particle_spacing = dx;
    sph::UpdatedLagrangianBody<2> body(rings, settings);
    auto rho = rings.field(body.density_field());
    auto v = rings.field(body.velocity_field());
    const std::size_t n = rings.n_particles();
    std::vector<char> left(n);
    const Real u0 = Real(p_.speed * c0);
    for (std::size_t i = 0; i < n; ++i) {
      left[i] = rings.position[i][0] < 0;
      rho[i] = Real(p_.density);
      v[i] = Vec2(left[i] ? u0 : -u0, 0);
    }
    body.initialise();

    auto ring_velocities = [&] {
      double sum[2] = {0, 0}, count[2] = {0, 0};
      for (std::size_t i = 0; i < n; ++i) {
        sum[left[i] ? 0 : 1] += v[i][0];
        count[left[i] ? 0 : 1] += 1;
      }
      return std::pair{sum[0] / count[0], sum[1] / count[1]};
    };

    sph::TimeStepper stepper(0, static_cast<Real>(p_.end_time));
    stepper.add_stage(body.stage("elastic dynamics"));
    sph::RunHarness run(stepper, ctx.report, {ctx.output_dir, "rubber-rings", ctx.quiet, ctx.checkpoint});
    run.add_body(rings, static_cast<Real>(p_.output_interval));
    run.add_relation("rings", body.relation());
    const double initial_energy = body.energies().total();
    run.add_time_series("rings.csv", {"left_velocity", "right_velocity", "kinetic", "internal", "total"},
                        static_cast<Real>(p_.end_time / 200), [&](const sph::StepInfo&) {
                          const auto [l, r] = ring_velocities();
                          const auto en = body.energies();
                          return std::vector<double>{l, r, en.kinetic, en.internal, en.total()};
                        });
    run.keep("body", body);
    run.run();

    plot_csv(ctx.output_dir, {"rings.csv", "rings.png",
                              std::string("Colliding rings, ") + (p_.artificial_stress ? "with" : "without") + " artificial stress",
                              "time", "mean velocity along x", {{1, 2, "left ring", ""}, {1, 3, "right ring", ""}}, false, "lines"});
    {  // The final shape, drawn as points.
      std::ostringstream csv;
      csv << "x,y,pressure\n";
      const auto p = rings.field(body.pressure_field());
      for (std::size_t i = 0; i < n; ++i) {
        char line[96];
        std::snprintf(line, sizeof line, "%.6g,%.6g,%.6g\n", double(rings.position[i][0]), double(rings.position[i][1]), double(p[i]));
        csv << line;
      }
      sph::write_file_atomically(ctx.output_dir / "shape.csv", csv.str());
      plot_csv(ctx.output_dir, {"shape.csv", "shape.png",
                                std::string("Rings at the end, ") + (p_.artificial_stress ? "with" : "without") + " artificial stress",
                                "x", "y", {{1, 2, "particles", ""}}, false, "points pt 7 ps 0.3"});
    }
    const auto& R = body.relation();
    std::size_t clumped = 0;
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t k = R.offsets[i]; k < R.offsets[i + 1]; ++k)
        if (R.distance[k] < Real(0.5) * dx) {
          ++clumped;
          break;
        }
    const auto [l, r] = ring_velocities();
    auto& report = ctx.report;
    report.reference = "Gray, Monaghan & Swift 2001: with artificial stress the rings bounce apart whole; without it they tear";
    report.results["fragments"] = double(count_clusters(R, n, Real(1.5) * dx));
    report.results["clumped_fraction"] = double(clumped) / double(n);
    report.results["rebound_velocity_ratio"] = l / double(u0);
    report.results["right_ring_velocity_ratio"] = r / double(-u0);
    report.results["energy_change_relative"] = (body.energies().total() - initial_energy) / initial_energy;
    report.results["bulk_sound_speed"] = c0;
    report.results["particle_spacing"] = dx;
  }

 private:
  RubberRingsParameters p_;
};

}  // namespace

std::unique_ptr<Scene> make_rubber_rings_scene(RubberRingsParameters parameters) {
  return std::make_unique<RubberRingsScene>(std::move(parameters));
}

}  // namespace cardiosph
