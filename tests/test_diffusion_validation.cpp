// Validation of the diffusion scenes against their analytic solutions (label: validation): relative
// L2 error at the default resolution below 0.65 % (isotropic band, measured 0.22 %) and 0.7 %
// (anisotropic Gaussian, measured 0.24 %), about three times the measured error, and the error falls
// at second order when the resolution doubles (observed order 2.09 and 2.01; bound: above 1.7).
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
  const double order = std::log(coarse / fine) / std::log(2.0);
  std::printf("diffusion: l2_relative %.4e at resolution %ld (bound 6.5e-3), %.4e at %ld; observed order %.2f (bound > 1.7)\n",
              fine, p.resolution, coarse, coarse_p.resolution, order);
  EXPECT_LT(fine, 6.5e-3);
  EXPECT_GT(order, 1.7);
}

TEST(DiffusionValidation, AnisotropicGaussian) {
  cardiosph::DiffusionGaussianParameters p;  // defaults: resolution 100, ratio 10 at 30 degrees
  const double fine = run_scene(*cardiosph::make_diffusion_gaussian_scene(p), "gauss");
  cardiosph::DiffusionGaussianParameters coarse_p = p;
  coarse_p.resolution = p.resolution / 2;
  const double coarse = run_scene(*cardiosph::make_diffusion_gaussian_scene(coarse_p), "gauss_coarse");
  const double order = std::log(coarse / fine) / std::log(2.0);
  std::printf("diffusion-aniso: l2_relative %.4e at resolution %ld (bound 7e-3), %.4e at %ld; observed order %.2f (bound > 1.7)\n",
              fine, p.resolution, coarse, coarse_p.resolution, order);
  EXPECT_LT(fine, 7e-3);
  EXPECT_GT(order, 1.7);
}

}  // namespace
