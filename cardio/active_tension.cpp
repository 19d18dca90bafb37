#include "cardio/active_tension.hpp"

#include <algorithm>
#include <cmath>

#include "libsph/core/parallel.hpp"

namespace cardio {

template <int Dim>
void ActiveTension<Dim>::advance(Real time, Real dt) {
  const auto V = particles_.field(potential_);
  const ActiveTensionSettings s = settings_;
  std::swap(start_, end_);
  sph::parallel_for(V.size(), [&](std::size_t i) {
    const double mean = 0.5 * (double(synced_potential_[i]) + double(V[i]));
    const double target = s.k_a * (mean - s.rest_potential);
    double T = target + (double(start_[i]) - target) * std::exp(-s.rate(mean) * double(dt));
    if (!s.allow_negative) T = std::max(T, 0.0);
    end_[i] = static_cast<Real>(T);
    synced_potential_[i] = V[i];
  });
  step_start_ = time;
  step_size_ = dt;
}

template <int Dim>
void ActiveTension<Dim>::interpolate(Real fraction, std::span<Real> tension) const {
  const Real w = std::clamp(fraction, Real(0), Real(1));
  sph::parallel_for(tension.size(), [&](std::size_t i) { tension[i] = start_[i] + w * (end_[i] - start_[i]); });
}

template class ActiveTension<2>;
template class ActiveTension<3>;

}  // namespace cardio
