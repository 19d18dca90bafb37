#pragma once
// Scenes of the impact family (libsph/impact, docs/impact.md):
//   sod-shock-tube (2D slab, periodic across): Sod's shock tube against the exact Riemann solution;
//   L1 errors of density, velocity and pressure;
//   rubber-rings: Gray, Monaghan & Swift's colliding elastic rings, with or without artificial stress.

#include <memory>

#include "apps/scenes/scene.hpp"

namespace cardiosph {

struct SodShockTubeParameters {
  long resolution = 200;       ///< particles per unit length (the same spacing on both sides)
  double end_time = 0.2;
  double tube_half_length = 1;  ///< the tube is [-L, L]; the error is measured on [-1/2, 1/2]
  long rows = 8;               ///< particle rows across the periodic width (at least 4 h / dx)
  double gamma = 1.4;
  double left_density = 1, left_pressure = 1, right_density = 0.125, right_pressure = 0.1;
  /// h / dx. The impact codes' 1.2 is for isotropic spacing; in the slab the expanded gas (density
  /// 0.426) has its layers 2.35 dx apart along x, beyond the support of h = 1.2 dx (docs/impact.md).
  double smoothing_length_ratio = 2.0;
  double alpha = 1, beta = 2, epsilon = 0.1;
  double output_interval = 0;
};

std::unique_ptr<Scene> make_sod_shock_tube_scene(SodShockTubeParameters parameters = {});

struct RubberRingsParameters {
  long resolution = 10;  ///< particles across the wall
  double inner_radius = 0.03, outer_radius = 0.04, gap = 0.002;
  double density = 1, youngs_modulus = 1e7, poisson_ratio = 0.3975;
  double speed = 0.059;  ///< each ring's speed, in units of c0 = sqrt(K / rho0)
  bool artificial_stress = true;
  double artificial_stress_factor = 0.2;
  double smoothing_length_ratio = 1.5;
  double alpha = 1, beta = 1;
  double end_time = 4e-4;
  double output_interval = 0;
};

std::unique_ptr<Scene> make_rubber_rings_scene(RubberRingsParameters parameters = {});

}  // namespace cardiosph
