#pragma once
// Verification and validation scenes of the weakly-compressible fluid (libsph/fluid). Each writes
// report.json with its error against its reference next to its run time (docs/fluid.md).
//
// dambreak (2D, nondimensional: rho 1, g 1): the SPHinXsys setup, a water column 2 x 1 in a 5.366
//   tank; surge front against Martin & Moyce 1952 and Koshizuka & Oka 1996, wall pressure probe.
// dambreak-3d: the same column extruded across a tank of finite depth, coarse.
// hydrostatic-tank (2D): water at rest, long run; bottom pressure against rho g H, spurious speed.
// taylor-green (2D, periodic): decaying vortex at Re 100; kinetic-energy decay rate, L2 velocity.
// poiseuille (2D, periodic in x): body-force driven channel; profile against the parabola.
// lid-driven-cavity (2D): Re 100 (preset re1000); centre lines against Ghia, Ghia & Shin 1982.

#include <memory>
#include <string>

#include "apps/scenes/fluid/fluid_run.hpp"
#include "apps/scenes/scene.hpp"

namespace cardiosph {

struct DamBreakParameters {
  long resolution = 40;       ///< particles across the water height (dp = water_height / resolution)
  double end_time = 20;
  double water_width = 2, water_height = 1;
  double tank_width = 5.366, tank_height = 5.366;
  double depth = 0.5;         ///< tank and water extent along z (3D only)
  double density = 1, gravity = 1;
  double sound_speed = 20;    ///< c0: 10 times the shallow-water speed 2 sqrt(g H)
  double viscosity = 0;       ///< dynamic viscosity
  double probe_height = 0.2;  ///< height of the pressure probe on the far wall
  FluidSceneNumerics numerics;
};

/// The 3D defaults: a coarser column 0.5 deep in a tank 3 high, to t = 6.
inline DamBreakParameters dambreak_3d_defaults() {
  DamBreakParameters p;
  p.resolution = 20;
  p.end_time = 6;
  p.tank_height = 3;
  return p;
}

struct HydrostaticTankParameters {
  long resolution = 20;       ///< particles across the water height
  double end_time = 20;
  double water_height = 1, tank_width = 1, tank_height = 1.2;
  double density = 1, gravity = 1;
  double sound_speed = 10;
  double viscosity = 0;
  FluidSceneNumerics numerics;
};

struct TaylorGreenParameters {
  long resolution = 50;       ///< particles across the unit period
  double end_time = 1;
  double reynolds = 100;      ///< U L / nu with U = L = rho = 1
  double sound_speed = 10;
  FluidSceneNumerics numerics = taylor_green_numerics();
};

struct PoiseuilleParameters {
  long resolution = 20;       ///< particles across the channel height
  double end_time = 8;
  double height = 1, length = 1;  ///< channel (periodic along x)
  double viscosity = 0.1;     ///< dynamic viscosity (rho = 1)
  double body_force = 0.8;    ///< g along x: u_max = g H^2 / (8 nu)
  double sound_speed = 10;
  FluidSceneNumerics numerics = internal_flow_numerics();
};

struct LidDrivenCavityParameters {
  long resolution = 50;       ///< particles across the unit cavity
  double end_time = 20;
  std::string preset = "re100";  ///< re100 or re1000 (Reynolds number and its Ghia table)
  double sound_speed = 10;
  FluidSceneNumerics numerics = internal_flow_numerics();
};

std::unique_ptr<Scene> make_dambreak_scene(DamBreakParameters parameters = {});
std::unique_ptr<Scene> make_dambreak_3d_scene(DamBreakParameters parameters = dambreak_3d_defaults());
std::unique_ptr<Scene> make_hydrostatic_tank_scene(HydrostaticTankParameters parameters = {});
std::unique_ptr<Scene> make_taylor_green_scene(TaylorGreenParameters parameters = {});
std::unique_ptr<Scene> make_poiseuille_scene(PoiseuilleParameters parameters = {});
std::unique_ptr<Scene> make_lid_driven_cavity_scene(LidDrivenCavityParameters parameters = {});

}  // namespace cardiosph
