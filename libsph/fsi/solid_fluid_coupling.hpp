#pragma once
// Fluid-structure interaction of a weakly-compressible fluid and a TLSPH elastic solid (Zhang,
// Rezavand & Hu 2021, J. Comput. Phys. 429:110028; docs/fsi.md has the equations).
//
// The solid is a moving wall of the fluid (libsph/fluid/fluid_wall.hpp): the fluid sees each solid
// particle through the one-sided Riemann problem of its wall boundary, with the solid's imaginary
// pressure (extrapolated from the fluid particle with the body force and the solid's acceleration)
// and imaginary velocity (mirrored about the solid's velocity), and the solid takes the equal and
// opposite force (recorded pair by pair by the fluid, WallForces::record):
//   f_j^p = - sum_i ( -2 V_i V_j P*_ij dW_ij e_ij ),    f_j^v = - sum_i 2 eta_i V_i V_j 2 (v_i - v_j) / r_ij dW_ij,
// (eta_i includes the fluid's renormalisation of the Laplacian), so that the total momentum of
// fluid and solid is conserved to round-off when no other wall or constraint acts.
//
// Multi-resolution: the solid may be finer than the fluid (h_fluid / h_solid = 1, 2, 4). The
// contact pairs are those within the fluid's kernel support and use the fluid's kernel, both ways;
// the solid's own stress uses its own inner relation and smoothing length.
//
// Multi time stepping (sec. 3.3 there): the solid sub-cycles inside each fluid acoustic step dt at
// its own acoustic step dt_s (position-based Verlet, ElasticSolid::stage), under the fluid's
// pressure force of that acoustic step and viscous force of that advection step, held fixed. The
// fluid sees the solid's motion averaged over the step:
//   v_avg = (x(t + dt) - x(t)) / dt,    a_mean = (v(t + dt) - v(t)) / dt,
// and the acceleration under relaxation, a_avg <- a_avg + theta (a_mean - a_avg) (theta =
// acceleration_relaxation, default 0.1), and, at each advection step, the current normal
// n = F^-T n0 / |F^-T n0| from the reference normal n0. The acceleration enters the fluid's wall
// pressure p_w = p_i + rho_i (g - a_avg) . (x_w - x_i), and with sub-cycling a_mean carries the
// solid's vibration that the fluid step does not resolve (its size grows as 1 / dt). Fed back
// unrelaxed through p_w it pumped the surface particles of a light solid: the elastic gate (rho_s /
// rho_f = 1.1) inverted at 15 ms at theta = 1, was shaken at 20 times the water's speed and inverted
// at 391 ms at 0.5, and ran through 400 ms at 0.2 and 0.1, while the FSI2 bar (rho_s / rho_f = 10)
// moved within 0.5 % between theta = 1 and 0.1. Without the acceleration term at all the FSI2 bar
// inverted at t = 22, so the term stays. Relaxing an interface quantity of a staggered coupling is
// the usual cure of its added-mass feedback (Kuettler & Wall 2008, Comput. Mech. 43:61); a lag of
// about 1 / theta acoustic steps is far below the physical time scales of these cases. With
// sub_cycling off, the fluid's acoustic step is bounded by the solid's stable step and the solid
// takes one step per acoustic step (the single-rate run the speed-up is measured against).
//
// The coupling is the relation of the two systems (libsph/core/interaction.hpp): it holds the
// contact data (the solid's surface as a wall of the fluid, the forces the fluid recorded on it,
// the solid's state at the start of the acoustic step), and two interactions act across it:
//   fluid on solid  interact(solid, fluid, coupling): the held pressure and viscous forces added to
//                   the solid's external force, in the solid's loads slot (ElasticSolid::loads_slot);
//   solid on fluid  interact(coupling.wall(), solid, coupling): the solid's motion over the acoustic
//                   step averaged into the wall's velocity and acceleration.
// `fill` places them, with the coupling's own updates, in the slots of the fluid's step
// (WeaklyCompressibleFluid::advection_stage):
//   [forces on bodies in '<fluid>']  surface of '<solid>': the normals (update_surface)
//   [bodies in the acoustic step of '<fluid>']  fsi '<solid>' (a nested stage over the acoustic step):
//       forces and start of '<solid>' (begin_acoustic_step)
//       solid '<solid>', sub-cycling at the solid's stable step (ElasticSolid::stage):
//           half drift | deformation and stress | [loads on '<solid>': fluid forces] | kick and drift
//       motion of '<solid>' (solid on fluid)
//
// Set-up check: a solid thinner than one fluid particle spacing somewhere (measured through the
// solid along its normals) is refused: the fluid could see across it.

#include <span>
#include <string>
#include <vector>

#include "libsph/core/interaction.hpp"
#include "libsph/core/section_timers.hpp"
#include "libsph/fluid/fluid_wall.hpp"
#include "libsph/fluid/weakly_compressible_fluid.hpp"
#include "libsph/solid/elastic_solid.hpp"

namespace sph {

template <int Dim>
class SolidFluidCoupling {
 public:
  struct Settings {
    Real solid_spacing = 0;   ///< dp of the solid's particles
    bool sub_cycling = true;  ///< multi time stepping (false: the solid's step bounds the fluid's)
    /// theta in (0, 1]: the weight of the newest mean acceleration in the one the fluid sees (1: none kept)
    Real acceleration_relaxation = Real(0.1);
  };

  /// `reference_normals`: unit outward normal of the solid's surface nearest to each solid particle,
  /// in the reference configuration. Throws std::invalid_argument if the solid is thinner than the
  /// fluid's particle spacing. Registers the fields wall_normal, fluid_velocity (averaged),
  /// fluid_acceleration, fluid_pressure_force and fluid_viscous_force on the solid's particles.
  SolidFluidCoupling(WeaklyCompressibleFluid<Dim>& fluid, ElasticSolid<Dim>& solid,
                     const std::vector<Vec<Dim>>& reference_normals, Settings settings);

  /// Fills the slots of the fluid's step `fluid_step` (its advection_stage) as above and, without
  /// sub-cycling, bounds the fluid's acoustic step by the solid's. The solid's steps are timed in
  /// `timers` under "solid_step", the coupling's updates under "fsi_forces".
  void fill(Stage& fluid_step, SectionTimers& timers);

  // The coupling's own updates (`fill` places them).
  /// The wall's normals n = F^-T n0 / |F^-T n0| from the solid's deformation gradient, recomputed
  /// at the current positions (at each advection step, with the fluid's relations).
  void update_surface();
  /// At the start of each acoustic step, after the fluid's pressure force: the forces the fluid
  /// recorded on the solid (pressure of this acoustic step, viscous of this advection step) into
  /// fluid_pressure_force and fluid_viscous_force, held over the solid's sub-steps, and the solid's
  /// positions and velocities, the start of the motion the fluid will see averaged.
  void begin_acoustic_step();

  /// Total force of the fluid on the solid (pressure and viscous parts).
  Vec<Dim> total_force() const;
  /// Solid steps taken so far.
  std::size_t solid_steps() const { return solid_steps_; }
  /// Saves or loads what changes besides the solid's fields (checkpoints, taken between advection
  /// steps): the solid step count. The relaxed acceleration is a field; the step's start state is
  /// taken anew at every acoustic step.
  void checkpoint(StateArchive& archive) { archive.io("solid_steps", solid_steps_); }
  const FluidWall<Dim>& wall() const { return wall_; }
  FluidWall<Dim>& wall() { return wall_; }
  /// The fluid's force on each solid particle held over the sub-steps (see begin_acoustic_step).
  FieldHandle<Vec<Dim>> pressure_force_field() const { return pressure_force_; }
  FieldHandle<Vec<Dim>> viscous_force_field() const { return viscous_force_; }
  /// The solid's positions and velocities at the start of the current acoustic step.
  const std::vector<Vec<Dim>>& start_position() const { return start_position_; }
  const std::vector<Vec<Dim>>& start_velocity() const { return start_velocity_; }
  const Settings& settings() const { return settings_; }
  /// The thinnest extent of the solid through its particles along their normals (set-up check).
  Real thickness() const { return thickness_; }

 private:
  WeaklyCompressibleFluid<Dim>& fluid_;
  ElasticSolid<Dim>& solid_;
  Settings settings_;
  FluidWall<Dim> wall_;
  std::size_t wall_index_ = 0;
  std::size_t solid_steps_ = 0;
  Real thickness_ = 0;
  std::vector<Vec<Dim>> reference_normal_, start_position_, start_velocity_;
  FieldHandle<Vec<Dim>> pressure_force_, viscous_force_;
};

/// Fluid on solid, in the solid's loads slot: the fluid's pressure and viscous forces held by the
/// coupling (begin_acoustic_step) added to the solid's external force, f_i += f_i^p + f_i^v.
template <int Dim>
void interact(ElasticSolid<Dim>& on, const WeaklyCompressibleFluid<Dim>& by, const SolidFluidCoupling<Dim>& coupling,
              Real time, Real dt);

/// Solid on fluid, at the end of the acoustic step [time, time + dt] after the solid's sub-steps:
/// the solid's motion over the step as the velocity v_avg and relaxed acceleration a_avg of its wall
/// (`on` is coupling.wall()), from the start state of begin_acoustic_step.
template <int Dim>
void interact(FluidWall<Dim>& on, const ElasticSolid<Dim>& by, const SolidFluidCoupling<Dim>& coupling, Real time,
              Real dt);

extern template class SolidFluidCoupling<2>;
extern template class SolidFluidCoupling<3>;

}  // namespace sph
