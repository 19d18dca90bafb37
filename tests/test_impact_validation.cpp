// The impact family against references: Sod's shock tube against the exact Riemann solution, at the
// default resolution (bound: errors.density_l1 below 5 %, the bound) and at half of it, for
// the order of convergence of the L1 density error.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "apps/scenes/impact/impact_scenes.hpp"
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
  std::printf("[ measured ] sod-shock-tube: density L1 %.4f at %ld per unit length (%.1f s), %.4f at %ld (%.1f s): order %.2f; "
              "velocity L1 %.4f, pressure L1 %.4f; energy change %.2e\n",
              rho_coarse, fine / 2, coarse.wall_time_s, rho, fine, r.wall_time_s, order, error(r, "velocity_l1"),
              error(r, "pressure_l1"), r.results.at("energy_change_relative").get<double>());
  EXPECT_LT(rho, 0.05);  // the bound at the default resolution
  EXPECT_LT(rho, rho_coarse);  // it converges
  // Total energy: the scheme conserves it to the time-integration error (bound 1e-3).
  EXPECT_LT(std::abs(r.results.at("energy_change_relative").get<double>()), 1e-3);
}

}  // namespace
