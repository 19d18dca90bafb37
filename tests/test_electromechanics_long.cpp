// Land et al. 2015 problem 3 at the resolution of its bound (label: long; not in the default suite,
// about two minutes on 2 cores): `ctest -L long`. Problem 2 at the default resolution stays in the
// validation suite.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "apps/scenes/electromechanics/em_scenes.hpp"
#include "libsph/io/parameters.hpp"
#include "run_scene_for_test.hpp"

namespace {

sph::RunReport run(std::unique_ptr<cardiosph::Scene> scene, const std::vector<std::string>& assignments,
                   const std::string& name) {
  sph::Parameters parameters;
  test::set_parameters(*scene, parameters, assignments);
  return test::run_scene(*scene, name);
}

double at(const sph::RunReport& r, const std::string& key) { return r.results.at(key).get<double>(); }

// Problem 3 (inflation to 15 kPa and contraction at T_a = 60 kPa) at dp = 0.75 mm with the benchmark's
// prolate-spheroidal fibre field: both apex positions within 0.5 mm of the refined published solution
// (endo -12.35, epi -15.45 mm). Measured -12.01 and -14.97 mm (+0.34, +0.48); at dp = 1 mm +0.81 and
// +0.49; with the LDRB fibres, whose direction near the apex points through the wall, +1.6 and +2.9.
TEST(ElectromechanicsLong, LandProblemThreeApexWithinHalfAMillimetre) {
  const auto r = run(cardiosph::make_land_lv_scene(), {"problem=3", "dp=0.75"}, "land_lv_p3");
  const double endo = at(r, "apex_z_endo_mm"), epi = at(r, "apex_z_epi_mm");
  std::cout << "land-lv problem 3, dp 0.75: apex z endo " << endo << " (published -12.347), epi " << epi
            << " (-15.452); bound 0.5 mm; J in [" << at(r, "min_jacobian") << ", " << at(r, "max_jacobian") << "], "
            << r.wall_time_s << " s\n";
  EXPECT_LT(std::abs(endo - -12.347), 0.5);
  EXPECT_LT(std::abs(epi - -15.452), 0.5);
}

}  // namespace
