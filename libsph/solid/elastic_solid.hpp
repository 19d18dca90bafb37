#pragma once
// An elastic solid in total-Lagrangian SPH (TLSPH). See docs/solid.md for the equations.
//
// Reference configuration X (the positions when the system is built): the inner relation and the
// kernel-correction matrix B0_i = ( - sum_j V_j X_ij (x) grad0 W_ij )^-1 are computed there once.
//   Deformation gradient  F_i = - sum_j V_j x_ij (x) (B0_i grad0 W_ij)      (exact for linear motion)
//   Momentum              rho0 dv_i/dt = sum_j V_j (P_i B0_i + P_j B0_j) grad0 W_ij + f_hg + f_load
//                         + rho0 g - rho0 c v                                (c: optional damping rate)
// with P = F S(F) from the material law (material_laws.hpp). The pair term is twice the
// inter-particle average 1/2 (P_i B0_i + P_j B0_j); with a full neighbourhood it is the corrected
// divergence of P (Vignjevic, Reveles & Campbell 2006; Zhang et al. 2021, CMAME 381:113847, eq. 25).
// With SolidNumerics::deformation_gradient = "quadratic", F_i = sum_j (x_j - x_i) (x) a_ij with the
// weights of a weighted least-squares fit on a quadratic basis (exact for quadratic motion, at free
// surfaces too), B0 = I, and the force is the derivative of sum_i V_i W(F_i):
// f_i = V_i P_i sum_j a_ij - sum_j V_j P_j a_ji (docs/solid.md).
// Hourglass control: the penalty force of Ganzenmueller 2015 (CMAME 286:87, eq. 20),
//   f_hg,i = alpha/2 sum_j V_i V_j W0_ij E / |X_ij|^2 (delta_ij^i + delta_ij^j) x_ij / |x_ij|,
//   delta_ij^i = (F_i X_ij - x_ij) . x_ij / |x_ij|,
// a pairwise antisymmetric force (momentum is conserved) that resists particle motion not
// described by the local F; E is the small-strain Young's modulus of the law, alpha = 0 disables it.
//
// Time integration: position-based Verlet (Zhang, Rezavand & Hu 2021, JCP 429:110028, sec. 3.3):
//   x += dt/2 v;  F(x), P(F), a;  v = (v + dt a) / (1 + c dt);  x += dt/2 v.
// The damping is implicit in v, so it is stable for any rate. A step is two passes over the pairs:
// F_i and, at once, P_i B0_i (only particle i's stress needs F_i), then the forces with the velocity
// update; the term P_i B0_i sum_j V_j grad0 W_ij of the momentum sum is taken out of the pair loop.
// Mass scaling (SolidNumerics::mass_scaling = s >= 1, quasi-static problems): the inertia is rho0 s,
//   rho0 s dv_i/dt = (forces above, with rho0 g) - rho0 s c v,
// which leaves every equilibrium unchanged and lets the acoustic step grow by sqrt(s); the kinetic
// energy is that of the scaled inertia, so its ratio to the strain energy measures what the
// scaling costs. Stable step (acoustic, sec. 3.3 there):
//   dt = cfl min( h / (c + max|v|), sqrt(h / max|a|) ),  c = sqrt(M / (rho0 s)),
// with M the larger of the small-strain P-wave modulus of the law and the largest current tangent
// modulus over the particles, M_i = max_e (dP/dF at F_i in the direction e (x) e) : (e (x) e) over the
// axes e = x, y, z and the fibre, by finite differences every `stiffness_update_interval` steps: the
// exponential laws stiffen many times over at large strain, and a step sized by the small-strain
// modulus alone then loses stability (measured on the inflated LV of Land et al. 2015).
// `tangent_time_step = false` keeps M at the small-strain modulus (the rule of SPHinXsys, whose
// c0 = sqrt(K / rho0) is fixed): fewer steps where the strains stay moderate, without that guarantee.
//
// Pair viscosity (`artificial_viscosity` eta > 0; off by default): the numerical damping of the
// SPHinXsys solids (Zhang, Hu et al.; its Integration1stHalf), a pair stress along the mean F,
//   N_ij = eta (W_ij / W(0)) (F_i + F_j) / 2 * (rho0 s c h / 2) d^2 (x_ij . v_ij) / |X_ij|^2,
// added to P_i B_i + P_j B_j in the pair force (d the dimension, v at the start of the step). It
// damps the particle-scale motion that otherwise shrinks the acceleration-limited step in
// undamped runs, and leaves the equilibria unchanged (it vanishes with the velocities).
//
// Active stress (Nash & Panfilov 2004, Prog. Biophys. Mol. Biol. 85:501), with Settings::active_stress:
//   P = P_passive(F) + T_a F f0 (x) f0,   i.e. S = S_passive + T_a f0 (x) f0,
// a tension T_a [stress] per particle along the reference fibre f0 (field "active_tension", set by
// the caller: prescribed, or from the electrophysiology by cardio/active_tension.hpp). The active
// part derives from no stored energy, so energies() reports the passive strain energy only.
// With Settings::active_stiffness the tension also follows the fibre stretch within a step,
//   T = T_a + k_a (lambda - lambda_0),   lambda = |F f0|,
// with k_a and lambda_0 per particle (fields "active_stiffness", "active_reference_stretch", set by
// the caller): the instantaneous stiffness of attached crossbridges (cardio/active_tension.hpp),
// evaluated at every sub-step so that it needs no lag; k_a enters the tangent time step. With
// Settings::active_tension_non_negative the sum is kept >= 0: a tension model whose own T_a may not
// fall below zero (crossbridges pull, they do not push) would otherwise be driven below it by the
// linear term under fast shortening, and a compressive fibre stress with the small cross-fibre
// stiffness of the myocardium buckles the particle arrangement (docs/electromechanics.md).
//
// Fields it registers (written to output unless noted): velocity, displacement, jacobian (J),
// von_mises_stress, and for the anisotropic laws fibre_direction, sheet_direction and fibre_stretch;
// not written: reference_position, acceleration, deformation_gradient, correction_matrix and the
// stress P B0. Displacement, J, von Mises and fibre stretch are filled by update_output_fields().
//
// Failure: if any particle gets a non-finite state or J <= 0 the step is undone (positions and
// velocities restored to the start of the step, the last good state) and NumericalFailure names
// the particle, its position, the time and the quantity.
//
// Distributed particle sets (libsph/core/distribution.hpp; the relation built on the set, owned
// targets): each rank integrates its owned particles and keeps the reference neighbours of its
// ghosts fixed, as the pair loops are one ring deep. Per step two halo exchanges: the mid-step
// positions after the half drift (with the start velocities when the pair viscosity is on), and F
// with P B0 after the stress; the samplers (energies, output fields, residual) refresh the ghosts'
// positions first. Time step, tangent modulus, energies and J range are reduced over the ranks
// (sums in global-id order: the same as one rank's). Not on several ranks: the quadratic
// reconstruction (a_ji needs the ghosts' own neighbourhoods) and the clamp by reflection (a mirror
// may lie on another rank); both are refused there.

#include <array>
#include <functional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "libsph/core/neighbour_relation.hpp"
#include "libsph/core/particles.hpp"
#include "libsph/core/time_stepper.hpp"
#include "libsph/solid/material_laws.hpp"

namespace sph {

class Parameters;
template <int Dim>
struct GlobalParticle;

/// Zero-energy-mode control of SolidNumerics (parameter hourglass_control).
enum class HourglassControl { penalty, energy };
/// Reconstruction of F of SolidNumerics (parameter deformation_gradient).
enum class DeformationGradient { corrected, quadratic };
/// Integration of a particle's energy of SolidNumerics (parameter quadrature).
enum class Quadrature { nodal, gauss };
/// The parameter values of each choice, as add_enum takes them.
inline const std::vector<std::pair<std::string, HourglassControl>>& hourglass_control_names() {
  static const std::vector<std::pair<std::string, HourglassControl>> names{{"penalty", HourglassControl::penalty},
                                                                           {"energy", HourglassControl::energy}};
  return names;
}
inline const std::vector<std::pair<std::string, DeformationGradient>>& deformation_gradient_names() {
  static const std::vector<std::pair<std::string, DeformationGradient>> names{{"corrected", DeformationGradient::corrected},
                                                                              {"quadratic", DeformationGradient::quadratic}};
  return names;
}
inline const std::vector<std::pair<std::string, Quadrature>>& quadrature_names() {
  static const std::vector<std::pair<std::string, Quadrature>> names{{"nodal", Quadrature::nodal}, {"gauss", Quadrature::gauss}};
  return names;
}

/// The numerical choices of a TLSPH solid (independent of the dimension). Scenes bind these members
/// directly as parameters through declare_parameters.
struct SolidNumerics {
  Real hourglass_coefficient = Real(0.1);  ///< alpha of the penalty force; 0 turns it off
  Real artificial_viscosity = 0;           ///< eta of the pair viscosity; 0 turns it off
  Real cfl = Real(0.6);                    ///< fraction of the acoustic step, in (0, 1]
  Real fixed_time_step = 0;                ///< > 0 replaces the stable step (no stability guarantee)
  int stiffness_update_interval = 10;      ///< steps between updates of the current tangent modulus
  bool tangent_time_step = true;           ///< false: size the step by the small-strain modulus only
  /// s >= 1: the inertia is rho0 s (loads and body force keep their physical size), for quasi-static
  /// problems where inertia only slows the approach to equilibrium; the acoustic step grows by sqrt(s).
  Real mass_scaling = 1;
  /// Zero-energy-mode control with alpha = hourglass_coefficient: "penalty" (Ganzenmueller's force,
  /// not derived from an energy) or "energy" (the derivative of a quadratic energy in the same
  /// defects: conservative); see docs/solid.md.
  HourglassControl hourglass_control = HourglassControl::penalty;
  /// How F is reconstructed from the positions: "corrected" (the kernel-corrected gradient, exact for
  /// linear motion) or "quadratic" (weighted least squares on a quadratic basis, exact for quadratic
  /// motion at free surfaces too); see docs/solid.md.
  DeformationGradient deformation_gradient = DeformationGradient::corrected;
  /// How the energy of a particle's cell is integrated: "nodal" (V_i W(F_i), the midpoint rule) or
  /// "gauss" (Dim + 1 Gauss points in the cell, F continued linearly by the gradient of F that the
  /// quadratic reconstruction gives; needs deformation_gradient = "quadratic"); see docs/solid.md.
  Quadrature quadrature = Quadrature::nodal;
};

/// Declares hourglass_coefficient, artificial_viscosity, acoustic_cfl, tangent_time_step, mass_scaling and
/// fixed_time_step [time_unit].
void declare_parameters(Parameters& p, SolidNumerics& numerics, const std::string& time_unit);

template <int Dim>
class ElasticSolid {
 public:
  struct Settings {
    MaterialLaw<Dim> material;
    Real density = 1;                ///< rho0 [mass/length^3]
    Real damping_rate = 0;           ///< c [1/time] of dv/dt = ... - c v (quasi-static runs); 0 = none
    Vec<Dim> body_force = Vec<Dim>::Zero();  ///< g [length/time^2]
    SolidNumerics numerics;                  ///< hourglass control and time step
    Vec<Dim> fibre = Vec<Dim>::UnitX();      ///< initial (uniform) fibre direction, anisotropic laws
    Vec<Dim> sheet = Vec<Dim>::UnitY();      ///< initial (uniform) sheet direction
    bool active_stress = false;              ///< add T_a f0 (x) f0 to S (anisotropic laws only)
    /// With active_stress: T_a + k_a (lambda - lambda_0) in place of T_a, lambda = |F f0| (see above).
    bool active_stiffness = false;
    /// With active_stiffness: max(0, T_a + k_a (lambda - lambda_0)), a tension that does not push
    /// (see above).
    bool active_tension_non_negative = false;
  };

  using Motion = std::function<Vec<Dim>(const Vec<Dim>& reference, Real time)>;

  struct Energies {
    double kinetic = 0, strain = 0;
    double hourglass = 0;  ///< the stored energy of hourglass_control = "energy" (0 otherwise)
    Real min_jacobian = 1, max_jacobian = 1;
    double total() const { return kinetic + strain + hourglass; }
  };

  /// The relation must be the inner relation of `particles` built at the current positions (the
  /// reference configuration) and must outlive the system.
  ElasticSolid(ParticleSet<Dim>& particles, const InnerRelation<Dim>& relation, Settings settings);

  // Boundary conditions (may be combined; applied in the order clamp, slide, prescribed motion).
  /// Particles held at their reference positions with zero velocity.
  void clamp(std::vector<Index> particles);
  /// Particles held at zero displacement on the far side of the clamp face, the plane through
  /// `point` with normal `normal`, by odd reflection: a clamped particle next to free ones moves
  /// with u(X) = -u(X'), X' its mirror image in the face (which must be a particle, as on a lattice
  /// whose face lies half-way between layers). The reconstruction of F near the face then sees the
  /// smooth extension of the displacement instead of its kink. These particles store no strain
  /// energy and no kinetic energy; the force on a reflected particle acts, reversed, on its mirror
  /// (the derivative of the energy through u(X) = -u(X')).
  void clamp_by_reflection(std::vector<Index> particles, const Vec<Dim>& point, const Vec<Dim>& normal);
  /// Particles whose `component` of position stays at its reference value (sliding support).
  void slide(std::vector<Index> particles, int component);
  /// Particles moved along x = position(X, t), v = velocity(X, t).
  void prescribe_motion(std::vector<Index> particles, Motion position, Motion velocity);
  /// Follower pressure on surface particles: f_i = - p(t) J F^-T N_i A_i (Nanson's formula), with
  /// area_normal[k] = N A, the outward unit normal times the area of surface particle k in the
  /// reference configuration; p > 0 pushes into the body.
  void add_pressure_load(std::vector<Index> particles, std::vector<Vec<Dim>> area_normal,
                         std::function<Real(Real time)> pressure);
  /// Dead traction (force per reference area, fixed direction) on surface particles of areas A_k.
  void add_traction_load(std::vector<Index> particles, std::vector<Real> area,
                         std::function<Vec<Dim>(Real time)> traction);

  /// Imposes the boundary conditions on the current positions and velocities (as a step does), e.g.
  /// after setting a state by hand.
  void apply_constraints(Real time) {
    apply_position_constraints(time);
    apply_velocity_constraints(time);
  }
  /// The step from `time` by dt as a stage of named phases (docs/architecture.md), at the stable step:
  ///   half drift | deformation and stress | [loads on '<particles>'] | kick and drift
  /// Couplings that load the solid (libsph/core/interaction.hpp) fill the slot loads_slot(): at the
  /// mid-step positions, with F and the stress current, each adds its force on every particle to
  /// external_force_field().
  Stage stage(std::string name);
  std::string loads_slot() const { return "loads on '" + particles_.name() + "'"; }
  /// The force per particle [force] that the couplings in the loads slot add to; zeroed by the phase
  /// "deformation and stress" of every step. Registered on first call (field "external_force", not
  /// written); a solid without it has no external forces.
  FieldHandle<Vec<Dim>> external_force_field();

  // The phases of a step from `time` by dt, in order (`stage` declares them; `advance` runs them).
  /// x += dt/2 v (the start of the step is kept as the last good state), constraints at mid-step.
  void half_drift(Real time, Real dt);
  /// F and the stress at the mid-step positions (a failure undoes the step); the external force zeroed.
  void deformation_and_stress(Real time, Real dt);
  /// The accelerations (internal force, loads, external force, body force), v += dt a with the
  /// damping, velocity constraints at the end, x += dt/2 v and the position constraints.
  void kick_and_drift(Real time, Real dt);
  /// One position-based Verlet step from `time` by dt with no coupling between the phases.
  void advance(Real time, Real dt) {
    half_drift(time, dt);
    deformation_and_stress(time, dt);
    kick_and_drift(time, dt);
  }
  /// Stable step from the acoustic and acceleration criteria (see above), or the fixed step if set.
  Real stable_time_step() const;

  /// Recomputes F at the current positions (deformation_gradient_field()).
  void update_deformation_gradient() { compute_deformation_gradient(); }
  /// Recomputes F at the current positions and fills displacement, J, von Mises stress and fibre stretch.
  void update_output_fields();
  /// Saves or loads what changes besides the particle fields (checkpoints): the step count, the
  /// current sound speed, the largest acceleration, the last good state and the load accelerations.
  void checkpoint(StateArchive& archive) {
    archive.io("steps", steps_);
    archive.io("current_sound_speed", current_sound_speed_);
    archive.io("max_acceleration", max_acceleration_);
    archive.io("previous_position", previous_position_);
    archive.io("previous_velocity", previous_velocity_);
    archive.io("load_acceleration", load_acceleration_);
  }
  /// Kinetic energy sum 1/2 m v^2, strain energy sum V0 W(F) and the range of J at the current positions.
  Energies energies();
  /// Equilibrium check of a (quasi-)static state: the l2 norms over the unconstrained particles of
  /// the net nodal force V_i rho0 a_i (stress, hourglass, loads and body force; no damping) and of
  /// the part of it from the active stress alone, at the current positions and `time`.
  /// `load` is the l2 norm of the loads and the body force on the same particles. The couplings'
  /// external force enters as the last step's loads slot left it (the slot runs inside a step).
  struct Residual {
    double net = 0, active = 0, load = 0;
  };
  Residual equilibrium_residual(Real time);
  /// Zero-energy-mode measure: the mean over pairs of |F_i X_ij - x_ij| / |X_ij| at the current positions.
  double hourglass_measure();

  FieldHandle<Vec<Dim>> velocity_field() const { return velocity_; }
  /// The acceleration of the last step or equilibrium_residual (internal, hourglass and load forces,
  /// body force; damping excluded; constrained particles included).
  FieldHandle<Vec<Dim>> acceleration_field() const { return acceleration_; }
  FieldHandle<Vec<Dim>> reference_position_field() const { return reference_position_; }
  FieldHandle<Vec<Dim>> fibre_field() const { return fibre_; }
  FieldHandle<Vec<Dim>> sheet_field() const { return sheet_; }
  FieldHandle<Mat<Dim>> deformation_gradient_field() const { return deformation_gradient_; }
  /// T_a per particle [stress]; valid with Settings::active_stress only.
  FieldHandle<Real> active_tension_field() const { return active_tension_; }
  /// k_a and lambda_0 per particle; valid with Settings::active_stiffness only.
  FieldHandle<Real> active_stiffness_field() const { return active_stiffness_; }
  FieldHandle<Real> active_reference_stretch_field() const { return active_reference_stretch_; }
  /// Cauchy stress of particle i from its current F (after update_output_fields or a step).
  Mat<Dim> cauchy_stress_of(std::size_t i) const;
  /// Small-strain sound speed c0 = sqrt(M / rho0) of the law.
  Real sound_speed() const { return sound_speed_; }
  /// Sound speed from the current tangent modulus (>= sound_speed()).
  Real current_sound_speed() const { return current_sound_speed_; }
  const Settings& settings() const { return settings_; }
  ParticleSet<Dim>& particles() { return particles_; }
  const ParticleSet<Dim>& particles() const { return particles_; }

 private:
  struct PrescribedMotion {
    std::vector<Index> particles;
    Motion position, velocity;
  };
  struct PressureLoad {
    std::vector<Index> particles;
    std::vector<Vec<Dim>> area_normal;
    std::function<Real(Real)> pressure;
  };
  struct TractionLoad {
    std::vector<Index> particles;
    std::vector<Real> area;
    std::function<Vec<Dim>(Real)> traction;
  };

  /// The largest |a| and the first particle with a non-finite state (or n) of a force pass.
  struct StepCheck {
    Real max_acceleration = 0;
    std::size_t first_bad = 0;
  };

  void check_indices(const std::vector<Index>& particles, const char* what) const;
  void compute_deformation_gradient();
  /// F_i; with hourglass_sum, also S_i = sum_j V_j W_ij / r0^2 x_ij (x) X_ij in the same pass over
  /// the pairs, so that H_i = F_i M_i - S_i (hourglass_moment_) needs no pass of its own.
  Mat<Dim> deformation_gradient_of(std::size_t i, std::span<const Vec<Dim>> x, std::span<const Real> V,
                                   std::span<const Mat<Dim>> B, Mat<Dim>* hourglass_sum = nullptr) const;
  /// F and the stress P B0 of every particle in one pass; the first particle with an invalid F, or n.
  std::size_t compute_deformation_and_stress();
  std::span<const Vec<Dim>> anisotropic_field(FieldHandle<Vec<Dim>> handle) const {
    return handle.valid() ? std::span<const Vec<Dim>>(particles_.field(handle)) : std::span<const Vec<Dim>>();
  }
  void update_current_sound_speed();
  enum HourglassMode { no_hourglass = 0, penalty_hourglass = 1, energy_hourglass = 2 };
  template <bool Quadratic, int Hourglass, bool Viscous>
  Vec<Dim> internal_force_of(std::size_t i, std::span<const Vec<Dim>> x, std::span<const Real> V,
                             std::span<const Mat<Dim>> F, std::span<const Mat<Dim>> PB) const;
  void compute_load_accelerations(Real time);
  template <class Finish>
  StepCheck accelerations(Real time, Finish&& finish);
  void compute_acceleration(Real time);
  void apply_position_constraints(Real time);
  void apply_velocity_constraints(Real time);
  /// Undoes the step on every rank and throws NumericalFailure naming the particle (its global id).
  [[noreturn]] void fail(const GlobalParticle<Dim>& particle, Real time, const std::string& quantity, const std::string& problem);

  // The reference geometry of each pair of the relation (same order), in single precision, without
  // the neighbour's volume (so that the pair terms stay exactly antisymmetric): grad0 W_ij =
  // dW/dr(r0) e_ij, the hourglass weight W_ij / r0^2 and X_ij = r0 e_ij. 28 bytes a pair, read in
  // place of the relation's 52 bytes of cached kernel data.
  using PairReal = float;
  using PairVector = Eigen::Matrix<PairReal, Dim, 1>;
  struct PairGradient {
    PairReal gradient[Dim];
    PairReal hourglass_weight;
    Eigen::Map<const Eigen::Matrix<PairReal, Dim, 1>> vector() const { return Eigen::Map<const Eigen::Matrix<PairReal, Dim, 1>>(gradient); }
  };

  ParticleSet<Dim>& particles_;
  const InnerRelation<Dim>& relation_;
  Settings settings_;
  std::vector<PairGradient> pair_gradient_;
  std::vector<PairVector> pair_offset_;
  /// Energy-based hourglass control: M_i = sum_j V_j W_ij / r0^2 X_ij (x) X_ij of the reference
  /// configuration, the part of H_i = sum_j V_j W_ij / r0^2 (F_i X_ij - x_ij) (x) X_ij = F_i M_i - S_i
  /// that does not change.
  std::vector<Mat<Dim>> hourglass_moment_;
  // The quadratic reconstruction (deformation_gradient = "quadratic"): F_i = sum_j (x_j - x_i) (x) a_ij
  // and the force of the energy sum_i V_i W(F_i), f_i = V_i P_i sum_j a_ij - sum_j V_j P_j a_ji, with
  // a_ij and a_ji stored per pair in the relation's order (single precision, the same numbers in F
  // and in the force, so momentum is conserved to round-off); a_sum_ = sum_j a_ij per particle. Empty
  // for "corrected". B0 is then the identity.
  struct PairWeights {
    PairVector a, reverse;  // a_ij and a_ji
  };
  /// The stress force per unit reference volume of particle i from the stresses PB (P B0, or P when quadratic).
  Vec<Dim> stress_divergence_of(std::size_t i, std::span<const Real> V, std::span<const Mat<Dim>> PB) const;
  std::vector<PairWeights> pair_weights_;
  std::vector<Vec<Dim>> a_sum_;
  // Gauss quadrature in the cells (quadrature = "gauss"): the gradient of F at i,
  // G_d,i = dF/dX_d = sum_j (x_j - x_i) (x) c_ij.col(d), from the second-derivative weights of the
  // quadratic fit, stored with their reverse c_ji per pair; c_sum_ = sum_j c_ij. At the Dim + 1 Gauss
  // points of the cell (edge cell_size_ = V_i^(1/Dim)), F_g = F_i + sum_d xi_gd G_d,i; the stress P_i
  // is then the mean of P(F_g) and gauss_moment_[i][d] = Q_d,i the mean of xi_gd P(F_g).
  using PairMatrix = Eigen::Matrix<PairReal, Dim, Dim>;
  struct PairCurvature {
    PairMatrix c, reverse;
  };
  std::vector<PairCurvature> pair_curvature_;
  std::vector<Mat<Dim>> c_sum_;
  std::vector<std::array<Mat<Dim>, Dim>> gauss_moment_;
  std::vector<Real> cell_size_;
  /// G_d,i (d = 0 .. Dim-1) at the positions x.
  std::array<Mat<Dim>, Dim> gradient_of_deformation(std::size_t i, std::span<const Vec<Dim>> x) const;
  /// The mean of W(F_g) over the Gauss points of particle i (quadrature = "gauss").
  template <class Law>
  Real cell_energy(std::size_t i, const Law& law, const Mat<Dim>& F_i, std::span<const Vec<Dim>> x) const;
  Real step_factor_ = 1;  // the acoustic step's factor for the reconstruction's stiffest mode
  void build_quadratic_reconstruction();
  Real sound_speed_ = 0, current_sound_speed_ = 0;
  Real hourglass_factor_ = 0;  // alpha E / 2
  bool energy_hourglass_ = false;
  Real viscosity_factor_ = 0;  // eta rho0 s c h d^2 / (4 W(0))
  Real inverse_inertia_ = 1;   // 1 / (rho0 s)
  std::size_t steps_ = 0;
  FieldHandle<Vec<Dim>> reference_position_, velocity_, acceleration_, displacement_, fibre_, sheet_;
  FieldHandle<Mat<Dim>> deformation_gradient_, correction_matrix_, stress_correction_;
  FieldHandle<Real> jacobian_, von_mises_, fibre_stretch_, active_tension_, active_stiffness_, active_reference_stretch_;

  std::vector<Index> clamped_;
  std::vector<std::pair<Index, Index>> reflected_;  // (clamped particle, its free mirror)
  std::vector<char> rigid_;                         // per particle: in a clamp by reflection (or empty)
  std::vector<Vec<Dim>> mirror_force_;              // scratch: reflected forces per unit volume of the mirror
  std::vector<std::pair<std::vector<Index>, int>> sliding_;
  std::vector<PrescribedMotion> prescribed_;
  std::vector<PressureLoad> pressure_loads_;
  std::vector<TractionLoad> traction_loads_;
  FieldHandle<Vec<Dim>> external_force_;     // of the couplings in the loads slot (or invalid)
  std::vector<Vec<Dim>> load_acceleration_;  // of all loads, per particle

  Real max_acceleration_ = 0;
  std::vector<Vec<Dim>> previous_position_, previous_velocity_;  // the last good state
};

extern template class ElasticSolid<2>;
extern template class ElasticSolid<3>;

}  // namespace sph
