#pragma once
// What the fluid scenes share: their numerical parameters, the Mach-number check, the tank of wall
// particles, and the run of one fluid with its walls (the dual-criteria stage on the run harness of
// libsph/io/run_harness.hpp: particles, energy series, observers, progress, the last state on failure).

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "apps/scenes/discretisation.hpp"
#include "apps/scenes/run_plan.hpp"
#include "apps/scenes/scene.hpp"
#include "geometry/shape.hpp"
#include "geometry/wall_particles.hpp"
#include "libsph/fluid/weakly_compressible_fluid.hpp"
#include "libsph/io/run_harness.hpp"

namespace cardiosph {

/// Numerical settings shared by the fluid scenes: the discretisation (Wendland C2, h = 1.3 dp as
/// in SPHinXsys) and the fluid's own choices (sph::FluidNumerics).
struct FluidSceneNumerics {
  Discretisation discretisation{1.3, "wendland_c2", 0};
  sph::FluidNumerics fluid;
};

/// The numerics of internal flows (no free surface): density from the number density at every
/// advection step, the transport-velocity shift (kappa = 0.2), and the advection step at CFL 0.1:
/// at 0.25 the pair geometry frozen over the advection step lets the particles order themselves
/// wrongly (measured in docs/fluid.md: cavity centre-line RMS 0.135 against 0.015, Poiseuille L2
/// 10 % against 2 %, Taylor-Green decay rate 55 % against 30 %).
inline FluidSceneNumerics internal_flow_numerics() {
  FluidSceneNumerics n;
  n.fluid.density_reinitialisation = sph::DensityReinitialisation::internal;
  n.fluid.transport_velocity = sph::Real(0.2);
  n.fluid.advection_cfl = sph::Real(0.1);
  return n;
}

/// The Taylor-Green vortex's: internal flow with the kernel-corrected pressure force and a weaker
/// shift (at 50 across: decay-rate error +3 % against +32 % with the plain force; docs/fluid.md).
inline FluidSceneNumerics taylor_green_numerics() {
  FluidSceneNumerics n = internal_flow_numerics();
  n.fluid.kernel_correction = true;
  n.fluid.transport_velocity = sph::Real(0.1);
  return n;
}

void declare_fluid_numerics(sph::Parameters& p, FluidSceneNumerics& n, const std::string& time_unit);

/// Mach number U_ref / c0 of a scene: ParameterError naming `sound_speed` above 0.3; returns a
/// warning for the report above 0.1 (empty otherwise).
std::string check_mach_number(double reference_speed, double sound_speed);

/// Fluid settings of a scene: linear equation of state, the scene's discretisation and numerics.
template <int Dim>
typename sph::WeaklyCompressibleFluid<Dim>::Settings fluid_settings(const FluidSceneNumerics& numerics, double dp,
                                                                    double density, double sound_speed,
                                                                    double viscosity, const sph::Vec<Dim>& body_force,
                                                                    double reference_speed);

/// Layers of wall particles that cover the kernel support (ceil(2h / dp)).
int wall_layers(const Discretisation& d);

/// Wall particles around the box container [lower, upper] (3D shape; z ignored in 2D), `layers`
/// thick, except along the periodic axes, where the wall spans exactly [lower, upper).
template <int Dim>
geometry::WallParticles<Dim> box_walls(const std::string& name, const sph::Vec<Dim>& lower, const sph::Vec<Dim>& upper,
                                       sph::Real dp, int layers, std::array<bool, Dim> periodic = {});

struct FluidRunPlan : RunPlan {  // sample_interval 0: end_time / 200 (also the energies)
  using RunPlan::RunPlan;
  /// Adds bodies, couplings and open boundaries to the run (may be empty): their outputs on the
  /// harness, their couplings in the slots of the fluid's step (WeaklyCompressibleFluid::advection_stage).
  std::function<void(sph::RunHarness&, sph::Stage& fluid_step)> extend;
};

struct FluidRunSummary {
  std::size_t advection_steps = 0, acoustic_steps = 0;
  double initial_energy = 0, max_energy_rise = 0;  ///< max (E(t) - E(0)) / max(|E(0)|, max |E|) over the samples
  double max_mach = 0;                             ///< max |v| / c0 over the samples
  double time_loop_seconds = 0;
};

/// Runs the fluid from t = 0 to the end time with its walls (the first walls of the fluid, in order). Writes <fluid>.pvd with its .vtu files,
/// each wall's first and last state, <fluid>_energy.csv (time, kinetic, potential, internal, total,
/// max speed) and observers.csv into ctx.output_dir. Fills steps, particles, memory, sound_speed,
/// advection_steps, acoustic_steps, particle_steps_per_second and max_mach in ctx.report.
template <int Dim>
FluidRunSummary run_fluid(sph::WeaklyCompressibleFluid<Dim>& fluid, std::vector<sph::FluidWall<Dim>*> walls,
                          const FluidRunPlan& plan, RunContext& ctx);

/// Sets density, pressure and mass of every fluid particle for the hydrostatic column whose free
/// surface is at height `surface` (axis Dim - 1 up, gravity g down): p = rho0 g (surface - y), the
/// particle keeping its lattice volume.
template <int Dim>
void set_hydrostatic_state(sph::WeaklyCompressibleFluid<Dim>& fluid, double surface, double g);

}  // namespace cardiosph
