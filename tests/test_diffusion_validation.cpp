// Validation of the diffusion scenes against their analytic solutions (label: validation):
// relative L2 error below 1% (isotropic band) and 3% (anisotropic Gaussian) at the default
// resolution, and the error falls when the resolution doubles (observed order printed).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "apps/scenes/diffusion_scenes.hpp"
#include "run_scene_for_test.hpp"

namespace {


double run_scene(cardiosph::Scene& scene, const std::string& name) {
  return test::run_scene(scene, name).errors["l2_relative"].get<double>();
}

TEST(DiffusionValidation, IsotropicBandAgainstErrorFunctions) {
  cardiosph::DiffusionBandParameters p;  // defaults: resolution 100
  const double fine = run_scene(*cardiosph::make_diffusion_band_scene(p), "band");
  cardiosph::DiffusionBandParameters coarse_p = p;
  coarse_p.resolution = p.resolution / 2;
  const double coarse = run_scene(*cardiosph::make_diffusion_band_scene(coarse_p), "band_coarse");
  std::printf("diffusion: l2_relative %.4e at resolution %ld (bound 1e-2), %.4e at %ld; observed order %.2f\n", fine,
              p.resolution, coarse, coarse_p.resolution, std::log(coarse / fine) / std::log(2.0));
  EXPECT_LT(fine, 0.01);
  EXPECT_LT(fine, coarse);
}

TEST(DiffusionValidation, AnisotropicGaussian) {
  cardiosph::DiffusionGaussianParameters p;  // defaults: resolution 100, ratio 10 at 30 degrees
  const double fine = run_scene(*cardiosph::make_diffusion_gaussian_scene(p), "gauss");
  cardiosph::DiffusionGaussianParameters coarse_p = p;
  coarse_p.resolution = p.resolution / 2;
  const double coarse = run_scene(*cardiosph::make_diffusion_gaussian_scene(coarse_p), "gauss_coarse");
  std::printf("diffusion-aniso: l2_relative %.4e at resolution %ld (bound 3e-2), %.4e at %ld; observed order %.2f\n",
              fine, p.resolution, coarse, coarse_p.resolution, std::log(coarse / fine) / std::log(2.0));
  EXPECT_LT(fine, 0.03);
  EXPECT_LT(fine, coarse);
}

}  // namespace
