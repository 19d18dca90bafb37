#pragma once
// Scenes of the impact family (libsph/impact, docs/impact.md):
//   sod-shock-tube (2D slab, periodic across): Sod's shock tube against the exact Riemann solution;
//   L1 errors of density, velocity and pressure;
//   rubber-rings: Gray, Monaghan & Swift's colliding elastic rings, with or without artificial stress;
//   taylor-bar: a copper bar onto a rigid wall, von Mises plasticity: final length and mushroom radius;
//   evrard-collapse: a self-gravitating gas sphere (Barnes-Hut, variable h): energies, their conservation;
//   impact: a basalt sphere struck at 3.2 km/s (Nakamura & Fujiwara 1991) with damage: fragments;
//   sedov-blast: a 2D point explosion against the self-similar Sedov-Taylor solution.

#include <memory>

#include "apps/scenes/scene.hpp"

namespace cardiosph {

struct SodShockTubeParameters {
  long resolution = 200;       ///< particles per unit length (the same spacing on both sides)
  double end_time = 0.2;
  double tube_half_length = 1;  ///< the tube is [-L, L]; the error is measured on [-1/2, 1/2]
  long dimension = 2;          ///< 2: a slab; 3: a square bar
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

struct TaylorBarParameters {
  long resolution = 4;  ///< particles across the radius
  double radius = 3.2e-3, length = 32.4e-3, speed = 227;
  double density = 8930, youngs_modulus = 117e9, poisson_ratio = 0.35;
  double yield_strength = 400e6, hardening_modulus = 100e6;
  double smoothing_length_ratio = 1.3;
  /// Artificial viscosity: the result depends on it (docs/impact.md: alpha 1 gives a bar 5 % too
  /// long and a mushroom 14 % too narrow at resolution 4, alpha 0.2 a face that splashes).
  double alpha = 0.5, beta = 1, xsph = 0;
  double end_time = 80e-6;
  double output_interval = 0;
};

std::unique_ptr<Scene> make_taylor_bar_scene(TaylorBarParameters parameters = {});

struct EvrardCollapseParameters {
  long particles = 10000;
  double internal_energy = 0.05, gamma = 5.0 / 3.0;
  double theta = 0.5;
  double gravitational_softening = 0.02;  ///< one M4 softening length for all (0: each particle's h, which loses energy)
  double smoothing_length_factor = 1.2;
  double alpha = 1, beta = 2;
  double end_time = 3;
  double output_interval = 0;
};

std::unique_ptr<Scene> make_evrard_collapse_scene(EvrardCollapseParameters parameters = {});

struct ImpactParameters {
  long resolution = 15;  ///< particles across the target's radius
  double target_radius = 0.03, projectile_mass = 0.2e-3, speed = 3200, impact_angle = 30;
  double shear_modulus = 22.7e9, yield_strength = 3.5e9;
  double weibull_k = 5e34, weibull_m = 8.5;  ///< Benz & Asphaug 1994 (5e28 cm^-3)
  long seed = 1;
  double smoothing_length_ratio = 1.2;
  double alpha = 1, beta = 2;
  double end_time = 60e-6;
  double output_interval = 0;
};

std::unique_ptr<Scene> make_impact_scene(ImpactParameters parameters = {});

struct SedovBlastParameters {
  long resolution = 100;  ///< particles per unit length
  double half_width = 0.5, energy = 1, density = 1, gamma = 1.4;
  double blast_radius = 2;  ///< in particle spacings
  double smoothing_length_factor = 1.5;
  double alpha = 1, beta = 2;
  double end_time = 0.1;
  double output_interval = 0;
};

std::unique_ptr<Scene> make_sedov_blast_scene(SedovBlastParameters parameters = {});

}  // namespace cardiosph
