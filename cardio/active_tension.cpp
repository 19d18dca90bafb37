#include "cardio/active_tension.hpp"

#include <algorithm>
#include <cmath>

#include "libsph/core/parallel.hpp"

namespace cardio {

template <int Dim>
ActiveTension<Dim>::ActiveTension(const sph::ParticleSet<Dim>& particles, sph::FieldHandle<Real> driver,
                                  ActiveTensionSettings settings)
    : particles_(particles), driver_(driver), settings_(settings), land_((settings.check(), settings.land)) {
  if (!driver_.valid())
    throw std::invalid_argument(settings_.model == TensionModel::land_2017
                                    ? "active tension (Land 2017): the cell model has no calcium (use ten Tusscher-Panfilov)"
                                    : "active tension: no potential field");
  const auto y = particles_.field(driver_);
  const std::size_t n = y.size();
  synced_driver_.assign(y.begin(), y.end());
  start_.assign(n, 0);
  end_.assign(n, 0);
  if (settings_.model == TensionModel::land_2017) {
    // Every cell starts from the steady state of its own resting calcium at lambda = 1 (cells at
    // the same calcium share it).
    states_.resize(n);
    double last_calcium = -1;
    Land2017::State rest{};
    for (std::size_t i = 0; i < n; ++i) {
      const double calcium = settings_.calcium_scale * double(y[i]);
      if (calcium != last_calcium) rest = land_.steady_state(calcium), last_calcium = calcium;
      states_[i] = rest;
      end_[i] = static_cast<Real>(land_.tension(rest, 1));
    }
    stretch_.assign(n, 1);
    previous_stretch_.assign(n, 1);
    if (settings_.velocity_dependence) stiffness_.assign(n, 0);
  }
}

template <int Dim>
void ActiveTension<Dim>::advance(Real time, Real dt) {
  const auto y = particles_.field(driver_);
  const ActiveTensionSettings& s = settings_;
  std::swap(start_, end_);
  if (s.model == TensionModel::land_2017) {
    const bool stiff = !stiffness_.empty();
    sph::parallel_for(particles_.n_owned(), [&](std::size_t i) {
      const double calcium = s.calcium_scale * 0.5 * (double(synced_driver_[i]) + double(y[i]));
      const double lambda = stretch_[i], change = double(stretch_[i]) - double(previous_stretch_[i]);
      // Where the last step ended: the tension the solid applied there (see the header).
      if (stiff) {
        const double applied = double(start_[i]) + double(stiffness_[i]) * change;
        start_[i] = static_cast<Real>(s.allow_negative ? applied : std::max(applied, 0.0));
      }
      land_.step(states_[i], calcium, lambda, s.velocity_dependence ? change / double(dt) : 0.0, double(dt));
      const auto& z = states_[i];
      double T = land_.tension(z, lambda);
      if (!s.allow_negative) T = std::max(T, 0.0);
      end_[i] = static_cast<Real>(T);
      if (stiff) stiffness_[i] = static_cast<Real>(land_.stretch_stiffness(z, lambda));
      synced_driver_[i] = y[i];
      previous_stretch_[i] = stretch_[i];
    });
  } else {
    sph::parallel_for(particles_.n_owned(), [&](std::size_t i) {
      const double mean = 0.5 * (double(synced_driver_[i]) + double(y[i]));
      const double target = s.k_a * (mean - s.rest_potential);
      double T = target + (double(start_[i]) - target) * std::exp(-s.rate(mean) * double(dt));
      if (!s.allow_negative) T = std::max(T, 0.0);
      end_[i] = static_cast<Real>(T);
      synced_driver_[i] = y[i];
    });
  }
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
