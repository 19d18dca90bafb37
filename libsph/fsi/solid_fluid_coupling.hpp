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
// its own acoustic step dt_s (position-based Verlet, ElasticSolid::advance), under the fluid's
// pressure force of that acoustic step and viscous force of that advection step, held fixed. The
// fluid sees the solid's motion averaged over the step:
//   v_avg = (x(t + dt) - x(t)) / dt,    a_mean = (v(t + dt) - v(t)) / dt,
// and the acceleration under relaxation, a_avg <- a_avg + theta (a_mean - a_avg) (theta =
// acceleration_relaxation, default 0.1). The acceleration enters the fluid's wall pressure
// p_w = p_i + rho_i (g - a_avg) . (x_w - x_i), and with sub-cycling a_mean carries the solid's
// vibration that the fluid step does not resolve (its size grows as 1 / dt). Fed back unrelaxed
// through p_w it pumped the surface particles of a light solid: the elastic gate (rho_s / rho_f =
// 1.1) inverted at 15 ms at theta = 1, was shaken at 20 times the water's speed and inverted at
// 391 ms at 0.5, and ran through 400 ms at 0.2 and 0.1, while the FSI2 bar (rho_s / rho_f = 10)
// moved within 0.5 % between theta = 1 and 0.1. Without the acceleration term at all the FSI2 bar
// inverted at t = 22, so the term stays. Relaxing an
// interface quantity of a staggered coupling is the usual cure of its added-mass feedback
// (Kuettler & Wall 2008, Comput. Mech. 43:61); a lag of about 1 / theta acoustic steps is far below
// the physical time scales of these cases.
// and, at each advection step, the current normal n = F^-T n0 / |F^-T n0| from the reference normal
// n0. With sub_cycling off, the fluid's acoustic step is bounded by the solid's stable step and the
// solid takes one step per acoustic step (the single-rate run the speed-up is measured against).
//
// Set-up check: a solid thinner than one fluid particle spacing somewhere (measured through the
// solid along its normals) is refused: the fluid could see across it.

#include <span>
#include <string>
#include <vector>

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

  /// Adds the coupling to the fluid's step: the viscous force on the solid after the fluid's forces,
  /// and the solid's sub-cycle with the averaging at the end of every acoustic step.
  void add_to(FluidStepHooks& hooks, SectionTimers& timers);

  /// Total force of the fluid on the solid (pressure and viscous parts).
  Vec<Dim> total_force() const;
  /// Solid steps taken so far.
  std::size_t solid_steps() const { return solid_steps_; }
  /// Saves or loads what changes besides the solid's fields (checkpoints, taken between advection
  /// steps): the solid step count. The relaxed acceleration is a field; the step's start state is
  /// taken anew at every acoustic step.
  void checkpoint(StateArchive& archive) { archive.io("solid_steps", solid_steps_); }
  const FluidWall<Dim>& wall() const { return wall_; }
  /// The thinnest extent of the solid through its particles along their normals (set-up check).
  Real thickness() const { return thickness_; }

 private:
  void update_normals();
  void update_viscous_force();
  void begin_step();
  void end_step(Real dt);

  WeaklyCompressibleFluid<Dim>& fluid_;
  ElasticSolid<Dim>& solid_;
  Settings settings_;
  FluidWall<Dim> wall_;
  std::size_t wall_index_ = 0;
  std::size_t solid_steps_ = 0;
  Real thickness_ = 0;
  std::vector<Vec<Dim>> reference_normal_, start_position_, start_velocity_, scratch_viscous_, scratch_pressure_;
  FieldHandle<Vec<Dim>> pressure_force_, viscous_force_;
};

extern template class SolidFluidCoupling<2>;
extern template class SolidFluidCoupling<3>;

}  // namespace sph
