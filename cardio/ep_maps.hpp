#pragma once
// Per-particle maps of the action potential, followed step by step from the monodomain's potential
// before and after each splitting step [t, t + dt] (cardio/monodomain.hpp):
//
//  - latest_activation_time: the latest upward crossing of the activation threshold (linear
//    interpolation in the step); `activation_time` of the monodomain keeps the first one.
//  - apdNN (NN the repolarisation percentage, e.g. apd90): the latest complete action potential's
//    duration, from its activation to the downward crossing of V_peak - NN/100 (V_peak - V_rest),
//    V_rest the lowest V since the previous repolarisation and V_peak the highest V of the beat.
//    This is the tissue definition (activation to repolarisation, e.g. Taggart et al. 2000's
//    activation-recovery interval measured on V_m); a single cell's APD
//    (sph::measure_action_potential) starts at the upward crossing of the same level instead of the
//    threshold, which moves the start by a fraction of the upstroke (< 0.5 ms for ten
//    Tusscher-Panfilov).
//  - repolarisation_time, and diastolic_interval: from the previous repolarisation to the latest
//    activation (-1 before the second beat), the abscissa of a restitution curve.
//  - max_upstroke_velocity: the largest (V(t + dt) - V(t)) / dt over the latest beat's steps, the
//    dV/dt_max of the upstroke resolved at the splitting step (it underestimates the peak of a
//    sub-millisecond upstroke by the averaging over dt).
//  - beats: the number of complete action potentials.
// A particle is in a beat from its activation until its repolarisation; a second threshold crossing
// inside a beat (an early afterdepolarisation) does not start a new one.
//
// Conduction velocity is a map of the activation times: CV = 1 / |grad t_a|, with the corrected
// SPH gradient (libsph/core/correction_matrix.hpp) of `activation_time` over the reference
// relation, where the particle and all its neighbours are activated (-1 elsewhere). Where a
// stimulus activates a region at once, |grad t_a| is near zero and CV meaningless (very large).

#include <span>
#include <string>
#include <vector>

#include "libsph/core/neighbour_relation.hpp"
#include "libsph/core/particles.hpp"

namespace cardio {

using sph::Real;

template <int Dim>
class ActionPotentialMaps {
 public:
  /// Registers the fields on `particles`; `repolarisation_percent` in (0, 100).
  ActionPotentialMaps(sph::ParticleSet<Dim>& particles, Real repolarisation_percent, Real activation_threshold);

  /// Follows every particle over the step [time, time + dt] from V_before to V_after.
  void record(std::span<const Real> V_before, std::span<const Real> V_after, Real time, Real dt);

  Real repolarisation_percent() const { return percent_; }
  /// "apd90" for 90 %.
  const std::string& apd_name() const { return apd_name_; }
  sph::FieldHandle<Real> apd_field() const { return apd_; }
  sph::FieldHandle<Real> latest_activation_field() const { return latest_activation_; }
  sph::FieldHandle<Real> repolarisation_field() const { return repolarisation_; }
  sph::FieldHandle<Real> diastolic_interval_field() const { return diastolic_interval_; }
  sph::FieldHandle<Real> upstroke_velocity_field() const { return upstroke_velocity_; }
  sph::FieldHandle<Real> beats_field() const { return beats_; }

 private:
  sph::ParticleSet<Dim>& particles_;
  Real percent_, threshold_;
  std::string apd_name_;
  sph::FieldHandle<Real> apd_, latest_activation_, repolarisation_, diastolic_interval_, upstroke_velocity_, beats_;
  sph::FieldHandle<Real> peak_, rest_;  // of the current beat, not written
};

/// CV = 1 / |grad t_a| of the activation times `activation` (-1: not activated) over `relation`
/// (the inner relation of the positions the times were taken on), written into `velocity`; -1 where
/// the particle or one of its neighbours is not activated, or the gradient vanishes.
template <int Dim>
void conduction_velocity(const sph::NeighbourList<Dim>& relation, std::span<const Real> volume,
                         std::span<const Real> activation, std::span<Real> velocity);

extern template class ActionPotentialMaps<2>;
extern template class ActionPotentialMaps<3>;

}  // namespace cardio
