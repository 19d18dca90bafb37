#include "cardio/cavity_pressure.hpp"

#include <algorithm>
#include <cmath>

#include "libsph/io/parameters.hpp"

namespace cardio {

const std::vector<std::pair<std::string, CavityPressureMode>>& cavity_pressure_mode_names() {
  static const std::vector<std::pair<std::string, CavityPressureMode>> names{{"none", CavityPressureMode::none},
                                                                             {"constant", CavityPressureMode::constant},
                                                                             {"ramp", CavityPressureMode::ramp},
                                                                             {"windkessel", CavityPressureMode::windkessel}};
  return names;
}

void declare_parameters(sph::Parameters& p, CavityPressureSettings& s) {
  p.add_enum("cavity_pressure", s.mode, cavity_pressure_mode_names(),
             "endocardial pressure load: none, constant, ramped over pressure_ramp_time, or a two-element Windkessel "
             "(ramped in as well)");
  p.add("lv_pressure", s.lv_pressure, "kPa", "LV cavity pressure (constant, ramp target, or Windkessel start)", sph::Range::any());
  p.add("rv_pressure", s.rv_pressure, "kPa", "RV cavity pressure", sph::Range::any());
  p.add("pressure_ramp_time", s.ramp_time, "ms", "duration of the pressure ramp", sph::Range::non_negative());
  p.add("windkessel_resistance", s.resistance, "kPa ms/mm^3", "R of the Windkessel", sph::Range::positive());
  p.add("windkessel_compliance", s.compliance, "mm^3/kPa", "C of the Windkessel", sph::Range::positive());
}

double CavityPressure::at(double t) const {
  const double rise = ramp_ > 0 ? std::min(1.0, t / ramp_) : 1.0;
  switch (mode_) {
    case CavityPressureMode::none: return 0;
    case CavityPressureMode::constant: return value_;
    case CavityPressureMode::ramp: return value_ * rise;
    case CavityPressureMode::windkessel: return pressure_ * rise;
  }
  return 0;
}

void CavityPressure::update(double t, double volume) {
  if (mode_ == CavityPressureMode::windkessel && last_volume_ >= 0 && t > last_time_) {
    const double dt = t - last_time_, flow = std::max(0.0, -(volume - last_volume_) / dt);
    const double tau = resistance_ * compliance_, equilibrium = flow * resistance_;
    pressure_ = equilibrium + (pressure_ - equilibrium) * std::exp(-dt / tau);
  }
  last_volume_ = volume;
  last_time_ = t;
}

}  // namespace cardio
