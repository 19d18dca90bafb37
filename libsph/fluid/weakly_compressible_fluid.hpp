#pragma once
// A weakly-compressible fluid in SPH with Riemann solvers and dual-criteria time stepping.
// docs/fluid.md has the equations; in short (e_ij = (x_i - x_j) / r_ij, dW_ij = dW/dr <= 0,
// V_j = m_j / rho_j):
//
// Momentum (Zhang, Hu & Adams 2017, J. Comput. Phys. 335:605, eq. 10):
//   dv_i/dt = -2 / rho_i sum_j V_j P*_ij dW_ij e_ij + (viscous) + g,
// with the inter-particle Riemann problem along the line of the pair, left state i, right state j,
// u_L = -v_i.e_ij, u_R = -v_j.e_ij:
//   P* = (p_i + p_j) / 2 + 1/2 beta rho0 c0 (u_L - u_R),  beta = min(eta max(u_L - u_R, 0) / c0, 1)
// (the low-dissipation limiter of Zhang et al. 2017, eq. 15, eta = 3: dissipation only where the
// pair compresses; the impedance rho c of the dissipative terms is taken at rho0, the density
// varying by about 1 %). scheme = plain drops the dissipative part; artificial_viscosity replaces it by
// Monaghan's Pi_ij (Monaghan 1992, Annu. Rev. Astron. Astrophys. 30:543, eq. 4.1).
// Continuity (same paper, eq. 9):
//   drho_i/dt = 2 rho_i sum_j V_j (U* - u_L) dW_ij,  U* = (u_L + u_R) / 2 + beta (p_L - p_R) / (2 rho0 c0),
// with the same limiter beta (without it the pressure jump diffuses the density with a coefficient
// of order c0 h, which at Mach 0.1 erases a hydrostatic or vortical pressure field within a
// fraction of a time unit: measured on the hydrostatic tank and the Taylor-Green vortex); the
// pressure jump is dropped for plain and artificial_viscosity. scheme = pressure_diffusion keeps the
// pressure jump of the continuity equation with beta = 1 for every pair (at the wall, the jump to
// the extrapolated wall pressure) and drops the momentum dissipation: the scheme SPHinXsys runs its
// internal flows with (Integration1stHalfWithWallRiemann with Integration2ndHalfWithWallNoRiemann),
// whose density diffusion of coefficient about c0 h is harmless where the density is re-initialised
// from the particle distribution every advection step, and which leaves vortex shedding undamped
// (docs/fsi.md: the limited momentum dissipation of riemann suppresses the shedding at Re 100).
// Kernel correction (numerics kernel_correction, for internal flows): the pressure part of P* acts
// through the corrected kernel gradient of each side,
//   dv_i/dt = -1 / rho_i sum_j V_j (p_i B_i + p_j B_j) dW_ij e_ij - (dissipative part as above),
// with B_i = (-sum_j V_j r_ij dW_ij e_ij (x) e_ij)^-1 over fluid and wall neighbours (Bonet & Lok
// 1999, CMAME 180:97; libsph/core/correction_matrix.hpp), computed at each advection step. The
// pair force stays antisymmetric (momentum is conserved); the gradient of a linear pressure is exact
// on any particle distribution, so the zeroth-order error of the plain form, which on a disordered
// distribution turns the pressure field into noise, is gone. A wall particle takes the fluid
// particle's B. The Taylor-Green vortex at 50 across: decay-rate error +32 % without, +3 % with
// (docs/fluid.md).
// Wall (Zhang et al. 2017, sec. 3.3; Adami, Hu & Adams 2012, eq. 27): a wall particle w takes the
// fluid particle's density, the mirrored velocity 2 v_w - v_i, and the pressure extrapolated with the
// body force, p_w = p_i + rho_i (g - a_w).(x_w - x_i); the dissipation uses the jump of the normal
// velocity, u_L - u_R = 2 (v_w - v_i).n_w.
// Viscosity (Hu & Adams 2006, J. Comput. Phys. 213:844, eq. 22; Morris et al. 1997):
//   dv_i/dt += 2 eta / rho_i sum_j V_j (v_i - v_j) / r_ij dW_ij, and with a no-slip wall v_j = 2 v_w - v_i.
//
// Dual-criteria time stepping (Zhang, Rezavand & Hu 2020, J. Comput. Phys. 404:109135):
//   advection step  dt_ad = cfl_ad min( h / max(|v|max, U_ref), h^2 / nu, sqrt(h / |g|) ),  cfl_ad = 0.25,
//   acoustic step   dt_ac = cfl_ac h / (c0 + |v|max),                                     cfl_ac = 0.6.
// Both are evaluated at the start of an advection step, which is then made a whole number of
// acoustic steps (the nearest to dt_ad / dt_ac): no sliver of an acoustic step is wasted, and the
// acoustic step holds through the advection step (c0 dominates c0 + |v|, which changes by a few
// per cent at most over 0.25 h of motion).
// At the start of each advection step: periodic wrap, re-sort along the cell list every
// `sort_interval` steps, neighbour rebuild (inner and every wall), density re-initialisation
//   free surface: rho_i = max(rho_i, rho0 sigma_i / sigma0),  internal: rho_i = rho0 sigma_i / sigma0,
// (sigma_i = sum_j V0_j W_ij over fluid and wall including i itself, sigma0 its value in a full
// lattice), then the viscous force, the body force and the transport-velocity shift
//   x_i -= 2 kappa h^2 grad sigma_i   (Zhang et al. 2017, J. Comput. Phys. 337:216; kappa = 0 off),
// which keeps internal flows free of voids and clumps. The acoustic steps inside (positions and
// kernel values of the pairs frozen) use the position-based Verlet scheme (Zhang et al. 2021, JCP
// 429:110028): rho += dt/2 drho/dt, p(rho), x += dt/2 v; force; v += dt a; x += dt/2 v; drho/dt; rho += dt/2 drho/dt.
//
// Bodies in the fluid (Zhang, Rezavand & Hu 2021, JCP 429:110028, sec. 3): a wall added with
// WallForces::record keeps the force of every fluid-wall pair, so the force of the fluid on each wall
// particle is exactly minus the sum of what its pairs gave the fluid (momentum is conserved to
// round-off): the pressure part (Riemann pressure P* above) at each acoustic step, the viscous part
// at each advection step.
//
// The step as a stage (advection_stage; libsph/core/time_stepper.hpp, "Slots"), with the slots in
// which couplings act (libsph/core/interaction.hpp), named after the fluid's particles:
//   advection:  [particles in and out of '<fluid>']              particles_slot()
//               neighbours | density and forces
//               [forces on bodies in '<fluid>']                 forces_slot()
//               acoustic:  pressure force | continuity
//                          [bodies in the acoustic step of '<fluid>']  acoustic_slot()
//               checks
//   particles_slot  particles created or deleted before the neighbour search: the emission of an
//                   inflow zone and the deletion of an outflow zone (libsph/fluid/open_boundaries.hpp);
//   forces_slot     after the density, viscous and body forces, with the relations just rebuilt: what
//                   a body takes once per advection step (the surface normals of an elastic solid,
//                   libsph/fsi/solid_fluid_coupling.hpp);
//   acoustic_slot   at the end of every acoustic step, the fluid's pressure force of the step
//                   recorded: the bodies that move under it (an elastic solid sub-cycling at its own
//                   step, a rigid body, libsph/fsi/), the velocity imposed in an inflow zone, and
//                   samples of the forces on bodies.
// A body whose step bounds the fluid's adds that bound with add_acoustic_step_limit.
//
// Order of the sums: a row lists its neighbours cell by cell, and within a cell by position
// (SourceOrder::by_position), and the energies are exact sums (exact_sum.hpp): re-sorting the
// particles in memory changes the speed only, never a bit of the result.
//
// Distribution (distribute()): each rank integrates its owned particles; the ghosts are rebuilt
// with the neighbours, and updated twice per acoustic step (the velocity after the pressure force,
// the density rate after the continuity), the ranks then advancing their ghosts' density, pressure
// and volume themselves with the same arithmetic as the owners; after the density
// re-initialisation the density once. The time step, the energies and the state check are reduced
// over the ranks.
//
// Failure: after each advection step a particle whose density leaves [0.5, 2] rho0, whose state is
// not finite, or which leaves the domain box stops the run with a NumericalFailure naming the
// body, the particle, its position, the time and the quantity.
//
// Fields (written to output unless noted): velocity, density, pressure; not written: mass,
// density_change_rate, acceleration (pressure part), prior_acceleration (body force and viscosity).
// A fluid allocates nothing of a solid's, and nothing of it lives on a solid.

#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "libsph/core/distribution.hpp"
#include "libsph/core/kernels.hpp"
#include "libsph/core/neighbour_relation.hpp"
#include "libsph/core/particles.hpp"
#include "libsph/core/section_timers.hpp"
#include "libsph/core/state_archive.hpp"
#include "libsph/core/time_stepper.hpp"
#include "libsph/fluid/equation_of_state.hpp"
#include "libsph/fluid/fluid_wall.hpp"

namespace sph {

class Parameters;

enum class FluidScheme { riemann, pressure_diffusion, plain, artificial_viscosity };
enum class DensityReinitialisation { free_surface, internal, none };

const std::vector<std::pair<std::string, FluidScheme>>& fluid_scheme_names();
const std::vector<std::pair<std::string, DensityReinitialisation>>& density_reinitialisation_names();

/// The numerical choices of a fluid (independent of the dimension); scenes bind them through
/// declare_parameters.
struct FluidNumerics {
  FluidScheme scheme = FluidScheme::riemann;
  Real limiter_strength = 3;        ///< eta of the low-dissipation limiter
  Real artificial_viscosity = Real(0.1);  ///< alpha of Monaghan's Pi_ij (scheme artificial_viscosity)
  Real advection_cfl = Real(0.25);
  Real acoustic_cfl = Real(0.6);
  DensityReinitialisation density_reinitialisation = DensityReinitialisation::free_surface;
  Real transport_velocity = 0;      ///< kappa of the transport-velocity shift; 0 = off (free surfaces)
  bool kernel_correction = false;   ///< pressure force with the corrected kernel gradient B_i grad W (internal flows)
  int sort_interval = 100;          ///< advection steps between re-sorts along the cell list; 0 = never
};

/// Whether a wall keeps the fluid's force on each of its particles (bodies, drag and lift) or not.
enum class WallForces { ignore, record };

/// Declares fluid_scheme, riemann_limiter, artificial_viscosity, advection_cfl, acoustic_cfl,
/// density_reinitialisation, transport_velocity, kernel_correction and sort_interval.
void declare_parameters(Parameters& p, FluidNumerics& numerics);

template <int Dim>
class WeaklyCompressibleFluid {
 public:
  struct Settings {
    EquationOfState equation_of_state;  ///< rho0, c0 and the kind
    Real viscosity = 0;                 ///< dynamic viscosity eta [mass / (length time)]
    Vec<Dim> body_force = Vec<Dim>::Zero();  ///< g [length / time^2]
    Real reference_speed = 0;           ///< U_ref: the largest flow speed expected (advection step, Mach)
    Real particle_spacing = 0;          ///< dp of the lattice the particles started on
    Real smoothing_length = 0;          ///< h
    AnyKernel<Dim> kernel = WendlandC2<Dim>{};
    PeriodicBox<Dim> periodic;          ///< periodic axes and their box (none by default)
    Vec<Dim> domain_lower = Vec<Dim>::Constant(-1e30);  ///< a particle leaving this box stops the run
    Vec<Dim> domain_upper = Vec<Dim>::Constant(1e30);
    FluidNumerics numerics;
  };

  /// The particles' volumes are their initial volumes (mass = rho0 V); velocity and density start at
  /// 0 and rho0 unless set through the fields before the first step.
  WeaklyCompressibleFluid(ParticleSet<Dim>& particles, Settings settings);
  ~WeaklyCompressibleFluid();

  /// Spreads the particles over the MPI ranks of the run (nothing on one rank): each rank then
  /// computes the particles in its region of space, which migrate between ranks at every neighbour
  /// rebuild, the regions cut anew every `rebalance_interval` rebuilds (MovingPartition,
  /// libsph/core/distribution.hpp); walls stay whole on every rank. Call once the particles' state
  /// is set. Results are bitwise those of one rank: rows and sums do not depend on where a particle
  /// is stored (see "Distribution" above). Throws std::invalid_argument for what does not
  /// distribute yet: periodic axes, walls whose forces are recorded.
  void distribute(std::size_t rebalance_interval = 20);

  /// A wall the fluid cannot cross (must outlive the fluid; its particles are not re-sorted, but
  /// may move); returns its index k. With WallForces::record, wall_forces(k, ...) gives the fluid's
  /// force on each of its particles.
  std::size_t add_wall(const FluidWall<Dim>& wall, WallForces forces = WallForces::ignore);
  /// The force of the fluid on each particle of wall k (added with WallForces::record): the
  /// pressure part from the last acoustic step and the viscous part from the last advection step.
  void wall_forces(std::size_t k, std::span<Vec<Dim>> pressure, std::span<Vec<Dim>> viscous) const;

  /// The dual-criteria step: an advection stage (neighbours, density, viscous and body forces)
  /// holding the acoustic stage (pressure force and continuity) as sub-steps, with the slots above.
  /// Phases are timed in `timers` (which must outlive the stage).
  Stage advection_stage(SectionTimers& timers);
  /// The slots of advection_stage (see above).
  std::string particles_slot() const { return "particles in and out of '" + particles_.name() + "'"; }
  std::string forces_slot() const { return "forces on bodies in '" + particles_.name() + "'"; }
  std::string acoustic_slot() const { return "bodies in the acoustic step of '" + particles_.name() + "'"; }
  /// A further upper bound of the acoustic step, evaluated when each advection step is planned
  /// (e.g. the stable step of a solid that does not sub-cycle). `limit` must outlive the fluid's runs.
  void add_acoustic_step_limit(std::function<Real()> limit) { acoustic_limits_.push_back(std::move(limit)); }

  // The parts of the step, for tests and custom stages.
  void update_neighbours();
  void reinitialise_density();
  void compute_prior_acceleration();
  void first_half(Real dt);   ///< rho, p, x to mid-step; pressure force; v to the end of the step
  void second_half(Real dt);  ///< x to the end of the step; continuity; rho to the end of the step
  /// Stops the run (NumericalFailure) if a particle's state is invalid (see above).
  void check_state(Real time) const;

  /// The advection criterion dt_ad and the acoustic criterion dt_ac (see above).
  Real advection_time_step() const;
  Real acoustic_time_step() const;
  /// The step of the advection stage: dt_ac now (bounded by add_acoustic_step_limit) times the whole
  /// number of acoustic steps nearest to dt_ad / dt_ac (at least one); the acoustic sub-steps of
  /// that advection step are then dt_ac.
  Real plan_advection_step();

  struct Energies {
    double kinetic = 0, potential = 0, internal = 0;
    double total() const { return kinetic + potential + internal; }
  };
  /// Kinetic, potential (-m g.x, zero at the origin) and compression energy of the fluid.
  Energies energies() const;
  Real max_speed() const;
  /// The particles' pressure recomputed from their density (after an external change of density).
  void update_pressure();

  std::size_t advection_steps() const { return advection_steps_; }
  std::size_t acoustic_steps() const { return acoustic_steps_; }
  std::size_t neighbour_rebuilds() const { return rebuilds_; }
  /// Saves or loads what changes besides the particle fields (checkpoints, taken between advection
  /// steps): the step and rebuild counts (the rebuild count decides when the particles are re-sorted).
  /// The relations and the planned acoustic step are rebuilt at the start of every advection step.
  void checkpoint(StateArchive& archive) {
    archive.io("advection_steps", advection_steps_);
    archive.io("acoustic_steps", acoustic_steps_);
    archive.io("neighbour_rebuilds", rebuilds_);
  }
  /// Reference number density sigma0 of a full lattice.
  Real reference_number_density() const { return sigma0_; }

  FieldHandle<Vec<Dim>> velocity_field() const { return velocity_; }
  FieldHandle<Real> density_field() const { return density_; }
  FieldHandle<Real> pressure_field() const { return pressure_; }
  FieldHandle<Real> mass_field() const { return mass_; }
  const Settings& settings() const { return settings_; }
  ParticleSet<Dim>& particles() { return particles_; }
  const ParticleSet<Dim>& particles() const { return particles_; }
  const InnerRelation<Dim>& inner_relation() const { return inner_; }
  /// The relation of the fluid to wall k (in the order of add_wall).
  const ContactRelation<Dim>& wall_relation(std::size_t k) const;
  std::size_t n_walls() const { return walls_.size(); }

 private:
  struct WallContact;
  // A wall's relation and fields as spans, taken once when the wall is added; with recorded forces,
  // the force of each pair on the fluid (pressure and viscous parts).
  struct WallView {
    const ContactRelation<Dim>* relation;
    std::span<const Real> volume;
    std::span<const Vec<Dim>> velocity, acceleration, normal;
    bool no_slip;
    std::vector<Vec<Dim>>* pressure_pairs;  // null unless recorded
    std::vector<Vec<Dim>>* viscous_pairs;
  };

  ParticleSet<Dim>& particles_;
  Settings settings_;
  Real sigma0_ = 1;
  Real planned_acoustic_step_ = 0;
  std::size_t advection_steps_ = 0, acoustic_steps_ = 0, rebuilds_ = 0;
  FieldHandle<Vec<Dim>> velocity_, acceleration_, prior_acceleration_;
  FieldHandle<Real> density_, pressure_, mass_, density_rate_;
  InnerRelation<Dim> inner_;
  std::vector<std::unique_ptr<WallContact>> walls_;
  std::vector<WallView> views_;
  std::vector<Vec<Dim>> shift_;  // scratch of the transport-velocity shift
  std::vector<Mat<Dim>> correction_;  // B_i of the kernel correction (kernel_correction only)
  std::vector<std::function<Real()>> acoustic_limits_;
  std::unique_ptr<MovingPartition<Dim>> partition_;  // null unless distributed
  // What the pair loops read of a neighbour, packed so that one neighbour costs one cache line
  // instead of three (copied from the fields in the update loops of the acoustic step).
  struct PairState {
    Vec<Dim> velocity;
    Real pressure, volume;
  };
  std::vector<PairState> state_;
};

extern template class WeaklyCompressibleFluid<2>;
extern template class WeaklyCompressibleFluid<3>;

}  // namespace sph
