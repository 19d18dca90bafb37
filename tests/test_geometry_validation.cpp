// Geometry stage on real meshes: the Land et al. 2015 LV at the default spacing (volume against the
// closed form, fibre angle against the prescribed linear law) and the third-party biventricular
// heart of ../shared/meshes (checks, geometric labels, fibres).

#include <gtest/gtest.h>

#include <filesystem>

#include <iostream>

#include "apps/scenes/geometry/geometry_scenes.hpp"
#include "libsph/io/parameters.hpp"
#include "run_scene_for_test.hpp"

namespace {

sph::RunReport run_particles(const std::vector<std::string>& assignments, const std::string& name) {
  auto scene = cardiosph::make_particles_scene();
  sph::Parameters parameters;
  test::set_parameters(*scene, parameters, assignments);
  return test::run_scene(*scene, name);
}

TEST(GeometryValidation, LvEllipsoidVolumeAndFibreAngleAtTheDefaultSpacing) {
  const auto report = run_particles({}, "lv_ellipsoid");
  const auto& r = report.results;
  const double volume_error = r["volume_relative_error"];
  const double mad = r["fibre_angle_mad_deg"];
  std::cout << "[ measured ] LV ellipsoid dp = 0.5 mm: " << r["particles"] << " particles, volume error " << volume_error
            << " (bound 0.01), volume spread " << r["density_spread"] << " (bound 0.011), fibre angle MAD " << mad
            << " deg (bound 3) over " << r["fibre_check_particles"] << " particles, largest " << r["fibre_angle_max_deg"]
            << " deg\n";
  // Against the closed-form wall volume (the mesh itself is 0.02 % short of it): measured -0.58 %,
  // bound 1 %. Fibre angle against the prescribed linear law: measured 1.91 deg, bound 3 deg.
  // Spread of the particle volumes after the relaxation: measured 0.0038, bound 0.011.
  EXPECT_LT(std::abs(volume_error), 0.01);
  EXPECT_LT(mad, 3.0);
  EXPECT_LT(double(r["density_spread"]), 0.011);
}

TEST(GeometryValidation, SharedBiventricularHeartYieldsLabelledParticlesAndFibres) {
  // The project's own equivalent: LvEllipsoidVolumeAndFibreAngleAtTheDefaultSpacing (shipped mesh).
  const std::string mesh = std::string(CARDIOSPH_SHARED_MESHES) + "/biventricular_heart.stl";
  if (!std::filesystem::exists(mesh)) GTEST_SKIP() << "third-party mesh not found: " << mesh;
  const auto report = run_particles({"mesh=" + mesh, "dp=1.5", "relaxation_steps=30"}, "shared_heart");
  const auto& r = report.results;
  std::cout << "[ measured ] shared heart dp = 1.5 mm, 30 relaxation steps: " << r["particles"] << " particles, volume error "
            << r["volume_relative_error"] << " (bound 0.008), labels " << r["labelled"] << " by " << r["label_method"] << '\n';
  EXPECT_EQ(r["label_method"], "geometric rule");
  for (const char* label : {"epicardium", "lv_endocardium", "rv_endocardium", "base"})
    EXPECT_GT(int(r["labelled"][label]), 0) << label;
  // Against the volume enclosed by the surface mesh: measured -0.25 %, bound 0.8 %.
  EXPECT_LT(std::abs(double(r["volume_relative_error"])), 0.008);
  EXPECT_FALSE(r.contains("fibre_angle_mad_deg"));  // no analytic reference for this mesh
}

}  // namespace
