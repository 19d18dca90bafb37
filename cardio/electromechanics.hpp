#pragma once
// Excitation-contraction coupling on one particle set: the monodomain (transmembrane potential and
// gating states), the active tension T_a and the TLSPH solid (displacement, F, stress, fibre and
// sheet) all live on the same particles and the same reference-configuration inner relation.
//
// Three systems on one particle set, coupled by three interactions (libsph/core/interaction.hpp),
//   tension  <- monodomain  the active tension from the potential,
//   solid    <- tension     the active stress T_a f0 (x) f0,
//   monodomain <- solid     the conduction tensor pulled back through F,
// and one stage (libsph/core/time_stepper.hpp), a coupling step [t, t + dt] of K monodomain
// splitting steps, K the largest whole number of them that fit in the solid's stable step (at least
// one; shorter to land on output and event times):
//   1. electrophysiology: K splitting steps, each reaction, diffusion over the step (nested stage at
//      its own stability limit), reaction (cardio/monodomain.hpp);
//   2. active tension over [t, t + dt] from the potential (or calcium) before and after step 1
//      (cardio/active_tension.hpp) and, for the Land model, the fibre stretch of the solid's F of
//      the last mechanics sub-step;
//   3. mechanics over [t, t + dt], a nested stage at the acoustic step of the solid (re-evaluated
//      before every sub-step: one sub-step when K > 1, several when the solid's step is the shorter);
//      the sub-step from s to s + ds sees T_a interpolated linearly at its midpoint s + ds/2, where
//      position-based Verlet evaluates the stress.
// All three fields are therefore at t + dt together at the end of the step. With a physical density
// the solid's step (about 0.16 ms on the default heart) is shorter than two EP steps and K = 1; mass
// scaling of the solid (sph::SolidNumerics::mass_scaling) lengthens it, and the mechanics then runs
// once every K EP steps. The tension's time constant (1/eps >= 12.9 ms) is long against any such
// coupling step, so advancing it once per coupling step with the mean potential loses little. The conduction update
// is an event every `conduction_update_interval`, between steps.
//
// Conduction on the deforming tissue: the reference-configuration form of the monodomain. With the
// current-configuration tensor D = D_t I + (D_l - D_t) f (x) f along the deformed fibre
// f = F f0 / |F f0|, the pulled-back tensor is
//   D0 = F^-1 D F^-T = D_t C^-1 + (D_l - D_t) / I4f  f0 (x) f0,   C = F^T F, I4f = f0.C f0,
// and dV/dt = Div(D0 Grad V) + R in the reference configuration. (The exact pull-back of
// chi C_m dV/dt = div(sigma grad V) gives J^-1 Div(J D0 Grad V); the two differ by terms in
// Grad J, which vanish for the nearly incompressible myocardium, |J - 1| < 1 % here.) This keeps the
// fixed reference relation of the TLSPH solid: only the pair coefficients of the diffusion operator
// are reassembled from the current F, every `conduction_update_interval`, instead of a neighbour
// search and kernel gradients in the deformed configuration every step.

#include <cstddef>

#include "cardio/active_tension.hpp"
#include "cardio/monodomain.hpp"
#include "libsph/core/interaction.hpp"
#include "libsph/core/section_timers.hpp"
#include "libsph/core/time_stepper.hpp"
#include "libsph/solid/elastic_solid.hpp"

namespace cardio {

/// D0 = D_t C^-1 + (D_l - D_t) / I4f f0 (x) f0 for deformation F and reference fibre f0 (unit).
template <int Dim>
sph::Mat<Dim> pulled_back_conduction(const sph::Mat<Dim>& F, const sph::Vec<Dim>& f0, Real longitudinal, Real transverse) {
  const sph::Mat<Dim> C = F.transpose() * F;
  const Real I4f = f0.dot(C * f0);
  return transverse * C.inverse() + (longitudinal - transverse) / I4f * (f0 * f0.transpose());
}

// The three interactions of the myocardium (all on one particle set).

/// The active tension over [time, time + dt] from the monodomain's potential (the field the
/// tension was built on).
template <int Dim>
void interact(ActiveTension<Dim>& on, const Monodomain<Dim>& by, sph::SameParticles, Real time, Real dt);

/// The fibre stretch lambda = |F f0| of the solid for the tension's next step (Land 2017), from the
/// deformation gradient of the last mechanics sub-step.
template <int Dim>
void interact(ActiveTension<Dim>& on, const sph::ElasticSolid<Dim>& by, sph::SameParticles, Real time, Real dt);

/// The active stress of the solid over the sub-step [time, time + dt]: T_a of the last tension step
/// interpolated at the sub-step's midpoint into the solid's active tension field.
template <int Dim>
void interact(sph::ElasticSolid<Dim>& on, const ActiveTension<Dim>& by, sph::SameParticles, Real time, Real dt);

/// The conduction tensor of the monodomain pulled back through the solid's deformation gradient
/// (D0 above, with the monodomain's D_l, D_t and the solid's reference fibres), and the diffusion
/// operator reassembled. F must be current (ElasticSolid::update_deformation_gradient).
template <int Dim>
void interact(Monodomain<Dim>& on, const sph::ElasticSolid<Dim>& by, sph::SameParticles, Real time, Real dt);

struct ElectromechanicsSettings {
  bool deformed_conduction = true;      ///< pull the conduction tensor back through F (else D in the reference)
  Real conduction_update_interval = 2;  ///< [ms] between reassemblies of the diffusion operator
};

/// Declares the coupled step on `stepper`: the stage described above and, with deformed
/// conduction, the conduction update event. The parts are timed in `timers` under "active_tension",
/// "mechanics" (one call per sub-step) and "conduction_update" (one per update); the monodomain
/// times its reaction and diffusion itself (Monodomain::timings). The solid needs active stress and its fibre field must hold f0; the
/// monodomain needs its D_l and D_t. Everything passed must outlive the stepper.
template <int Dim>
void add_electromechanics(sph::TimeStepper& stepper, Monodomain<Dim>& monodomain, ActiveTension<Dim>& tension,
                          sph::ElasticSolid<Dim>& solid, const ElectromechanicsSettings& settings,
                          sph::SectionTimers& timers);

}  // namespace cardio
