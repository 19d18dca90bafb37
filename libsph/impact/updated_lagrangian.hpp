#pragma once
// An updated-Lagrangian SPH body with an energy equation: the compressible hydrodynamics of the
// impact family (Monaghan 1992, Annu. Rev. Astron. Astrophys. 30:543; Benz & Asphaug 1994, Icarus
// 107:98). With v_ij = v_i - v_j and grad_i W_ij the kernel gradient at x_i - x_j:
//
//   d rho_i / dt = rho_i sum_j m_j / rho_j  v_ij . grad_i W_ij
//   d v_i / dt   = - sum_j m_j (p_i / rho_i^2 + p_j / rho_j^2 + Pi_ij) grad_i W_ij
//   d e_i / dt   = 1/2 sum_j m_j (p_i / rho_i^2 + p_j / rho_j^2 + Pi_ij) v_ij . grad_i W_ij
//
// with Monaghan's artificial viscosity, for approaching pairs (v_ij . x_ij < 0),
//   Pi_ij = (-alpha c_ij phi_ij + beta phi_ij^2) / rho_ij,  phi_ij = h v_ij . x_ij / (|x_ij|^2 + epsilon h^2),
// c_ij and rho_ij the pair means. The pressure comes from the body's equation of state: an ideal gas
// p = (gamma - 1) rho e, or Tillotson (libsph/impact/tillotson.hpp).
//
// Time stepping: leapfrog kick-drift-kick (Springel 2005, MNRAS 364:1105) on v, rho and e, the
// rates re-evaluated once per step at the drifted positions with the predicted v, rho, e, and the
// step dt = CFL min_i h / (c_i + |v_i|) with CFL = 0.2. Strength, damage, artificial stress,
// variable smoothing lengths and self-gravity are not part of this body yet.
//
// Numerical failure (a density or internal energy that is not positive where the equation of state
// needs it, a non-finite velocity, a stable step fallen below 1e-6 of the initial one) stops the run
// with a NumericalFailure naming particle and time.

#include <string>
#include <variant>
#include <vector>

#include "libsph/core/kernels.hpp"
#include "libsph/core/neighbour_relation.hpp"
#include "libsph/core/particles.hpp"
#include "libsph/core/state_archive.hpp"
#include "libsph/impact/tillotson.hpp"

namespace sph {

/// p = (gamma - 1) rho e, c = sqrt(gamma p / rho).
struct IdealGas {
  double gamma = 1.4;
};

using ImpactEquationOfState = std::variant<IdealGas, TillotsonParameters>;

template <int Dim>
class UpdatedLagrangianBody {
 public:
  struct Settings {
    ImpactEquationOfState equation_of_state = IdealGas{};
    Real smoothing_length = 0;                     ///< h (the same for every particle)
    AnyKernel<Dim> kernel = CubicSplineM4<Dim>{};  ///< M4 by default, h = 1.2 dx in the impact codes
    Real alpha = 1, beta = 2;                      ///< artificial viscosity (Monaghan 1992)
    Real epsilon = Real(0.1);                      ///< the epsilon h^2 in phi_ij's denominator
    Real cfl = Real(0.2);
    PeriodicBox<Dim> periodic;                     ///< periodic axes (none by default)
  };

  /// Registers mass, density, velocity, energy, pressure, sound_speed, acceleration, density_rate
  /// and energy_rate on `particles`. Throws std::invalid_argument for impossible settings.
  UpdatedLagrangianBody(ParticleSet<Dim>& particles, Settings settings);

  /// Sets mass = density x volume and evaluates the pressure, the sound speed and the rates: call
  /// once after the initial density, velocity and energy are set.
  void initialise();
  Real stable_time_step() const;
  /// One kick-drift-kick step from `time` by dt.
  void advance(Real time, Real dt);

  struct Energies {
    double kinetic = 0, internal = 0;
    double total() const { return kinetic + internal; }
  };
  Energies energies() const;

  FieldHandle<Real> mass_field() const { return mass_; }
  FieldHandle<Real> density_field() const { return density_; }
  FieldHandle<Vec<Dim>> velocity_field() const { return velocity_; }
  FieldHandle<Real> energy_field() const { return energy_; }
  FieldHandle<Real> pressure_field() const { return pressure_; }
  ParticleSet<Dim>& particles() { return particles_; }
  const Settings& settings() const { return settings_; }
  std::size_t steps() const { return steps_; }
  const InnerRelation<Dim>& relation() const { return relation_; }

  /// Saves or loads what changes besides the fields (checkpoints): the step count. The rates a step
  /// starts from are fields; the relation is rebuilt where they are evaluated.
  void checkpoint(StateArchive& archive) { archive.io("steps", steps_); }

 private:
  void update_equation_of_state();
  void compute_rates();
  void check_state(Real time) const;

  ParticleSet<Dim>& particles_;
  Settings settings_;
  InnerRelation<Dim> relation_;
  FieldHandle<Real> mass_, density_, energy_, pressure_, sound_speed_, density_rate_, energy_rate_;
  FieldHandle<Vec<Dim>> velocity_, acceleration_;
  std::size_t steps_ = 0;
  Real initial_time_step_ = 0;  // a step below 1e-6 of it stops the run
  std::vector<Vec<Dim>> v_half_;  // scratch of a step: the half-step state
  std::vector<Real> rho_half_, e_half_;
};

extern template class UpdatedLagrangianBody<2>;
extern template class UpdatedLagrangianBody<3>;

}  // namespace sph
