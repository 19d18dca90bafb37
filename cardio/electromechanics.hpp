#pragma once
// Excitation-contraction coupling on one particle set: the monodomain (transmembrane potential and
// gating states), the active tension T_a and the TLSPH solid (displacement, F, stress, fibre and
// sheet) all live on the same particles and the same reference-configuration inner relation.
//
// Time stepping (multi-rate, exact time bookkeeping), one macro step [t, t + dt] of the size of the
// monodomain's splitting step (or shorter, to land on output and event times):
//   1. electrophysiology: reaction dt/2, diffusion over dt in sub-steps at its own stability limit,
//      reaction dt/2 (cardio/monodomain.hpp);
//   2. active tension over [t, t + dt] from the potential before and after step 1
//      (cardio/active_tension.hpp);
//   3. mechanics over [t, t + dt] in ceil(dt / dt_acoustic) equal sub-steps; the sub-step from s to
//      s + ds sees T_a interpolated linearly at its midpoint s + ds/2, where position-based Verlet
//      evaluates the stress.
// All three fields are therefore at t + dt together at the end of the macro step.
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

#include <functional>
#include <vector>

#include "cardio/active_tension.hpp"
#include "cardio/monodomain.hpp"
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

template <int Dim>
class Electromechanics {
 public:
  struct Settings {
    Real longitudinal_diffusivity = 0;   ///< D_l along the fibre [mm^2/ms]
    Real transverse_diffusivity = 0;     ///< D_t across it
    bool deformed_conduction = true;     ///< pull the conduction tensor back through F (else D in the reference)
    Real conduction_update_interval = 2; ///< [ms] between reassemblies of the diffusion operator
  };
  /// Seconds spent in each part.
  struct Timings {
    double reaction = 0, diffusion = 0, tension = 0, mechanics = 0, conduction = 0;
  };

  /// The three systems must share one particle set; the solid needs Settings::active_stress and
  /// its fibre field holds f0 (set before the first step).
  Electromechanics(Monodomain<Dim>& monodomain, ActiveTension<Dim>& tension, sph::ElasticSolid<Dim>& solid, Settings settings);

  /// Adds the stages to `stepper`: electrophysiology with the active tension (steps 1-2 above), then
  /// the sub-cycled mechanics (step 3).
  void add_stages(sph::TimeStepper& stepper);
  /// Reassembles the diffusion operator with D0 from the current F.
  void update_conduction();

  Timings timings() const;
  std::size_t mechanics_substeps() const { return mechanics_substeps_; }
  std::size_t conduction_updates() const { return conduction_updates_; }

 private:
  Monodomain<Dim>& monodomain_;
  ActiveTension<Dim>& tension_;
  sph::ElasticSolid<Dim>& solid_;
  Settings settings_;
  Timings own_;
  Real last_conduction_update_ = 0;
  std::size_t mechanics_substeps_ = 0, conduction_updates_ = 0;
};

extern template class Electromechanics<2>;
extern template class Electromechanics<3>;

}  // namespace cardio
