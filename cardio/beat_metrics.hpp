#pragma once
// The clinical measures of one ventricle over one beat, from its pressure-volume trace sampled at
// every coupling step:
//   EDV  end-diastolic volume, the largest volume of the beat; EDP the pressure there;
//   ESV  end-systolic volume, the smallest volume of the beat;
//   SV = EDV - ESV, EF = SV / EDV;
//   peak pressure, and dP/dt max and min: the steepest rise and fall of the pressure over differences
//   at least `window` apart (default 2 ms; the coupling step's pressure carries the penalty's
//   small-scale noise, which a difference over 0.1 ms would turn into dP/dt).

#include <algorithm>
#include <cmath>
#include <limits>

#include "libsph/core/state_archive.hpp"

namespace cardio {

struct BeatMeasures {
  double edv = 0, esv = 0, stroke_volume = 0, ejection_fraction = 0;  ///< [mm^3], [1]
  double edp = 0, peak_pressure = 0;                                  ///< [kPa]
  double dpdt_max = 0, dpdt_min = 0;                                  ///< [kPa/ms]
};

class BeatRecorder {
 public:
  explicit BeatRecorder(double window = 2) : window_(window) {}
  /// Adds the sample (t [ms], V [mm^3], p [kPa]).
  void add(double t, double volume, double pressure) {
    if (!has_last_) {
      last_t_ = t, last_p_ = pressure, has_last_ = true;
    } else if (t - last_t_ >= window_) {
      const double slope = (pressure - last_p_) / (t - last_t_);
      m_.dpdt_max = std::max(m_.dpdt_max, slope);
      m_.dpdt_min = std::min(m_.dpdt_min, slope);
      last_t_ = t, last_p_ = pressure;
    }
    if (count_ == 0 || volume > m_.edv) m_.edv = volume, m_.edp = pressure;
    if (count_ == 0 || volume < m_.esv) m_.esv = volume;
    m_.peak_pressure = count_ == 0 ? pressure : std::max(m_.peak_pressure, pressure);
    ++count_;
  }
  /// The measures of the samples since the last call (the next beat's dP/dt continues from the
  /// last difference point).
  BeatMeasures finish() {
    BeatMeasures m = m_;
    m.stroke_volume = m.edv - m.esv;
    m.ejection_fraction = m.edv > 0 ? m.stroke_volume / m.edv : 0;
    m_ = {};
    count_ = 0;
    return m;
  }
  long samples() const { return count_; }
  /// Saves or loads the measures of the beat so far (checkpoints).
  void checkpoint(sph::StateArchive& archive) {
    archive.io("measures", m_);
    archive.io("count", count_);
    archive.io("has_last", has_last_);
    archive.io("last_t", last_t_);
    archive.io("last_p", last_p_);
  }

 private:
  double window_;
  BeatMeasures m_;
  long count_ = 0;
  bool has_last_ = false;
  double last_t_ = 0, last_p_ = 0;
};

}  // namespace cardio
