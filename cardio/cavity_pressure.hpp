#pragma once
// The pressure of a ventricular cavity on its endocardium: none, constant, ramped to a value, or a
// two-element Windkessel (Westerhof, Lankhaar & Westerhof 2009, Med. Biol. Eng. Comput. 47:131)
// whose pressure also rises from zero over the ramp time:
//   C dp/dt = Q - p / R,   Q = max(-dV/dt, 0),
// the outflow from the cavity through a valve that closes against backflow (filling draws nothing
// from the compliance), integrated exactly over each interval between two volume updates for the
// mean Q of that interval. The cavity sees p throughout (no separate filling pressure).

#include <string>
#include <utility>
#include <vector>

namespace sph {
class Parameters;
}

namespace cardio {

enum class CavityPressureMode { none, constant, ramp, windkessel };
/// The names of the modes as parameters take them.
const std::vector<std::pair<std::string, CavityPressureMode>>& cavity_pressure_mode_names();

struct CavityPressureSettings {
  CavityPressureMode mode = CavityPressureMode::none;
  double lv_pressure = 0, rv_pressure = 0;  ///< [kPa] constant value, ramp target or Windkessel start
  double ramp_time = 50;                    ///< [ms] a sudden load would shock the tissue
  /// Systemic values of an adult (Westerhof et al. 2009): R about 1 mmHg s/mL = 0.13 kPa ms/mm^3,
  /// C about 1.5 mL/mmHg = 11,000 mm^3/kPa (RC about 1.5 s).
  double resistance = 0.13;    ///< [kPa ms/mm^3]
  double compliance = 11000;   ///< [mm^3/kPa]
};

/// Declares cavity_pressure, lv_pressure, rv_pressure, pressure_ramp_time, windkessel_resistance
/// and windkessel_compliance.
void declare_parameters(sph::Parameters& p, CavityPressureSettings& settings);

class CavityPressure {
 public:
  /// `start` is the cavity's constant value, ramp target or Windkessel start [kPa].
  CavityPressure(const CavityPressureSettings& settings, double start)
      : mode_(settings.mode), value_(start), ramp_(settings.ramp_time), resistance_(settings.resistance),
        compliance_(settings.compliance), pressure_(start) {}

  /// The pressure at time t [kPa].
  double at(double t) const;
  /// Advances the Windkessel to time t with the cavity volume at t [mm^3] (no-op in the other modes).
  void update(double t, double volume);
  bool active() const { return mode_ != CavityPressureMode::none; }

 private:
  CavityPressureMode mode_;
  double value_, ramp_, resistance_, compliance_;
  double pressure_, last_volume_ = -1, last_time_ = 0;
};

}  // namespace cardio
