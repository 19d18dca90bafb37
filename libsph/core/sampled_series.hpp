#pragma once
// Reading a sampled time series (t_k, y_k) between its samples.

#include <algorithm>
#include <cstddef>
#include <span>

namespace sph {

/// Linear interpolation of the samples (t_k, y_k) at time s (clamped to its ends); t increasing.
inline double interpolate_trace(std::span<const double> t, std::span<const double> y, double s) {
  if (s <= t.front()) return y.front();
  if (s >= t.back()) return y.back();
  const auto upper = static_cast<std::size_t>(std::upper_bound(t.begin(), t.end(), s) - t.begin());
  const double w = (s - t[upper - 1]) / (t[upper] - t[upper - 1]);
  return (1 - w) * y[upper - 1] + w * y[upper];
}

}  // namespace sph
