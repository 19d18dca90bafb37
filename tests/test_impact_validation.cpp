// The impact family against references: Sod's shock tube against the exact Riemann solution, at the
// default resolution (bound: errors.density_l1 below the 5 % asked, measured 1.82 %) and at half of it, for
// the order of convergence of the L1 density error; strength on Gray, Monaghan & Swift's oscillating
// plate (period against thin-plate theory) and their colliding rings (with and without artificial
// stress); the Taylor bar, Evrard's collapse, the Sedov blast, and the regression guard of the
// basalt-sphere impact (ImpactRegression), whose largest fragment misses the experiment's.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "apps/scenes/impact/impact_scenes.hpp"
#include "geometry/lattice.hpp"
#include "libsph/core/numerical_failure.hpp"
#include "libsph/impact/updated_lagrangian.hpp"
#include "run_scene_for_test.hpp"

namespace {

double error(const sph::RunReport& r, const char* key) { return r.errors.at(key).get<double>(); }

TEST(ImpactValidation, SodShockTubeConvergesToTheExactSolution) {
  cardiosph::SodShockTubeParameters p;
  const long fine = p.resolution;
  p.resolution = fine / 2;
  const auto coarse = test::run_scene(*cardiosph::make_sod_shock_tube_scene(p), "sod_coarse");
  p.resolution = fine;
  const auto r = test::run_scene(*cardiosph::make_sod_shock_tube_scene(p), "sod");
  const double rho_coarse = error(coarse, "density_l1"), rho = error(r, "density_l1");
  const double order = std::log2(rho_coarse / rho);
  std::printf("[ measured ] sod-shock-tube: density L1 %.4f at %ld per unit length (%.1f s), %.4f at %ld (%.1f s; bound 0.05): order "
              "%.2f; velocity L1 %.4f, pressure L1 %.4f; energy change %.2e (bound 1.6e-5)\n",
              rho_coarse, fine / 2, coarse.wall_time_s, rho, fine, r.wall_time_s, order, error(r, "velocity_l1"),
              error(r, "pressure_l1"), r.results.at("energy_change_relative").get<double>());
  EXPECT_LT(rho, 0.05);  // the bound asked at the default resolution (measured 1.82 %)
  EXPECT_LT(rho, rho_coarse);  // it converges
  // Total energy: the scheme conserves it to the time-integration error (measured -5.4e-6, bound 1.6e-5).
  EXPECT_LT(std::abs(r.results.at("energy_change_relative").get<double>()), 1.6e-5);
}

// The 3D bar (8 x 8 rows, periodic across both sides) at 50 per unit length: the same method in
// three dimensions, density L1 below the 5 % asked (measured 3.85 %; 2.43 % at 100, 1.73 % at 200).
TEST(ImpactValidation, SodShockTubeInThreeDimensions) {
  cardiosph::SodShockTubeParameters p;
  p.dimension = 3;
  p.resolution = 50;
  const auto r = test::run_scene(*cardiosph::make_sod_shock_tube_scene(p), "sod_3d");
  std::printf("[ measured ] sod-shock-tube in 3D at 50 per unit length: density L1 %.4f (bound 0.05), velocity L1 %.4f, pressure L1 %.4f, %.1f s\n",
              error(r, "density_l1"), error(r, "velocity_l1"), error(r, "pressure_l1"), r.wall_time_s);
  EXPECT_LT(error(r, "density_l1"), 0.05);
}

}  // namespace

// Strength: Gray, Monaghan & Swift 2001's oscillating plate (their section 5; the `oscillating-beam`
// setup): a plate 0.2 x 0.02 m clamped over 0.06 m at one end (held particles), rho0 = 1000,
// E = 2 MPa, nu = 0.3975, started in its first bending mode at a tip speed of 0.05 c0, c0 = sqrt(K / rho0).
// Its period against thin-plate theory, 2 pi / omega with omega^2 = E H^2 k^4 / (12 rho (1 - nu^2) L^4),
// k = 1.875: 0.2541 s. Artificial stress on, as in their runs.
namespace {

double plate_period(long across, bool artificial_stress, double& amplitude, double& seconds) {
  using Vec2 = sph::Vec<2>;
  const double L = 0.2, H = 0.02, clamp = 0.06, rho0 = 1000, E = 2e6, nu = 0.3975;
  const double K = E / (3 * (1 - 2 * nu)), mu = E / (2 * (1 + nu)), c0 = std::sqrt(K / rho0);
  const sph::Real dx = sph::Real(H / double(across));
  auto plate = geometry::lattice_box<2>("plate", Vec2(sph::Real(-clamp), sph::Real(-H / 2)), Vec2(sph::Real(L), sph::Real(H / 2)), dx);
  sph::UpdatedLagrangianBody<2>::Settings s;
  s.equation_of_state = sph::LinearPressure{rho0, c0};
  s.smoothing_length = sph::Real(1.3) * dx;
  s.shear_modulus = sph::Real(mu);
  s.artificial_stress = artificial_stress;
  s.particle_spacing = dx;
  sph::UpdatedLagrangianBody<2> body(plate, s);
  auto rho = plate.field(body.density_field());
  auto v = plate.field(body.velocity_field());
  const double k = 1.875, M = std::sin(k) + std::sinh(k), N = std::cos(k) + std::cosh(k);
  const double Q = 2 * (std::cos(k) * std::sinh(k) - std::sin(k) * std::cosh(k));
  std::vector<sph::Index> held, tip;
  for (std::size_t i = 0; i < plate.n_particles(); ++i) {
    rho[i] = sph::Real(rho0);
    const double x = plate.position[i][0] / L;
    if (x < 0) held.push_back(sph::Index(i));
    else v[i] = Vec2(0, sph::Real(0.05 * c0 * (M * (std::cos(k * x) - std::cosh(k * x)) - N * (std::sin(k * x) - std::sinh(k * x))) / Q));
    if (plate.position[i][0] > L - dx) tip.push_back(sph::Index(i));
  }
  body.hold(held);
  body.initialise();
  const auto y0 = plate.position;
  auto deflection = [&] {
    double sum = 0;
    for (const auto i : tip) sum += plate.position[i][1] - y0[i][1];
    return sum / double(tip.size());
  };
  const auto start = std::chrono::steady_clock::now();
  std::vector<double> crossings;
  double t = 0, previous = 0;
  amplitude = 0;
  while (t < 0.6) {
    const double dt = body.stable_time_step();
    body.advance(sph::Real(t), sph::Real(dt));
    t += dt;
    const double d = deflection();
    amplitude = std::max(amplitude, std::abs(d));
    if (t > dt && (d > 0) != (previous > 0)) crossings.push_back(t - dt * d / (d - previous));
    previous = d;
  }
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (crossings.size() < 3) return std::nan("");
  return 2 * (crossings.back() - crossings.front()) / double(crossings.size() - 1);
}

TEST(ImpactValidation, OscillatingPlatePeriodMatchesThinPlateTheory) {
  const double reference = 2 * M_PI / std::sqrt(2e6 * 0.02 * 0.02 * std::pow(1.875, 4) / (12 * 1000 * (1 - 0.3975 * 0.3975) * std::pow(0.2, 4)));
  double amplitude = 0, seconds = 0;
  const double period = plate_period(5, true, amplitude, seconds);
  std::printf("[ measured ] oscillating plate, updated-Lagrangian SPH, 5 across, artificial stress: period %.4f s (thin plate %.4f s, "
              "%+.1f %%; bound: above it, by less than 30 %%), tip amplitude %.4f m, %.1f s\n",
              period, reference, 100 * (period / reference - 1), amplitude, seconds);
  // Bound 30 %: five particles across the plate. The error falls with resolution (+25.7 % at 5
  // across, +12.9 % at 10, measured), as the total-Lagrangian beam's does with the nodal quadrature
  // (19 % at 5 across, README): the updated-Lagrangian gradient is only as good as its sampling of
  // the thickness.
  EXPECT_NEAR(period, reference, 0.30 * reference);
  EXPECT_GT(period, reference);  // SPH's bending is too soft at this resolution, never too stiff
}

// Gray, Monaghan & Swift 2001's colliding rings at 5 particles across the wall: with artificial
// stress the rings bounce back whole (2 clusters, no clumped particles, the velocity reversed);
// without it they tear (more than 2 clusters, clumped particles) and hardly rebound.
TEST(ImpactValidation, RubberRingsBounceWithArtificialStressAndTearWithout) {
  cardiosph::RubberRingsParameters p;
  p.resolution = 5;
  p.end_time = 3.2e-4;  // the rings have separated by then
  const auto with = test::run_scene(*cardiosph::make_rubber_rings_scene(p), "rings_with");
  p.artificial_stress = false;
  const auto without = test::run_scene(*cardiosph::make_rubber_rings_scene(p), "rings_without");
  auto result = [](const sph::RunReport& r, const char* key) { return r.results.at(key).get<double>(); };
  for (const auto* r : {&with, &without})
    std::printf("[ measured ] rubber-rings %s artificial stress: %g clusters, clumped %.3f, rebound velocity ratio %+.3f, "
                "energy change %+.3f, %.1f s\n",
                r == &with ? "with" : "without", result(*r, "fragments"), result(*r, "clumped_fraction"),
                result(*r, "rebound_velocity_ratio"), result(*r, "energy_change_relative"), r->wall_time_s);
  EXPECT_EQ(result(with, "fragments"), 2);
  EXPECT_EQ(result(with, "clumped_fraction"), 0);
  EXPECT_LT(result(with, "rebound_velocity_ratio"), -0.5);  // bounced back at more than half the speed
  EXPECT_GT(result(without, "fragments"), 2);
  EXPECT_GT(result(without, "clumped_fraction"), 0.05);
  EXPECT_GT(result(without, "rebound_velocity_ratio"), -0.5);
}

}  // namespace

// Taylor's copper bar (32.4 mm, radius 3.2 mm, 227 m/s onto a rigid frictionless wall, von Mises with
// linear hardening) at 3 and 2 particles across the radius: final length and mushroom radius against
// the finite-element values (21.47 mm, 7.12 mm). The artificial viscosity (alpha 0.5, beta 1) was
// chosen from runs at resolution 3 (docs/impact.md), so the test also runs the coarser bar, which
// played no part in that choice. Bound 5 % on each error at both (measured at 3: length +1.6 %,
// radius +0.4 %; at 2: -0.4 %, +3.2 %; at 4 and 5, not run here: +0.7 %, -1.5 % and +2.0 %, +4.0 %):
// three times the largest length error, 1.6 times the largest radius error. The energy is conserved to the time integration (measured 2.1e-4 at 3 and 3.1e-4
// at 2, bound 6e-4).
namespace {

TEST(ImpactValidation, TaylorBarFinalShapeMatchesTheFiniteElementReference) {
  for (const long resolution : {3L, 2L}) {
    cardiosph::TaylorBarParameters p;
    p.resolution = resolution;
    const auto r = test::run_scene(*cardiosph::make_taylor_bar_scene(p), "taylor_bar_" + std::to_string(resolution));
    const double length = error(r, "final_length_relative"), radius = error(r, "mushroom_radius_relative");
    const double energy = r.results.at("energy_change_relative").get<double>();
    std::printf("[ measured ] taylor-bar, %ld across the radius: final length %.2f mm (%+.1f %%), mushroom radius %.2f mm (%+.1f %%), "
                "bounds 5 %%; largest plastic strain %.2f, energy change %.1e (bound 6e-4), %.1f s\n",
                resolution, 1e3 * r.results.at("final_length").get<double>(), 100 * length,
                1e3 * r.results.at("mushroom_radius").get<double>(), 100 * radius, r.results.at("largest_plastic_strain").get<double>(),
                energy, r.wall_time_s);
    EXPECT_LT(std::abs(length), 0.05) << resolution;
    EXPECT_LT(std::abs(radius), 0.05) << resolution;
    EXPECT_LT(std::abs(energy), 6e-4) << resolution;
    EXPECT_LT(r.results.at("kinetic_energy_left").get<double>(), 0.01) << resolution;  // the bar has come to rest
  }
}

}  // namespace

// Evrard's collapse at 2,000 particles through the bounce (t = 1.3): kinetic + thermal + potential
// energy conserved within 8e-4 (measured 2.7e-4; the 1 % asked of errors.energy_conservation_relative
// is far above what the scheme does, and would not see it lose a tenth of that). The
// extremes are printed beside a 1D Lagrangian solution of the same problem (docs/impact.md: kinetic
// maximum 0.451 at t = 0.88, thermal maximum 1.760 at 1.07, potential minimum -2.546 at 1.05); at this
// resolution the collapse is slower and shallower than the 1D limit.
namespace {

TEST(ImpactValidation, EvrardCollapseConservesEnergy) {
  cardiosph::EvrardCollapseParameters p;
  p.particles = 2000;
  p.end_time = 1.3;
  const auto r = test::run_scene(*cardiosph::make_evrard_collapse_scene(p), "evrard");
  auto result = [&](const char* key) { return r.results.at(key).get<double>(); };
  const double drift = error(r, "energy_conservation_relative");
  std::printf("[ measured ] evrard-collapse, %ld particles: energy conserved to %.2e (bound 8e-4); kinetic maximum %.3f (1D 0.451), thermal maximum "
              "%.3f at t = %.2f (1D 1.760 at 1.07), potential minimum %.3f at t = %.2f (1D -2.546 at 1.05), initial potential %.4f "
              "(continuum -0.6667), %.1f s\n",
              p.particles, drift, result("peak_kinetic_energy"), result("peak_thermal_energy"), result("peak_thermal_time"),
              result("lowest_potential_energy"), result("lowest_potential_time"), result("initial_potential_energy"), r.wall_time_s);
  EXPECT_LT(drift, 8e-4);
  // Softening and sampling of the 1/r profile: measured 0.0072 above the continuum's -2/3, bound 0.02.
  EXPECT_NEAR(result("initial_potential_energy"), -2.0 / 3.0, 0.02);
  EXPECT_GT(result("peak_thermal_energy"), 1.0);  // the collapse has bounced: most of the infall's energy is heat
}

// The basalt-sphere impact (Nakamura & Fujiwara 1991) at 10 particles across the target's radius:
// it completes, damage spreads through most of the target and the energy is conserved (measured
// 1.3e-4, bound 4e-4). The code misses the experiment: the largest fragment is 0.22 of
// the target here against the experiment's 0.31 (0.206 at the default 15 across, 28 s, which the
// suite cannot afford; 0.266 at 8, 0.285 at 12: SPH's largest fragment depends on the resolution and
// the flaws' seed, docs/impact.md). A regression guard: |fraction - 0.31| below 1.5 times today's
// 0.090.
TEST(ImpactRegression, BasaltSphereLargestFragment) {
  cardiosph::ImpactParameters p;
  p.resolution = 10;
  const auto r = test::run_scene(*cardiosph::make_impact_scene(p), "impact");
  auto result = [&](const char* key) { return r.results.at(key).get<double>(); };
  std::printf("[ measured ] impact, 10 across the target: largest fragment %.3f of the target, error %+.3f against the experiment's "
              "0.31 (not met; guard 0.135), %g fragments (%g of one particle), damaged share %.2f, %g flaws, energy change %.1e "
              "(bound 4e-4), %.1f s\n",
              result("largest_fragment_fraction"), error(r, "largest_fragment_fraction"), result("fragments"),
              result("fragments_of_one_particle"), result("damaged_mass_share"), result("flaws"), result("energy_change_relative"),
              r.wall_time_s);
  EXPECT_LT(std::abs(error(r, "largest_fragment_fraction")), 0.135);
  EXPECT_GT(result("damaged_mass_share"), 0.1);
  EXPECT_LT(std::abs(result("energy_change_relative")), 4e-4);
}

// Extreme cases complete or stop with a diagnostic: a 10 km/s impact (energy kept to 1.5e-3 if it
// completes; measured 5.1e-4), and flaws too strong ever to open (k tiny): the target then takes no
// damage at all.
TEST(ImpactValidation, ExtremeImpactsCompleteOrStopWithADiagnostic) {
  cardiosph::ImpactParameters p;
  p.resolution = 6;
  p.end_time = 15e-6;
  p.speed = 10000;
  try {
    const auto r = test::run_scene(*cardiosph::make_impact_scene(p), "impact_fast");
    std::printf("[ measured ] impact at 10 km/s completed: damaged share %.2f, energy change %.1e (bound 1.5e-3)\n",
                r.results.at("damaged_mass_share").get<double>(), r.results.at("energy_change_relative").get<double>());
    EXPECT_LT(std::abs(r.results.at("energy_change_relative").get<double>()), 1.5e-3);
  } catch (const sph::NumericalFailure& failure) {
    std::printf("[ measured ] impact at 10 km/s stopped: %s\n", failure.what());
    EXPECT_NE(std::string(failure.what()).find("particle"), std::string::npos);
  }
  p.speed = 3200;
  p.weibull_k = 1e-10;  // the weakest flaw of the whole target opens at a strain of about 30
  const auto r = test::run_scene(*cardiosph::make_impact_scene(p), "impact_no_flaws");
  std::printf("[ measured ] impact without flaws at physical strains: damaged share %.3g, largest fragment %.3f\n",
              r.results.at("damaged_mass_share").get<double>(), r.results.at("largest_fragment_fraction").get<double>());
  EXPECT_EQ(r.results.at("damaged_mass_share").get<double>(), 0);
}

}  // namespace

// The 2D Sedov-Taylor blast (E = 1 per unit length, rho0 = 1, gamma = 1.4) at 60 and 100 particles
// per unit length, t = 0.1, against R(t) = 1.0040 (E t^2 / rho0)^(1/4). The error of the shock radius
// changes sign with the resolution (-0.79 %, -0.04 % and +0.82 % at 60, 100 and 200; -4.1 % at 40,
// where the shell is a few particles wide), so the default's -0.04 % is a zero crossing, not its
// accuracy: the bound, 2.5 %, is on the largest |error| over the resolutions run, three times that
// envelope over 60 to 200 (0.82 %). The density L1 falls with resolution (it is dominated by the shell, a few h wide in
// SPH where the exact one is a jump to 6 rho0); the energy is kept to 7e-4 (measured -2.4e-4).
namespace {

TEST(ImpactValidation, SedovBlastShockFollowsTheSelfSimilarSolution) {
  cardiosph::SedovBlastParameters p;
  p.resolution = 60;
  const auto coarse = test::run_scene(*cardiosph::make_sedov_blast_scene(p), "sedov_coarse");
  p.resolution = 100;
  const auto fine = test::run_scene(*cardiosph::make_sedov_blast_scene(p), "sedov");
  double envelope = 0;
  for (const auto* r : {&coarse, &fine}) {
    envelope = std::max(envelope, std::abs(error(*r, "shock_radius_relative")));
    std::printf("[ measured ] sedov-blast at %s per unit length: shock radius %.4f (exact %.4f, %+.2f %%), density L1 %.3f, energy change "
                "%.1e (bound 7e-4), %.1f s\n",
                r == &coarse ? "60" : "100", r->results.at("shock_radius").get<double>(), r->results.at("exact_shock_radius").get<double>(),
                100 * error(*r, "shock_radius_relative"), error(*r, "density_l1"), r->results.at("energy_change_relative").get<double>(),
                r->wall_time_s);
  }
  std::printf("[ measured ] sedov-blast: largest |shock radius error| over 60 and 100 per unit length %.2f %% (bound 2.5 %%)\n",
              100 * envelope);
  EXPECT_LT(envelope, 0.025);
  EXPECT_LT(error(fine, "density_l1"), error(coarse, "density_l1"));
  for (const auto* r : {&coarse, &fine}) EXPECT_LT(std::abs(r->results.at("energy_change_relative").get<double>()), 7e-4);
}

}  // namespace
