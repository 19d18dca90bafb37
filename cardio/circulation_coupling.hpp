#pragma once
// The 0D circulation (cardio/circulation.hpp) coupled to the LV and RV cavities of a 3D heart
// (cardio/cavities.hpp), with the preload before it starts.
//
// Preload: over [0, start_time] the cavity pressures ramp to lv_pressure and rv_pressure over
// pressure_ramp_time and then hold (CavityPressure in ramp form, set after every coupling step for
// the next). At start_time the circulation starts (its time 0 is the first stimulus) with the
// coupled ventricles' blood volumes equal to the cavity volumes at those pressures; until then it
// follows the unloaded cavities (for its output). Afterwards, two interactions
// (libsph/core/interaction.hpp) after every coupling step [t, t + dt]:
//   circulation <- cavities   the circulation advances over the step with the new cavity volumes
//                             (V_3D linear over the step, cardio/circulation.hpp);
//   cavities <- circulation   each cavity takes the pressure of its ventricle, p_ref + (V_b - V) / C_c
//                             at its current volume, for the mechanics sub-steps of the next step.
// add_circulation_coupling declares both as the phases of a stage that follows the coupled step of
// the tissue, so they see the cavities at the end of that step.

#include <array>
#include <cstddef>

#include "cardio/cavities.hpp"
#include "cardio/circulation.hpp"
#include "libsph/core/time_stepper.hpp"

namespace cardio {

class CirculationCoupling {
 public:
  /// `settings` with both ventricles coupled (lv_mode and rv_mode are set here) and heart period
  /// `heart_period`; `preload` the ramp to the end-diastolic pressures; the circulation starts at
  /// `start_time` (at once if 0). Throws sph::ParameterError unless `cavities` has the LV and the RV
  /// endocardium. The cavities must outlive the coupling.
  CirculationCoupling(const CirculationSettings& settings, double heart_period, const CavityPressureSettings& preload,
                      double start_time, Cavities& cavities);

  /// The settings of the circulation that a coupling runs (both ventricles coupled, the period set).
  static CirculationSettings coupled_settings(CirculationSettings settings, double heart_period);
  /// Throws sph::ParameterError unless the cavities have both endocardia (before anything is written).
  static void require_cavities(const Cavities& cavities);

  /// The preload pressure of cavity c at time t [kPa].
  double preload_pressure(std::size_t c, double t) const;
  const Circulation& circulation() const { return circulation_; }
  Circulation& circulation() { return circulation_; }
  double start_time() const { return start_; }
  bool started() const { return started_; }
  /// True if the last coupling step advanced the circulation (not a preload step, nor its start).
  bool advanced() const { return advanced_; }
  std::size_t lv() const { return lv_; }
  std::size_t rv() const { return rv_; }
  /// The blood volume of the circulation when it started [mm^3].
  double initial_blood_volume() const { return initial_blood_; }
  /// Saves or loads the circulation and whether it started (checkpoints).
  void checkpoint(sph::StateArchive& archive);

  /// Preload step ending at t: the circulation starts at start_time, or follows the cavities.
  void preload_step(double t, const std::array<double, 2>& volumes);
  /// A coupled step over [t - dt, t]: the circulation advances to the new cavity volumes.
  void coupled_step(double t, double dt, const std::array<double, 2>& volumes);

 private:
  void start(const std::array<double, 2>& volumes, double lv_pressure, double rv_pressure);

  Circulation circulation_;
  CavityPressureSettings preload_;
  double start_;
  std::size_t lv_ = 0, rv_ = 1;
  std::array<double, 2> targets_{};  // preload pressure of the LV and the RV cavity
  bool started_ = false, advanced_ = false;
  double initial_blood_ = 0;
};

/// The circulation over the coupling step [time, time + dt] from the cavity volumes at its end,
/// time + dt (preload or coupled step, see above).
void interact(CirculationCoupling& on, const Cavities& by, sph::SameParticles, Real time, Real dt);
/// The cavity pressures after the circulation's step: the preload ramp at time + dt, or the
/// circulation's pressure and its volume penalty.
void interact(Cavities& on, const CirculationCoupling& by, sph::SameParticles, Real time, Real dt);

/// Declares the coupling on `stepper`: a stage "circulation" of the two interactions above, added
/// after the stages already declared (the tissue's coupled step), and, with a preload, the event
/// "end of preload" that ends a step at the start time. Both must outlive the stepper.
void add_circulation_coupling(sph::TimeStepper& stepper, CirculationCoupling& coupling, Cavities& cavities);

}  // namespace cardio
