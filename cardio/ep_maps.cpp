#include "cardio/ep_maps.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "libsph/core/correction_matrix.hpp"
#include "libsph/core/parallel.hpp"

namespace cardio {

template <int Dim>
ActionPotentialMaps<Dim>::ActionPotentialMaps(sph::ParticleSet<Dim>& particles, Real repolarisation_percent,
                                              Real activation_threshold)
    : particles_(particles), percent_(repolarisation_percent), threshold_(activation_threshold) {
  if (!(repolarisation_percent > 0 && repolarisation_percent < 100))
    throw std::invalid_argument("action potential maps: the repolarisation percentage must lie in (0, 100), not " +
                                std::to_string(repolarisation_percent));
  const long rounded = std::lround(double(repolarisation_percent));
  apd_name_ = "apd" + (std::abs(double(repolarisation_percent) - double(rounded)) < 1e-9
                           ? std::to_string(rounded)
                           : std::to_string(double(repolarisation_percent)));
  apd_ = particles.template register_field<Real>(apd_name_, Real(-1));
  latest_activation_ = particles.template register_field<Real>("latest_activation_time", Real(-1));
  repolarisation_ = particles.template register_field<Real>("repolarisation_time", Real(-1));
  diastolic_interval_ = particles.template register_field<Real>("diastolic_interval", Real(-1));
  upstroke_velocity_ = particles.template register_field<Real>("max_upstroke_velocity", Real(0));
  beats_ = particles.template register_field<Real>("beats", Real(0));
  peak_ = particles.template register_field<Real>("beat_peak_potential", Real(0), false);
  rest_ = particles.template register_field<Real>("beat_rest_potential", std::numeric_limits<Real>::max(), false);
}

template <int Dim>
void ActionPotentialMaps<Dim>::record(std::span<const Real> V0, std::span<const Real> V1, Real time, Real dt) {
  auto apd = particles_.field(apd_);
  auto activation = particles_.field(latest_activation_);
  auto repolarisation = particles_.field(repolarisation_);
  auto diastolic = particles_.field(diastolic_interval_);
  auto upstroke = particles_.field(upstroke_velocity_);
  auto beats = particles_.field(beats_);
  auto peak = particles_.field(peak_);
  auto rest = particles_.field(rest_);
  const Real fraction = percent_ / 100;
  auto crossing = [&](std::size_t i, Real level) { return time + (level - V0[i]) / (V1[i] - V0[i]) * dt; };
  sph::parallel_for(V1.size(), [&](std::size_t i) {
    const bool in_beat = activation[i] >= 0 && activation[i] > repolarisation[i];
    const Real rate = (V1[i] - V0[i]) / dt;
    if (!in_beat) {
      rest[i] = std::min(rest[i], V0[i]);
      if (V0[i] < threshold_ && V1[i] >= threshold_) {
        activation[i] = crossing(i, threshold_);
        diastolic[i] = repolarisation[i] >= 0 ? activation[i] - repolarisation[i] : Real(-1);
        peak[i] = V1[i];
        upstroke[i] = rate;
      } else {
        rest[i] = std::min(rest[i], V1[i]);
      }
      return;
    }
    peak[i] = std::max(peak[i], V1[i]);
    upstroke[i] = std::max(upstroke[i], rate);
    const Real level = peak[i] - fraction * (peak[i] - rest[i]);
    if (V0[i] > level && V1[i] <= level) {
      repolarisation[i] = crossing(i, level);
      apd[i] = repolarisation[i] - activation[i];
      beats[i] += 1;
      rest[i] = V1[i];
    }
  });
}

template <int Dim>
void conduction_velocity(const sph::NeighbourList<Dim>& relation, std::span<const Real> volume,
                         std::span<const Real> activation, std::span<Real> velocity) {
  std::vector<sph::Mat<Dim>> correction(relation.n_targets());
  sph::compute_correction_matrix<Dim>(relation, volume, correction);
  sph::parallel_for(relation.n_targets(), [&](std::size_t i) {
    velocity[i] = -1;
    if (activation[i] < 0) return;
    sph::Vec<Dim> sum = sph::Vec<Dim>::Zero();
    for (const auto [k, j] : relation.row(i)) {
      if (activation[j] < 0) return;
      sum += volume[j] * (activation[j] - activation[i]) * relation.kernel_derivative[k] * relation.unit_vector[k];
    }
    const Real slowness = (correction[i] * sum).norm();
    if (slowness > 0) velocity[i] = 1 / slowness;
  });
}

template class ActionPotentialMaps<2>;
template class ActionPotentialMaps<3>;
template void conduction_velocity<2>(const sph::NeighbourList<2>&, std::span<const Real>, std::span<const Real>, std::span<Real>);
template void conduction_velocity<3>(const sph::NeighbourList<3>&, std::span<const Real>, std::span<const Real>, std::span<Real>);

}  // namespace cardio
