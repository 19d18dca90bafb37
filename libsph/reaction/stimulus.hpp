#pragma once
// A paced stimulus: pulses of `strength` (an applied dV/dt, I_stim / C_m, in the voltage unit per
// ms) lasting `duration` ms, starting at `start` and repeated every `period` ms, `count` times, and
// further pulses of the same duration and strength at `extra_onsets` (e.g. the S2 of an S1-S2
// protocol, or the blocks of a restitution protocol).
// Integrators take the stimulus as its average over their step, so the charge delivered is exact
// whatever the step and however the step straddles a pulse edge.

#include <algorithm>
#include <cmath>
#include <vector>

namespace sph {

struct StimulusProtocol {
  StimulusProtocol() = default;
  StimulusProtocol(double start_, double duration_, double strength_, double period_ = 0, int count_ = 1)
      : start(start_), duration(duration_), strength(strength_), period(period_), count(count_) {}

  double start = 0;     ///< onset of the first pulse [ms]
  double duration = 1;  ///< length of each pulse [ms]
  double strength = 0;  ///< applied dV/dt during a pulse [voltage unit / ms]
  double period = 0;    ///< time between pulse onsets [ms]; 0 with count 1
  int count = 1;        ///< number of pulses
  std::vector<double> extra_onsets;  ///< onsets of further pulses [ms]

  /// Every pulse onset, in order.
  std::vector<double> onsets() const {
    std::vector<double> all;
    for (int p = 0; p < count; ++p) all.push_back(start + p * period);
    all.insert(all.end(), extra_onsets.begin(), extra_onsets.end());
    std::sort(all.begin(), all.end());
    return all;
  }

  /// Mean applied rate over [t, t + dt] (the rate itself for dt = 0).
  double average(double t, double dt) const {
    double overlap = 0;
    auto pulse = [&](double a) {
      const double b = a + duration;
      if (dt <= 0) return t >= a && t < b;
      overlap += std::max(0.0, std::min(t + dt, b) - std::max(t, a));
      return false;
    };
    for (int p = 0; p < count; ++p)
      if (pulse(start + p * period)) return strength;
    for (double a : extra_onsets)
      if (pulse(a)) return strength;
    return dt > 0 ? strength * overlap / dt : 0;
  }

  /// Pulse onsets and ends in (t0, t1], in order: where an adaptive integrator must restart.
  std::vector<double> switching_times(double t0, double t1) const {
    std::vector<double> times;
    for (double a : onsets())
      for (double s : {a, a + duration})
        if (s > t0 && s <= t1) times.push_back(s);
    std::sort(times.begin(), times.end());
    return times;
  }
};

}  // namespace sph
