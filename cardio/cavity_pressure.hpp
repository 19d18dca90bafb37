#pragma once
// The pressure of a ventricular cavity on its endocardium: none, constant, ramped to a value over
// the ramp time, or taken from a 0D circulation coupled to the cavity volumes (cardio/circulation.hpp;
// the scene owns the circulation and passes its pressure on, see set()).

#include <string>
#include <utility>
#include <vector>

#include "libsph/core/state_archive.hpp"

namespace sph {
class Parameters;
}

namespace cardio {

enum class CavityPressureMode { none, constant, ramp, circulation };
/// The names of the modes as parameters take them.
const std::vector<std::pair<std::string, CavityPressureMode>>& cavity_pressure_mode_names();

struct CavityPressureSettings {
  CavityPressureMode mode = CavityPressureMode::none;
  double lv_pressure = 0, rv_pressure = 0;  ///< [kPa] constant value or ramp target (circulation: preload)
  double ramp_time = 50;                    ///< [ms] a sudden load would shock the tissue
};

/// Declares cavity_pressure, lv_pressure, rv_pressure and pressure_ramp_time.
void declare_parameters(sph::Parameters& p, CavityPressureSettings& settings);

class CavityPressure {
 public:
  /// `target` is the cavity's constant value or ramp target [kPa].
  CavityPressure(const CavityPressureSettings& settings, double target)
      : mode_(settings.mode), value_(target), ramp_(settings.ramp_time) {}

  /// The pressure at time t [kPa]: in circulation mode the value last set.
  double at(double t) const;
  /// The pressure of the circulation (circulation mode).
  void set(double pressure) { value_ = pressure; }
  bool active() const { return mode_ != CavityPressureMode::none; }
  /// Saves or loads the value last set (checkpoints).
  void checkpoint(sph::StateArchive& archive) { archive.io("value", value_); }

 private:
  CavityPressureMode mode_;
  double value_, ramp_;
};

}  // namespace cardio
