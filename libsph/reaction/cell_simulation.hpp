#pragma once
// One cell under a stimulus protocol with a fixed step, and the measures of its action potential.

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

#include "libsph/core/sampled_series.hpp"
#include "libsph/reaction/cell_integrators.hpp"
#include "libsph/reaction/stimulus.hpp"

namespace sph {

/// Steps the cell from its resting state to end_time with steps of dt (the last one shortened to
/// land on end_time), calling record(t, y) at t = 0 and after every step. Returns false, and stops,
/// as soon as the state leaves the model's valid range or becomes non-finite (an unstable scheme).
template <ReactionModel M, class Record>
bool simulate_cell(const M& model, ReactionScheme scheme, double dt, const StimulusProtocol& stimulus, double end_time,
                   Record&& record) {
  auto y = model.initial_state();
  const VoltageRange range = model.valid_voltage();
  record(0.0, y);
  const auto steps = static_cast<long>(std::ceil(end_time / dt - 1e-9));
  for (long s = 0; s < steps; ++s) {
    const double t = s * dt, t_next = s + 1 == steps ? end_time : (s + 1) * dt;
    advance_cell(model, y, stimulus.average(t, t_next - t), t_next - t, scheme);
    for (double v : y)
      if (!std::isfinite(v)) return false;
    if (!(y[0] >= range.lower && y[0] <= range.upper)) return false;
    record(t_next, y);
  }
  return true;
}

/// Action potential measures of a sampled trace V(t) within [window_start, window_end).
struct ActionPotential {
  double resting = 0;     ///< V at the last sample at or before the window start
  double peak = 0;        ///< largest V in the window
  double upstroke = -1;   ///< time V first rises through the repolarisation level
  double repolarised = -1;  ///< time V first falls back through it after the peak
  /// Duration at the given repolarisation fraction (APD90 for 0.9), or -1 if incomplete.
  double duration() const { return upstroke >= 0 && repolarised >= 0 ? repolarised - upstroke : -1; }
};

/// APD at `fraction` repolarisation: the level is V_peak - fraction (V_peak - V_rest), and the duration
/// runs from the upward to the downward crossing of that level (both linearly interpolated).
inline ActionPotential measure_action_potential(std::span<const double> t, std::span<const double> V,
                                                double window_start, double window_end, double fraction = 0.9) {
  ActionPotential ap;
  std::size_t first = 0, last = t.size();
  // The resting value is taken at or before the window start, never inside a stimulated step.
  while (first + 1 < t.size() && t[first + 1] <= window_start) ++first;
  while (last > first && t[last - 1] >= window_end) --last;
  if (last - first < 3) return ap;
  ap.resting = V[first];
  std::size_t peak_index = first;
  for (std::size_t i = first; i < last; ++i)
    if (V[i] > V[peak_index]) peak_index = i;
  ap.peak = V[peak_index];
  const double level = ap.peak - fraction * (ap.peak - ap.resting);
  auto crossing = [&](std::size_t i) { return t[i - 1] + (level - V[i - 1]) / (V[i] - V[i - 1]) * (t[i] - t[i - 1]); };
  for (std::size_t i = first + 1; i <= peak_index; ++i)
    if (V[i - 1] < level && V[i] >= level) {
      ap.upstroke = crossing(i);
      break;
    }
  for (std::size_t i = peak_index + 1; i < last; ++i)
    if (V[i - 1] > level && V[i] <= level) {
      ap.repolarised = crossing(i);
      break;
    }
  return ap;
}

}  // namespace sph
