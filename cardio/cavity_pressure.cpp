#include "cardio/cavity_pressure.hpp"

#include <algorithm>
#include <cmath>

#include "libsph/io/parameters.hpp"

namespace cardio {

const std::vector<std::pair<std::string, CavityPressureMode>>& cavity_pressure_mode_names() {
  static const std::vector<std::pair<std::string, CavityPressureMode>> names{{"none", CavityPressureMode::none},
                                                                             {"constant", CavityPressureMode::constant},
                                                                             {"ramp", CavityPressureMode::ramp},
                                                                             {"circulation", CavityPressureMode::circulation}};
  return names;
}

void declare_parameters(sph::Parameters& p, CavityPressureSettings& s) {
  p.add_enum("cavity_pressure", s.mode, cavity_pressure_mode_names(),
             "endocardial pressure load: none, constant, ramped over pressure_ramp_time, or from the 0D circulation "
             "(circulation_model) after a preload ramped to lv_pressure and rv_pressure");
  p.add("lv_pressure", s.lv_pressure, "kPa",
        "LV cavity pressure (constant, ramp target, or the end-diastolic preload of the circulation)", sph::Range::any());
  p.add("rv_pressure", s.rv_pressure, "kPa", "RV cavity pressure (as lv_pressure)", sph::Range::any());
  p.add("pressure_ramp_time", s.ramp_time, "ms", "duration of the pressure ramp (the preload phase with the circulation)",
        sph::Range::non_negative());
}

double CavityPressure::at(double t) const {
  const double rise = ramp_ > 0 ? std::min(1.0, t / ramp_) : 1.0;
  switch (mode_) {
    case CavityPressureMode::none: return 0;
    case CavityPressureMode::constant:
    case CavityPressureMode::circulation: return value_;
    case CavityPressureMode::ramp: return value_ * rise;
  }
  return 0;
}

}  // namespace cardio
