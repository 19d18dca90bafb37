// Validation and stability of the weakly-compressible fluid scenes (label: validation), at coarse
// resolution.
// Every bound on an error against a reference lies within about three times the error measured
// now (docs/fluid.md has the convergence tables), and each test prints the measured value beside
// its bound.
#include <gtest/gtest.h>

#include <cstdio>

#include "apps/scenes/fluid/fluid_scenes.hpp"
#include "run_scene_for_test.hpp"

namespace {

using test::run_scene;

double result(const sph::RunReport& r, const std::string& key) { return r.results.at(key).get<double>(); }
double error(const sph::RunReport& r, const std::string& key) { return r.errors.at(key).get<double>(); }

// The SPHinXsys dam break at dp = 0.05 (half its resolution) to t = 20: the violent impact on the
// far wall and the plunging jet without failure; the surge front within 0.1 column widths RMS of
// Martin & Moyce and of Koshizuka & Oka (measured 0.075 and 0.091: the bound is the scatter between
// the two experiments themselves, 0.05-0.1 at equal T, docs/fluid.md); the total energy never above
// its initial value by more than 6e-6 (one-sided: the scheme only dissipates; measured 1.9e-6, the
// acoustic transient of the release); the wall probe sees the impact before t = 3 (sanity).
TEST(FluidValidation, DamBreakSurgeFrontAndStabilityToTwenty) {
  cardiosph::DamBreakParameters p;
  p.resolution = 20;
  const auto r = run_scene(*cardiosph::make_dambreak_scene(p), "dambreak");
  std::printf("dambreak dp=0.05 t=20: surge front RMS %.4f (Martin & Moyce), %.4f (Koshizuka & Oka), bound 0.1; "
              "energy rise %.2e (bound 6e-6); pressure first rise at t = %.3f; %g acoustic steps, %.1f s\n",
              error(r, "surge_front_rms"), error(r, "surge_front_rms_koshizuka"), result(r, "max_energy_rise_relative"),
              result(r, "pressure_first_rise_time"), result(r, "acoustic_steps"), r.wall_time_s);
  EXPECT_EQ(r.status, "completed");
  EXPECT_LT(error(r, "surge_front_rms"), 0.1);
  EXPECT_LT(error(r, "surge_front_rms_koshizuka"), 0.1);
  EXPECT_LT(result(r, "max_energy_rise_relative"), 6e-6);
  EXPECT_LT(result(r, "pressure_first_rise_time"), 3.0);
  EXPECT_LT(result(r, "max_mach"), 0.3);
}

// The 3D column at dp = 0.1 to t = 2.5 (the front reaches the far wall): surge front within 0.15
// column widths RMS of Martin & Moyce (measured 0.088).
TEST(FluidValidation, DamBreak3dSurgeFront) {
  auto p = cardiosph::dambreak_3d_defaults();
  p.resolution = 10;
  p.end_time = 2.5;
  const auto r = run_scene(*cardiosph::make_dambreak_3d_scene(p), "dambreak3d");
  std::printf("dambreak-3d dp=0.1 t=2.5: surge front RMS %.4f (bound 0.15), %.1f s\n", error(r, "surge_front_rms"),
              r.wall_time_s);
  EXPECT_LT(error(r, "surge_front_rms"), 0.15);
}

// Water at rest for t = 20 at the default H/dp = 20 and at 10: floor pressure within 5 % of rho g H
// at 20 (measured +1.9 %) and 9 % at 10 (measured +4.5 %; +3.8 % at 40, docs/fluid.md: the error is
// not monotone, and the default is its smallest), spurious speed below 0.25 sqrt(g H) (measured 0.14
// and 0.15), free-surface drift below one spacing (measured 0.38 at both).
TEST(FluidValidation, HydrostaticTankStaysAtRest) {
  for (const long resolution : {20L, 10L}) {
    cardiosph::HydrostaticTankParameters p;
    p.resolution = resolution;
    const auto r = run_scene(*cardiosph::make_hydrostatic_tank_scene(p), "hydrostatic_" + std::to_string(resolution));
    const double bound = resolution == 20 ? 0.05 : 0.09;
    std::printf("hydrostatic-tank H/dp=%ld t=20: floor pressure error %+.4f (bound %.2f), spurious speed %.4f sqrt(gH) "
                "(bound 0.25), surface drift %.3f dp (bound 1)\n",
                resolution, result(r, "bottom_pressure") / result(r, "reference_bottom_pressure") - 1, bound,
                error(r, "spurious_speed_relative"), result(r, "surface_drift_over_spacing"));
    EXPECT_LT(error(r, "bottom_pressure_relative"), bound) << resolution;
    EXPECT_LT(error(r, "spurious_speed_relative"), 0.25) << resolution;
    EXPECT_LT(result(r, "surface_drift_over_spacing"), 1.0) << resolution;
  }
}

// Plane Poiseuille flow at the default H/dp = 20 and at 10 across: profile within 1 % (L2) of the
// parabola at 20 (measured 0.38 %) and within 6 % at 10 (measured 2.4 %; its mean speed never comes
// within 1 % of the steady one, so no time to steady state is printed). The error is not monotone in
// resolution (0.96 % at 40 across, docs/fluid.md), so the default is not the whole story: the
// coarser run checks that its error is the size the table says.
TEST(FluidValidation, PoiseuilleProfileAtTwoResolutions) {
  for (const long resolution : {20L, 10L}) {
    cardiosph::PoiseuilleParameters p;
    p.resolution = resolution;
    const auto r = run_scene(*cardiosph::make_poiseuille_scene(p), "poiseuille_" + std::to_string(resolution));
    const double bound = resolution == 20 ? 0.01 : 0.06;
    std::printf("poiseuille H/dp=%ld: profile L2 error %.4f (bound %.2f), steady after t = %.2f, %.2f s\n", resolution,
                error(r, "profile_l2_relative"), bound, result(r, "time_to_steady_state"), r.wall_time_s);
    EXPECT_LT(error(r, "profile_l2_relative"), bound) << resolution << " across";
  }
}

// Lid-driven cavity at Re 100, t = 15, at 40 and 25 particles across: centre lines within 0.045
// lid velocities RMS of Ghia et al. 1982 at both (measured 0.016 and 0.015): not only the
// resolution the test has always run at.
TEST(FluidValidation, LidDrivenCavityCentreLinesAtTwoResolutions) {
  for (const long resolution : {40L, 25L}) {
    cardiosph::LidDrivenCavityParameters p;
    p.resolution = resolution;
    p.end_time = 15;
    const auto r = run_scene(*cardiosph::make_lid_driven_cavity_scene(p), "cavity_" + std::to_string(resolution));
    const double bound = 0.045;
    std::printf("lid-driven-cavity Re100 n=%ld t=15: centre-line RMS %.4f (bound %.3f), %.1f s\n", resolution,
                error(r, "centreline_rms"), bound, r.wall_time_s);
    EXPECT_LT(error(r, "centreline_rms"), bound) << resolution << " across";
  }
}

// Taylor-Green vortex at Re 100 at the scene's default (50 particles across, t = 1, the
// kernel-corrected pressure force): the kinetic energy's decay rate within 5 % of 16 pi^2 / Re
// (measured +3.1 %; +32 % with the plain pressure force, docs/fluid.md). The velocity field's L2
// error against the exact solution (measured 0.079; 0.25 with the plain force) has no published
// bound: bounded at 0.12, 1.5 times today's (round-off-level changes of the arithmetic move it by
// about 7 %: the particle pattern after the lattice breaks up near t = 0.1 is chaotic).
TEST(FluidValidation, TaylorGreenDecayRateAtTheDefault) {
  cardiosph::TaylorGreenParameters p;
  const auto r = run_scene(*cardiosph::make_taylor_green_scene(p), "taylor_green");
  const double rate = result(r, "decay_rate"), exact = result(r, "reference_decay_rate");
  std::printf("taylor-green Re100 n=50 t=1: decay rate %.4f (exact %.4f), error %+.4f (bound 0.05), "
              "velocity L2 %.4f (bound 0.12), %.1f s\n",
              rate, exact, rate / exact - 1, error(r, "velocity_l2_relative"), r.wall_time_s);
  EXPECT_GT(rate, 0);
  EXPECT_LT(error(r, "decay_rate_relative"), 0.05);
  EXPECT_LT(error(r, "velocity_l2_relative"), 0.12);
}

}  // namespace
