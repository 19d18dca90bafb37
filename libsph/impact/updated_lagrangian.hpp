#pragma once
// An updated-Lagrangian SPH body with an energy equation: the compressible hydrodynamics of the
// impact family (Monaghan 1992, Annu. Rev. Astron. Astrophys. 30:543; Benz & Asphaug 1994, Icarus
// 107:98). With v_ij = v_i - v_j and grad_i W_ij the kernel gradient at x_i - x_j:
//
//   d rho_i / dt = rho_i sum_j m_j / rho_j  v_ij . grad_i W_ij
//   d v_i / dt   = - sum_j m_j (p_i / rho_i^2 + p_j / rho_j^2 + Pi_ij) grad_i W_ij
//   d e_i / dt   = sum_j m_j (p_i / rho_i^2 + Pi_ij / 2) v_ij . grad_i W_ij
//
// with Monaghan's artificial viscosity, for approaching pairs (v_ij . x_ij < 0),
//   Pi_ij = (-alpha c_ij phi_ij + beta phi_ij^2) / rho_ij,  phi_ij = h v_ij . x_ij / (|x_ij|^2 + epsilon h^2),
// c_ij and rho_ij the pair means. The pressure comes from the body's equation of state: an ideal gas
// p = (gamma - 1) rho e, or Tillotson (libsph/impact/tillotson.hpp).
//
// Strength (shear_modulus > 0; Gray, Monaghan & Swift 2001, Comput. Methods Appl. Mech. Engrg.
// 190:6641): the stress is sigma = -p I + S, S the deviatoric stress, with Hooke's law in the Jaumann
// rate
//   dS/dt = 2 mu (eps' - 1/3 tr(eps') I) + S Omega^T + Omega S,
// eps' and Omega the symmetric and antisymmetric parts of the velocity gradient
//   grad v_i = sum_j m_j / rho_j (v_j - v_i) (x) (C_i grad_i W_ij),  C_i = (sum_j m_j / rho_j (x_j - x_i) (x) grad_i W_ij)^-1
// (the correction makes it exact for linear velocity fields); the momentum equation takes
// sigma_i / rho_i^2 + sigma_j / rho_j^2 in place of the pressures, and the energy equation takes the
// work of particle i's own stress in the same discrete form, -sum_j m_j v_ij . (S_i / rho_i^2 grad_i W_ij)
// (plus half the artificial stress's pair work), so that kinetic plus internal energy is conserved to
// the time integration (the continuum form S_i : eps'_i / rho_i with the corrected gradient is not the
// discrete momentum equation's work: on the Taylor bar it gained 17 % of the energy at 3 particles per
// radius, this form loses 2e-4).
//
// The energy equation gives each particle the work of its own pressure and stress (Monaghan 1992,
// eq. 2.24 form): with the symmetric momentum equation, sum_i m_i (v_i . a_i + de_i/dt) = 0 pair by
// pair, exactly as with the split form 1/2 (p_i / rho_i^2 + p_j / rho_j^2), but a cold particle next to
// a hot one is not cooled by its neighbour's pressure (the split form drives it to negative energy
// at the edge of a point explosion).
// In 2D the deviator is taken with 1/3 (plane strain), as Gray et al. do.
// Artificial stress (optional): each particle's tension R_i = U diag(-0.2 max(sigma_A, 0) / rho^2) U^T
// from the principal stresses sigma_A (U its eigenvectors), added to the pair as
// (R_i + R_j) (W(r_ij) / W(dx))^4 against the tensile instability. The sound speed is then
// c^2 = c_eos^2 + 4 mu / (3 rho). Plasticity (yield_strength Y0 > 0): von Mises, the deviator scaled
// back to sqrt(3/2 S:S) <= Y0 + H eps_p after every update (Wilkins 1964, Methods Comput. Phys. 3:211),
// eps_p the equivalent plastic strain, H the linear hardening modulus.
// XSPH (xsph = epsilon > 0; Monaghan 1989, J. Comput. Phys. 82:1): particles drift with
// v_i + epsilon sum_j m_j / rho_ij (v_j - v_i) W_ij, the velocity smoothed over the neighbours.
//
// Time stepping: leapfrog kick-drift-kick (Springel 2005, MNRAS 364:1105) on v, rho, e and S, the
// rates re-evaluated once per step at the drifted positions with the predicted state, and the
// step dt = CFL min_i h / (c_i + |v_i|) with CFL = 0.2 (with self-gravity also CFL sqrt(h_i / |a_i|)).
//
// Variable smoothing lengths (smoothing_length_factor eta > 0): h_i = eta (m_i / rho_i)^(1/Dim) at every
// evaluation, pairs with h_ij = (h_i + h_j) / 2 from the k-d tree (libsph/core/kd_tree.hpp); the grad-h
// terms are left out, so energy is conserved only to their size. Self-gravity (3D): Barnes-Hut with
// the M4-matched softening at h_i (libsph/impact/gravity.hpp).
//
// Damage (Grady-Kipp, libsph/impact/damage.hpp): D^(1/3) is kicked with the step like the other
// state; the pressure in tension and the deviator are carried reduced, p' = (1 - D) p for p < 0 and
// (1 - D) S, and Drucker-Prager's yield strength moves from the intact to the damaged branch with D.
//
// Numerical failure (a density or internal energy that is not positive where the equation of state
// needs it, a non-finite velocity, a stable step fallen below 1e-6 of the initial one) stops the run
// with a NumericalFailure naming particle and time.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "libsph/core/kd_tree.hpp"
#include "libsph/core/kernels.hpp"
#include "libsph/core/neighbour_relation.hpp"
#include "libsph/core/particles.hpp"
#include "libsph/core/time_stepper.hpp"
#include "libsph/core/state_archive.hpp"
#include "libsph/impact/damage.hpp"
#include "libsph/impact/gravity.hpp"
#include "libsph/impact/porosity.hpp"
#include "libsph/impact/tillotson.hpp"

namespace sph {

/// p = (gamma - 1) rho e, c = sqrt(gamma p / rho).
struct IdealGas {
  double gamma = 1.4;
};

/// p = c0^2 (rho - rho0), c = c0: a weakly compressible solid or liquid (Gray, Monaghan & Swift 2001).
struct LinearPressure {
  double reference_density = 1, sound_speed = 1;
};

/// A porous material over a Tillotson matrix: p = p_s(alpha rho, e) / alpha with the distension
/// alpha following the p-alpha crush curve, never increasing (libsph/impact/porosity.hpp).
struct PorousTillotson {
  TillotsonParameters matrix;
  PAlphaParameters porosity;
};

using ImpactEquationOfState = std::variant<IdealGas, LinearPressure, TillotsonParameters, PorousTillotson>;

enum class YieldModel { von_mises, drucker_prager };

/// Grady-Kipp damage (libsph/impact/damage.hpp): flaws drawn per particle from the Weibull law with
/// this seed when the body is initialised.
struct DamageSettings {
  WeibullParameters weibull;
  std::uint64_t seed = 1;
  Real youngs_modulus = 0;  ///< E of the strain sigma_max / ((1 - D) E)
};

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
    Real shear_modulus = 0;                        ///< mu; 0: no strength (a gas or liquid)
    bool artificial_stress = false;                ///< Gray, Monaghan & Swift 2001 (needs strength)
    Real artificial_stress_factor = Real(0.2);     ///< epsilon of R = -epsilon sigma_A / rho^2
    Real artificial_stress_exponent = 4;           ///< n of (W(r) / W(dx))^n
    Real particle_spacing = 0;                     ///< dx of W(dx) (artificial stress)
    Real yield_strength = 0;                       ///< von Mises Y0; 0: elastic
    Real hardening_modulus = 0;                    ///< H of Y = Y0 + H eps_p (linear isotropic hardening)
    YieldModel yield_model = YieldModel::von_mises;  ///< with Drucker-Prager, yield_strength is the cohesion Y0
    Real yield_limit = 0;                          ///< Drucker-Prager: the strength limit Y_m
    Real internal_friction = 0, damaged_friction = 0;  ///< Drucker-Prager: mu_i, mu_d
    std::optional<DamageSettings> damage;          ///< Grady-Kipp damage (needs strength); none by default
    Real xsph = 0;                                 ///< XSPH factor (Monaghan 1989; 0.5 in the impact codes, 0: off)
    /// eta > 0: variable smoothing lengths h_i = eta (m_i / rho_i)^(1/Dim) (1.2 for M4), neighbours by
    /// the k-d tree; 0: the constant smoothing_length (which is then also the initial h).
    Real smoothing_length_factor = 0;
    /// true: the density is the kernel sum rho_i = sum_j m_j W_ij (self included) at every evaluation,
    /// for gases (an expanding hot spot's density falls with its neighbours' distance); false: the
    /// continuity equation (solids, and gases whose edges must not lose density).
    bool density_summation = false;
    std::optional<GravitySettings> gravity;        ///< self-gravity by Barnes-Hut (3D); none by default
    /// > 0: one softening length for every particle (the force is then the exact gradient of the
    /// potential energy); 0: each particle's h (closer to the gas, but the softened potential changes
    /// with h without work, Price & Monaghan 2007).
    Real gravitational_softening = 0;
  };

  /// Registers mass, density, velocity, energy, pressure, sound_speed, acceleration, density_rate
  /// and energy_rate on `particles`. Throws std::invalid_argument for impossible settings.
  UpdatedLagrangianBody(ParticleSet<Dim>& particles, Settings settings);

  /// Sets mass = density x volume and evaluates the pressure, the sound speed and the rates: call
  /// once after the initial density, velocity and energy are set.
  void initialise();
  Real stable_time_step() const;
  /// The kick-drift-kick step from `time` by dt as a stage of named phases (docs/architecture.md), at
  /// the stable step:
  ///   kick and drift | neighbours | density and pressure | stress rates | forces | self-gravity | second kick
  /// the rates evaluated at the drifted positions with the state predicted to the full step.
  Stage stage(std::string name);
  /// One kick-drift-kick step from `time` by dt (the phases of `stage` in order).
  void advance(Real time, Real dt);

  // The phases of a step, in order (`stage` declares them).
  /// D^(1/3) and the fracture area a half step on; v, rho, e, S kicked to the half step with the old
  /// rates, x drifted by dt, the state predicted to the full step; stops on a state out of range or a
  /// particle that crossed its kernel support.
  void kick_and_drift(Real time, Real dt);
  /// The relation at the current positions (with variable h: h from the density first).
  void update_neighbours();
  /// The summation density (if chosen), then pressure and sound speed from the equation of state.
  void update_density_and_pressure();
  /// With strength: the corrected velocity gradient, the Jaumann stress rate and the artificial
  /// stress per particle; with damage: the damage and fracture-area rates.
  void compute_stress_rates();
  /// The pair sums: acceleration, density and energy rates, the XSPH correction.
  void compute_forces();
  /// Adds the self-gravity acceleration (a body without self-gravity: nothing).
  void add_self_gravity();
  /// Damage a half step on, the second kick with the new rates, the state check, the equation of
  /// state, and the check that the step has not collapsed.
  void second_kick(Real time, Real dt);
  /// Holds these particles at rest where they are (a clamp): they keep their state and still act on
  /// their neighbours.
  void hold(std::vector<Index> particles);

  struct Energies {
    double kinetic = 0, internal = 0, potential = 0;  ///< potential: 1/2 sum_i m_i phi_i (self-gravity)
    double total() const { return kinetic + internal + potential; }
  };
  Energies energies() const;

  FieldHandle<Real> mass_field() const { return mass_; }
  FieldHandle<Real> density_field() const { return density_; }
  FieldHandle<Vec<Dim>> velocity_field() const { return velocity_; }
  FieldHandle<Real> energy_field() const { return energy_; }
  FieldHandle<Real> pressure_field() const { return pressure_; }
  /// The deviatoric stress S (registered with strength only).
  FieldHandle<Mat<Dim>> deviatoric_stress_field() const { return deviatoric_stress_; }
  /// The equivalent plastic strain (registered with a yield strength only).
  FieldHandle<Real> plastic_strain_field() const { return plastic_strain_; }
  /// Each particle's h (registered with variable smoothing lengths only).
  FieldHandle<Real> smoothing_length_field() const { return smoothing_length_; }
  /// The gravitational potential phi_i (registered with self-gravity only).
  FieldHandle<Real> potential_field() const { return potential_; }
  /// The distension alpha >= 1 (registered with a porous equation of state only; starts at alpha0).
  FieldHandle<Real> distension_field() const { return distension_; }
  /// The scalar damage D in [0, 1] (registered with damage only).
  FieldHandle<Real> damage_field() const { return damage_; }
  const WeibullFlaws& flaws() const { return flaws_; }
  /// The Grady-Kipp fracture area per unit volume A_i (registered with damage only).
  FieldHandle<Real> fracture_area_field() const { return fracture_area_; }
  ParticleSet<Dim>& particles() { return particles_; }
  const Settings& settings() const { return settings_; }
  std::size_t steps() const { return steps_; }
  const InnerRelation<Dim>& relation() const { return relation_; }

  /// Saves or loads what changes besides the fields (checkpoints): the step count. The rates a step
  /// starts from are fields; the relation is rebuilt where they are evaluated.
  void checkpoint(StateArchive& archive) { archive.io("steps", steps_); }

 private:
  void update_equation_of_state();
  /// The rates at the current positions: update_neighbours ... add_self_gravity.
  void compute_rates();
  void check_state(Real time) const;
  Mat<Dim> yield(const Mat<Dim>& S, Real plastic_strain, Real pressure, Real damage, Real& plastic_increment) const;
  void kick_fracture_area(Real dt);
  /// The fields both kicks read and write, with D^(1/3) and the fracture area advanced by `half`
  /// (each kick takes half of the step's damage growth).
  struct KickViews {
    std::span<Vec<Dim>> v;
    std::span<Real> rho, e;
    std::span<const Vec<Dim>> a;
    std::span<const Real> drho, de, p;
    std::span<Mat<Dim>> S, dS;
    std::span<Real> eps_p, D;
    bool strength, plastic, summation;
  };
  KickViews kick_views(Real half);

  ParticleSet<Dim>& particles_;
  Settings settings_;
  InnerRelation<Dim> relation_;
  FieldHandle<Real> mass_, density_, energy_, pressure_, sound_speed_, density_rate_, energy_rate_;
  FieldHandle<Vec<Dim>> velocity_, acceleration_, xsph_correction_;  // the XSPH term of the drift
  FieldHandle<Mat<Dim>> deviatoric_stress_, stress_rate_;
  FieldHandle<Real> plastic_strain_, smoothing_length_, potential_, damage_, damage_rate_, damage_cap_, distension_;
  FieldHandle<Real> fracture_area_, fracture_area_rate_;
  WeibullFlaws flaws_;
  std::vector<Mat<Dim>> stress_;                  // the damaged stress -p' I + (1 - D) S
  std::vector<Real> radius_;                      // crack-growth radius of each particle
  KdTree<Dim> tree_;                              // neighbours with variable h
  std::unique_ptr<BarnesHutGravity> gravity_;
  std::vector<Real> gravity_h_;
  std::vector<Vec<Dim>> gravity_acceleration_;
  std::size_t steps_ = 0;
  Real initial_time_step_ = 0;  // a step below 1e-6 of it stops the run
  std::vector<Index> held_;
  std::vector<char> is_held_;
  std::vector<Vec<Dim>> v_half_;  // scratch of a step: the half-step state
  std::vector<Real> rho_half_, e_half_;
  std::vector<Mat<Dim>> s_half_, tension_;  // half-step deviatoric stress; artificial stress R_i
  std::vector<Real> eps_p_half_;              // plastic strain after the first kick
};

extern template class UpdatedLagrangianBody<2>;
extern template class UpdatedLagrangianBody<3>;

}  // namespace sph
