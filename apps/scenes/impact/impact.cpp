// A small basalt-sphere impact after Nakamura & Fujiwara 1991 (Icarus 92:132): a basalt sphere of
// radius 3 cm struck at 3.2 km/s, 30 degrees from its normal, by a 0.2 g projectile; their
// largest fragment kept about 31 % of the target's mass (as quoted by the SPH studies of the shot;
// the paper's table itself was not at hand). Benz & Asphaug 1994 (Icarus 107:98) simulated it with
// SPH, strength and Grady-Kipp damage.
//
// The setup follows the public inputs of those studies: basalt Tillotson (Benz & Asphaug 1999),
// shear modulus 22.7 GPa, von Mises yield 3.5 GPa, Weibull flaws k = 5e34 m^-3, m = 8.5 (Benz &
// Asphaug 1994; the values of miluphcuda's `nakamura` test case and Spheral's SphereImpact script).
// One difference: the body holds one material, so the projectile is basalt of the same mass and
// speed (0.2 g, radius 2.6 mm) rather than nylon (radius 3.4 mm); impulse and energy are the
// experiment's. The impact parameter is (R_target + R_projectile) sin 30 degrees.
//
// Measured at end_time: fragments as clusters of particles joined through neighbours that are not
// fully damaged (D < 1; fully damaged particles are dust of one particle each), their masses
// (fragments.csv: the cumulative number of fragments above each mass), the largest fragment's mass
// fraction against the experiment's 0.31 (errors.largest_fragment_fraction: the difference), and
// the damaged share of the target; the fracture area (Grady-Kipp, summed over the target) and,
// inside the damaged particles, Grady-Kipp's fragment sizes (grady_kipp_sizes.csv and .png).

#include <algorithm>
#include <cmath>
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
#include "libsph/impact/damage.hpp"
#include "libsph/impact/updated_lagrangian.hpp"
#include "libsph/io/atomic_file.hpp"
#include "libsph/io/run_harness.hpp"

namespace cardiosph {
namespace {

using sph::Real;
using Vec3 = sph::Vec<3>;

// The reference, fixed (not a parameter, so no setting moves the reported error): the largest
// fragment of Nakamura & Fujiwara 1991 (Icarus 92:132) kept about 31 % of the target's mass.
constexpr double kExperimentLargestFragment = 0.31;  // [-] mass fraction of the target

class ImpactScene final : public Scene {
 public:
  explicit ImpactScene(ImpactParameters p) : p_(std::move(p)) {}

  void declare(sph::Parameters& p) override {
    p.add("resolution", p_.resolution, "-", "particles across the target's radius", sph::Range::closed(4, 200));
    p.add("target_radius", p_.target_radius, "m", "radius of the basalt sphere", sph::Range::positive());
    p.add("projectile_mass", p_.projectile_mass, "kg", "projectile mass (basalt of this mass)", sph::Range::positive());
    p.add("speed", p_.speed, "m/s", "impact speed", sph::Range::positive());
    p.add("impact_angle", p_.impact_angle, "deg", "angle from the target's normal at the point of impact", {0, 90, false, true});
    p.add("shear_modulus", p_.shear_modulus, "Pa", "shear modulus", sph::Range::positive());
    p.add("yield_strength", p_.yield_strength, "Pa", "von Mises yield strength", sph::Range::positive());
    p.add("weibull_k", p_.weibull_k, "1/m^3", "Weibull flaw density k of n(eps) = k eps^m", sph::Range::positive());
    p.add("weibull_m", p_.weibull_m, "-", "Weibull exponent m", sph::Range::positive());
    p.add("seed", p_.seed, "-", "seed of the flaw assignment", sph::Range::closed(0, 1e9));
    p.add("smoothing_length_ratio", p_.smoothing_length_ratio, "-", "h / dx (cubic spline M4 kernel)", sph::Range::closed(1.0, 2.5));
    declare_artificial_viscosity(p, p_.alpha, p_.beta);
    declare_run_length(p, p_.end_time, p_.output_interval, "s");
  }

  bool checkpoints() const override { return true; }  // the flaws are drawn again from the seed

  void run(RunContext& ctx) override {
    const auto& basalt = sph::tillotson_material("basalt").parameters;
    const double rho0 = basalt.reference_density, R = p_.target_radius;
    const Real dx = Real(R / double(p_.resolution));
    const double r_projectile = std::cbrt(3 * p_.projectile_mass / (4 * M_PI * rho0));
    // Target centred at the origin; the projectile comes along -x towards it, offset along y.
    const double offset = (R + r_projectile) * std::sin(p_.impact_angle * M_PI / 180);
    const double start_x = std::sqrt(std::max(0.0, (R + r_projectile) * (R + r_projectile) - offset * offset)) + double(dx);
    const double cells = std::ceil(R / dx) + 1, span = double(dx) * cells;
    auto target = geometry::lattice_where<3>("basalt", Vec3(Real(-span), Real(-span), Real(-span)), Vec3(Real(span), Real(span), Real(span)),
                                             dx, [&](const Vec3& x) { return x.norm() < Real(R); });
    std::vector<Vec3> x = target.position;
    std::vector<Real> volume = target.volume;
    const std::size_t n_target = x.size();
    // The projectile's particles on the same lattice spacing, their volumes scaled to its mass.
    const double p_cells = std::ceil(r_projectile / dx);
    std::vector<Vec3> projectile;
    for (double i = -p_cells; i <= p_cells; ++i)
      for (double j = -p_cells; j <= p_cells; ++j)
        for (double k = -p_cells; k <= p_cells; ++k) {
          const Vec3 d(Real(i * dx), Real(j * dx), Real(k * dx));
          if (d.norm() <= Real(std::max(r_projectile, 0.5 * double(dx)))) projectile.push_back(d);
        }
    const Real projectile_volume = Real(p_.projectile_mass / rho0 / double(projectile.size()));
    for (const auto& d : projectile) {
      x.push_back(d + Vec3(Real(start_x), Real(offset), 0));
      volume.push_back(projectile_volume);
    }
    sph::ParticleSet<3> rock("rock", std::move(x), std::move(volume));
    const std::size_t n = rock.n_particles();

    sph::UpdatedLagrangianBody<3>::Settings settings;
    settings.equation_of_state = basalt;
    settings.smoothing_length = Real(p_.smoothing_length_ratio) * dx;
    settings.alpha = Real(p_.alpha);
    settings.beta = Real(p_.beta);
    settings.shear_modulus = Real(p_.shear_modulus);
    settings.yield_strength = Real(p_.yield_strength);
    const double K = basalt.A, mu = p_.shear_modulus;
    settings.damage = sph::DamageSettings{{p_.weibull_k, p_.weibull_m}, std::uint64_t(p_.seed), Real(9 * K * mu / (3 * K + mu))};
    sph::UpdatedLagrangianBody<3> body(rock, settings);
    auto rho = rock.field(body.density_field());
    auto v = rock.field(body.velocity_field());
    for (std::size_t i = 0; i < n; ++i) {
      rho[i] = Real(rho0);
      v[i] = i < n_target ? Vec3::Zero() : Vec3(Real(-p_.speed), 0, 0);
    }
    body.initialise();

    sph::TimeStepper stepper(0, static_cast<Real>(p_.end_time));
    stepper.add_stage(body.stage("impact"));
    sph::RunHarness run(stepper, ctx.report, {ctx.output_dir, "impact", ctx.quiet, ctx.checkpoint});
    run.add_body(rock, static_cast<Real>(p_.output_interval));
    run.add_relation("rock", body.relation());
    const auto D = rock.field(body.damage_field());
    const auto m = rock.field(body.mass_field());
    const double target_mass = [&] {
      double sum = 0;
      for (std::size_t i = 0; i < n_target; ++i) sum += m[i];
      return sum;
    }();
    auto damaged_share = [&] {
      double sum = 0;
      for (std::size_t i = 0; i < n_target; ++i) sum += m[i] * D[i];
      return sum / target_mass;
    };
    const double initial_energy = body.energies().total();
    run.add_time_series("impact.csv", {"damaged_mass_share", "kinetic", "internal", "total"}, static_cast<Real>(p_.end_time / 200),
                        [&](const sph::StepInfo&) {
                          const auto en = body.energies();
                          return std::vector<double>{damaged_share(), en.kinetic, en.internal, en.total()};
                        });
    run.keep("body", body);
    run.run();

    const auto fragments = sph::find_fragments<3>(body.relation(), m, D, Real(1));
    sph::write_file_atomically(ctx.output_dir / "fragments.csv", sph::cumulative_mass_distribution_csv(fragments));
    plot_csv(ctx.output_dir, {"fragments.csv", "fragments.png", "Fragments: cumulative number above each mass", "mass [kg]",
                              "number of fragments", {{1, 2, "fragments", ""}}, true, "steps"});
    // Grady-Kipp's fragment sizes inside the damaged particles (Melosh et al. 1992): each particle
    // with a fracture area A_i > 0 holds F_cum(L) fragments larger than L, with L_max from A_i.
    const auto A = rock.field(body.fracture_area_field());
    const sph::WeibullParameters weibull{p_.weibull_k, p_.weibull_m};
    double total_area = 0, smallest = 1e300, largest_size = 0;
    for (std::size_t i = 0; i < n_target; ++i) {
      if (!(A[i] > 0)) continue;
      const double particle_volume = m[i] / rho[i];
      total_area += A[i] * particle_volume;
      const double l_max = sph::largest_fragment_size(weibull, sph::most_frequent_fragment_size(weibull, A[i]));
      smallest = std::min(smallest, l_max);
      largest_size = std::max(largest_size, l_max);
    }
    {
      std::ostringstream csv;
      csv << "size,cumulative_number\n";
      if (largest_size > 0) {
        const int points = 60;
        const double low = 0.01 * smallest;
        for (int k = 0; k < points; ++k) {
          const double L = low * std::pow(largest_size / low, double(k) / (points - 1));
          double count = 0;
          for (std::size_t i = 0; i < n_target; ++i) {
            if (!(A[i] > 0)) continue;
            const double l_max = sph::largest_fragment_size(weibull, sph::most_frequent_fragment_size(weibull, A[i]));
            if (L < l_max) count += sph::cumulative_fragment_number(weibull, L, l_max, m[i] / rho[i]);
          }
          csv << L << ',' << count << '\n';
        }
      }
      sph::write_file_atomically(ctx.output_dir / "grady_kipp_sizes.csv", csv.str());
      if (largest_size > 0)
        plot_csv(ctx.output_dir, {"grady_kipp_sizes.csv", "grady_kipp_sizes.png",
                                  "Grady-Kipp fragments inside the damaged particles: number larger than L", "L [m]", "number",
                                  {{1, 2, "fragments", ""}}, true, "lines"});
    }
    std::size_t dust = 0;
    for (const auto& f : fragments.fragments) dust += f.particles == 1;
    const double largest = fragments.fragments.empty() ? 0.0 : double(fragments.fragments.front().mass) / double(fragments.total_mass);
    auto& report = ctx.report;
    report.reference = "Nakamura & Fujiwara 1991 (Icarus 92:132): largest fragment 0.31 of the target's mass (docs/impact.md)";
    report.errors["largest_fragment_fraction"] = largest - kExperimentLargestFragment;
    report.results["largest_fragment_fraction"] = largest;
    report.results["fragments"] = double(fragments.n_fragments());
    report.results["fragments_of_one_particle"] = double(dust);
    report.results["damaged_mass_share"] = damaged_share();
    report.results["flaws"] = double(body.flaws().total_flaws);
    report.results["fracture_area"] = total_area;            // m^2, summed over the target
    report.results["largest_grady_kipp_size"] = largest_size;  // m, L_max of the least damaged particle with cracks
    report.results["energy_change_relative"] = (body.energies().total() - initial_energy) / initial_energy;
    report.results["projectile_particles"] = double(n - n_target);
    report.results["particle_spacing"] = dx;
  }

 private:
  ImpactParameters p_;
};

}  // namespace

std::unique_ptr<Scene> make_impact_scene(ImpactParameters parameters) { return std::make_unique<ImpactScene>(std::move(parameters)); }

}  // namespace cardiosph
