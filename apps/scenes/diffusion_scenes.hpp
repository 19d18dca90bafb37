#pragma once
// Verification scenes of the diffusion operator (libsph/diffusion), 2D, SI units.
//
// `diffusion`: a band a < x < b of concentration 1 across a box, isotropic D; the no-flux walls at
// x = 0 and x = L are not reached by the end time, so the exact solution is the superposition of
// error functions C = 1/2 [erf((x - a) / (2 sqrt(D t))) - erf((x - b) / (2 sqrt(D t)))].
// `diffusion-aniso`: a Gaussian of width sigma0 at the centre of a square, D with ratio
// D_l / D_t = 10 along a direction at 30 degrees; exact solution the Gaussian with covariance
// Sigma(t) = sigma0^2 I + 2 D t, C = sigma0^2 / sqrt(det Sigma) exp(-1/2 x^T Sigma^-1 x).
// Both report errors.l2_relative (volume-weighted L2 norm of C - C_exact over that of C_exact) and
// errors.max_abs at the end time.

#include <memory>
#include <string>

#include "apps/scenes/discretisation.hpp"
#include "apps/scenes/scene.hpp"
#include "libsph/diffusion/diffusion_system.hpp"

namespace cardiosph {

/// Numerical settings shared by the diffusion scenes: the discretisation, and the diffusion's own
/// choices bound directly (libsph/diffusion/diffusion_system.hpp).
struct DiffusionNumerics {
  Discretisation discretisation;  ///< output_interval [s]
  sph::DiffusionNumerics diffusion;
};

struct DiffusionBandParameters {
  long resolution = 100;        ///< particles across the box length
  double end_time = 10;         ///< [s]
  double box_length = 1;        ///< [m] along x
  double box_height = 0.2;      ///< [m] along y
  double band_start = 0.4;      ///< [m] a
  double band_end = 0.6;        ///< [m] b
  double diffusivity = 1e-4;    ///< [m^2/s]
  DiffusionNumerics numerics;
};

struct DiffusionGaussianParameters {
  long resolution = 100;                   ///< particles across the box
  double end_time = 4;                     ///< [s]
  double box_size = 1;                     ///< [m]
  double initial_width = 0.05;             ///< [m] sigma0
  double diffusivity_longitudinal = 5e-4;  ///< [m^2/s] along the direction
  double diffusivity_transverse = 5e-5;    ///< [m^2/s] across it
  double direction_angle_deg = 30;         ///< [deg] from the x axis
  DiffusionNumerics numerics;
};

std::unique_ptr<Scene> make_diffusion_band_scene(DiffusionBandParameters parameters = {});
std::unique_ptr<Scene> make_diffusion_gaussian_scene(DiffusionGaussianParameters parameters = {});

}  // namespace cardiosph
