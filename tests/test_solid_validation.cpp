// Validation and stability of the TLSPH solid (label: validation). Bounds are stated in each test
// and the measured values printed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "apps/run_scene.hpp"
#include "apps/scenes/solid/solid_scenes.hpp"
#include "geometry/lattice.hpp"
#include "libsph/core/numerical_failure.hpp"
#include "run_scene_for_test.hpp"

namespace {

namespace fs = std::filesystem;
using sph::Real;
using Vec3 = sph::Vec<3>;

using test::run_scene;

double result(const sph::RunReport& r, const std::string& key) { return r.results.at(key).get<double>(); }

// Gray et al. 2001 plate at H/dp = 10 with the scene's defaults (quadratic reconstruction, Gauss
// quadrature in the cells, energy-based hourglass control, clamp by reflection), over three periods
// (the default runs five; three measure the same period, 0.2542 s, and energy drift, in 60 % of the
// time). Period within 0.5 % of the thin-plate value (measured +0.08 %). The bound is the accuracy of
// the reference, not of the code: the thin-plate period leaves out shear and rotary inertia (about
// 0.6 % for L / H = 10) and the stiffening at this amplitude (about -0.35 %), and the Gauss series
// converges to 0.10 % above it (docs/solid.md); 0.07 % is agreement within that, not a measure of
// the error. Total energy (no damping) within 5e-6 (measured 1.4e-6 over three periods, 1.5e-6 over
// five).
TEST(SolidValidation, OscillatingBeamPeriodAndEnergy) {
  cardiosph::OscillatingBeamParameters p;  // H/dp = 10
  p.end_time = 0.8;
  const auto r = run_scene(*cardiosph::make_oscillating_beam_scene(p), "beam");
  const double error = r.errors.at("period_relative").get<double>(), drift = result(r, "energy_drift_relative");
  std::printf("oscillating-beam H/dp=10, t = 0.8: period %.5f s (reference %.4f), error %+.3f%% (bound 0.5%%), amplitude %.4f m, "
              "energy drift %.2e (bound 5e-6), %g half periods, %.1f s\n",
              result(r, "period_s"), result(r, "reference_period_s"), 100 * (result(r, "period_s") / result(r, "reference_period_s") - 1),
              result(r, "amplitude_m"), drift, result(r, "half_periods_measured"), r.wall_time_s);
  EXPECT_LT(error, 0.005);
  EXPECT_LT(drift, 5e-6);
  EXPECT_GE(result(r, "half_periods_measured"), 5);
}

// Holzapfel-Ogden cube in four homogeneous deformations at 12 across: interior Cauchy stress within
// 1.2e-3 of the closed form (measured 3.9e-4, the fs shear; the others 5e-5 to 7e-5).
TEST(SolidValidation, HomogeneousDeformationStress) {
  cardiosph::HomogeneousDeformationParameters p;
  p.resolution = 12;
  const auto r = run_scene(*cardiosph::make_homogeneous_deformation_scene(p), "homogeneous");
  const double error = r.errors.at("stress_relative").get<double>();
  std::printf("homogeneous-deformation (resolution 12): max interior stress error %.2e (bound 1.2e-3): fibre %.1e, "
              "sheet %.1e, shear fs %.1e, shear sf %.1e\n", error, r.errors.at("stress_relative_fibre_stretch").get<double>(),
              r.errors.at("stress_relative_sheet_stretch").get<double>(), r.errors.at("stress_relative_shear_fs").get<double>(),
              r.errors.at("stress_relative_shear_sf").get<double>());
  EXPECT_LT(error, 1.2e-3);
}

// The passive cantilever runs to t = 3 without instability at a coarse resolution.
TEST(SolidStability, CantileverRunsToTheEnd) {
  cardiosph::CantileverParameters p;
  p.resolution = 4;
  const auto r = run_scene(*cardiosph::make_cantilever_scene(p), "cantilever");
  std::printf("cantilever (resolution 4, t = 3): J in [%.4f, %.4f], max tip deflection %.3f m, energy drift %.2e, %zu steps\n",
              result(r, "min_jacobian"), result(r, "max_jacobian"), result(r, "tip_max_deflection_m"),
              result(r, "energy_drift_relative"), r.steps);
  EXPECT_EQ(r.status, "completed");
  EXPECT_GT(result(r, "min_jacobian"), 0.5);
  EXPECT_LT(result(r, "max_jacobian"), 1.5);
  EXPECT_GT(result(r, "tip_max_deflection_m"), 0.5);  // the kick bends it visibly
}

// nu = 0.4999 (K / mu about 5000): the cantilever runs and J stays within 5e-3 of 1, the
// incompressible limit (measured [0.9985, 1.0015]).
TEST(SolidStability, NearlyIncompressibleCantilever) {
  cardiosph::CantileverParameters p;
  p.resolution = 4;
  p.poisson_ratio = 0.4999;
  p.end_time = 0.2;
  const auto r = run_scene(*cardiosph::make_cantilever_scene(p), "incompressible");
  std::printf("cantilever nu = 0.4999 (resolution 4, t = 0.2): J in [%.5f, %.5f] (bound [0.995, 1.005]), %zu steps\n",
              result(r, "min_jacobian"), result(r, "max_jacobian"), r.steps);
  EXPECT_EQ(r.status, "completed");
  EXPECT_GT(result(r, "min_jacobian"), 0.995);
  EXPECT_LT(result(r, "max_jacobian"), 1.005);
}

// A column twisted past 90 degrees: with the hourglass penalty the zero-energy-mode measure stays
// smaller than without it.
TEST(SolidStability, TwistingColumnHourglassControl) {
  cardiosph::TwistingColumnParameters p;
  p.resolution = 4;
  const auto with = run_scene(*cardiosph::make_twisting_column_scene(p), "twist_on");
  p.numerics.solid.hourglass_coefficient = 0;
  const auto without = run_scene(*cardiosph::make_twisting_column_scene(p), "twist_off");
  std::printf("twisting-column (resolution 4): max twist %.0f deg; hourglass measure max %.3e with alpha = 0.1, %.3e "
              "without; J min %.3f / %.3f\n", result(with, "max_twist_deg"), result(with, "hourglass_measure_max"),
              result(without, "hourglass_measure_max"), result(with, "min_jacobian"), result(without, "min_jacobian"));
  EXPECT_GT(result(with, "max_twist_deg"), 90);
  EXPECT_LT(result(with, "hourglass_measure_max"), result(without, "hourglass_measure_max"));
  EXPECT_GT(result(with, "min_jacobian"), 0);
}

// Holzapfel-Ogden column (fibres along the axis) compressed to half its length by its top face,
// the bottom face sliding: every particle keeps J > 0.
TEST(SolidStability, HolzapfelOgdenCompressionToHalfLength) {
  const Real dp = Real(0.125);
  auto body = geometry::lattice_box<3>("column", Vec3::Zero(), Vec3(1, 1, 2), dp);
  const auto relation = sph::build_inner_relation<3>(body.position, sph::make_kernel<3>("wendland_c4"), Real(1.3) * dp);
  sph::ElasticSolid<3>::Settings settings;
  settings.material = sph::holzapfel_ogden_2009_kpa<3>(50);
  settings.fibre = Vec3::UnitZ();
  settings.sheet = Vec3::UnitX();
  settings.numerics.hourglass_coefficient = Real(0.1);
  settings.damping_rate = 2;
  sph::ElasticSolid<3> solid(body, relation, settings);
  const Real duration = 10;  // ms, slow compared with the acoustic time (about 0.2 ms)
  std::vector<sph::Index> bottom;
  for (std::size_t i = 0; i < body.n_particles(); ++i)
    if (body.position[i][2] < dp) bottom.push_back(static_cast<sph::Index>(i));
  solid.slide(bottom, 2);
  solid.prescribe_motion(
      [&] {
        std::vector<sph::Index> top;
        for (std::size_t i = 0; i < body.n_particles(); ++i)
          if (body.position[i][2] > 2 - dp) top.push_back(static_cast<sph::Index>(i));
        return top;
      }(),
      [&](const Vec3& X, Real t) { return Vec3(X[0], X[1], X[2] * (1 - Real(0.5) * std::min(t / duration, Real(1)))); },
      [&](const Vec3& X, Real t) { return Vec3(0, 0, t < duration ? -Real(0.5) * X[2] / duration : 0); });
  Real t = 0;
  std::size_t steps = 0;
  EXPECT_NO_THROW({
    while (t < duration) {
      const Real dt = std::min(solid.stable_time_step(), duration - t);
      solid.advance(t, dt);
      t += dt;
      ++steps;
    }
  });
  const auto e = solid.energies();
  double height = 0;
  for (std::size_t i = 0; i < body.n_particles(); ++i) height = std::max(height, double(body.position[i][2]));
  std::printf("Holzapfel-Ogden compression to half length: top at z = %.3f (from 2), J in [%.3f, %.3f] (bound J > 0), %zu steps\n",
              height, e.min_jacobian, e.max_jacobian, steps);
  EXPECT_GT(e.min_jacobian, 0);
  EXPECT_LT(height, 1.05);
}

// A time step far above the acoustic limit: the run stops with a diagnostic naming the body,
// particle, position and time, writes the last good state, reports status "failed" and exits 1.
TEST(SolidStability, TooLargeTimeStepIsDetected) {
  const test::TemporaryFolder scratch("solid_blowup");
  const fs::path out = scratch / "out";
  cardiosph::CommonOptions options;
  options.output = out;
  options.quiet = true;
  options.resolution = "4";
  options.end_time = "0.5";
  options.assignments = {"fixed_time_step=2e-3"};  // about 4 times the acoustic step
  const auto result = cardiosph::run_scene("cantilever", options);
  std::printf("cantilever with fixed_time_step = 2e-3 s: exit %d, message: %s\n", result.exit_code, result.report.message.c_str());
  EXPECT_EQ(result.exit_code, cardiosph::exit_run_failed);
  EXPECT_EQ(result.report.status, "failed");
  for (const char* part : {"body 'beam'", "particle", "time", "at ("})
    EXPECT_NE(result.report.message.find(part), std::string::npos) << part;
  EXPECT_TRUE(fs::exists(out / "report.json"));
  EXPECT_TRUE(fs::exists(out / "beam.pvd"));
  EXPECT_TRUE(fs::exists(out / "beam_00001.vtu"));  // the last good state after the initial one
}

}  // namespace

namespace {

// Land et al. 2015 problem 1 at 3 and 4 particles across the thickness, with the scene's defaults
// (quadratic reconstruction, Gauss quadrature in the cells, clamp by reflection, quasi-static
// relaxation stopped at a residual of 1e-4). Checked: the default (4 across) inside the published
// spread 4.15-4.20 mm (measured 4.1697 mm; 4.1502 at 3 across, 4.1699 at 6; the bound is the
// spread of the published codes, wider than three times the distance from its middle), closer to its
// middle than 3 across, both runs converged, and J within 3e-3 of 1 (the nearly incompressible law,
// K / C = 100; measured [0.9991, 1.0009]). With the nodal quadrature: 4.425, 4.300, 4.254 mm at
// 4, 6, 8 across (the long test LandBeamNodalSeriesConverges); with the fixed clamp as well 4.580,
// 4.403, 4.332; with the corrected gradient 5.41, 4.73, 4.50.
TEST(SolidValidation, LandBeamConvergesToThePublishedTip) {
  cardiosph::LandBeamParameters p;
  p.resolution = 3;
  const auto coarse = run_scene(*cardiosph::make_land_beam_scene(p), "land3");
  p.resolution = 4;
  const auto fine = run_scene(*cardiosph::make_land_beam_scene(p), "land4");
  const double z3 = result(coarse, "tip_z_mm"), z4 = result(fine, "tip_z_mm");
  const double middle = 4.175;
  std::printf("land-beam: tip z %.4f mm (resolution 3), %.4f mm (4, the default; bound: inside 4.15-4.20); J in [%.4f, %.4f] (bound 1 +- 3e-3); "
              "residual %.1e, %zu steps, %.1f s\n", z3, z4, result(fine, "min_jacobian"), result(fine, "max_jacobian"),
              result(fine, "residual_relative"), fine.steps, fine.wall_time_s);
  EXPECT_LT(std::abs(z4 - middle), std::abs(z3 - middle));
  EXPECT_GE(z4, 4.15);
  EXPECT_LE(z4, 4.20);
  EXPECT_TRUE(coarse.results.at("converged").get<bool>());
  EXPECT_TRUE(fine.results.at("converged").get<bool>());
  EXPECT_LE(result(fine, "residual_relative"), 1e-4);
  EXPECT_GT(result(fine, "min_jacobian"), 0.997);
  EXPECT_LT(result(fine, "max_jacobian"), 1.003);
}

// A quasi-static solve that cannot converge in the pseudo-time allowed stops as failed, naming the
// residual and the steps, instead of reporting the unrelaxed state as the solution.
TEST(SolidStability, QuasiStaticNonConvergenceIsReported) {
  const test::TemporaryFolder scratch("quasi_static_failure");
  cardiosph::CommonOptions options;
  options.output = scratch / "out";
  options.quiet = true;
  options.resolution = "4";
  options.end_time = "20";  // a tenth of what the relaxation needs
  const auto result = cardiosph::run_scene("land-beam", options);
  std::printf("land-beam to 20 ms: exit %d, message: %s\n", result.exit_code, result.report.message.c_str());
  EXPECT_EQ(result.exit_code, cardiosph::exit_run_failed);
  EXPECT_EQ(result.report.status, "failed");
  for (const char* part : {"did not converge", "residual", "steps", "beam"})
    EXPECT_NE(result.report.message.find(part), std::string::npos) << part;
}

}  // namespace
