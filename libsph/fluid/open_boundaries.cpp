#include "libsph/fluid/open_boundaries.hpp"

#include <stdexcept>

#include "libsph/core/parallel.hpp"

namespace sph {

template <int Dim>
InflowZone<Dim>::InflowZone(WeaklyCompressibleFluid<Dim>& fluid, Settings settings)
    : fluid_(fluid), settings_(std::move(settings)) {
  const std::string zone = "inflow of fluid '" + fluid_.particles().name() + "'";
  for (int d = 0; d < Dim; ++d)
    if (!(settings_.upper[d] > settings_.lower[d])) throw std::invalid_argument(zone + ": the buffer box is empty");
  if (!settings_.velocity) throw std::invalid_argument(zone + ": no velocity profile");
  const Real limit = fluid_.settings().equation_of_state.sound_speed / 10;
  if (!(settings_.mean_speed >= 0) || settings_.mean_speed > limit)
    throw std::invalid_argument(zone + ": the mean inflow speed " + std::to_string(settings_.mean_speed) +
                                " exceeds c0 / 10 = " + std::to_string(limit) +
                                " (weakly-compressible limit): raise the sound speed or lower the inflow");
  in_buffer_ = fluid_.particles().template register_field<Real>("in_inflow_buffer", Real(0), false);
  auto flag = fluid_.particles().field(in_buffer_);
  const auto& x = fluid_.particles().position;
  for (std::size_t i = 0; i < x.size(); ++i) flag[i] = inside(x[i]) ? Real(1) : Real(0);
}

template <int Dim>
bool InflowZone<Dim>::inside(const Vec<Dim>& x) const {
  for (int d = 0; d < Dim; ++d)
    if (!(x[d] >= settings_.lower[d] && x[d] < settings_.upper[d])) return false;
  return true;
}

template <int Dim>
void interact(WeaklyCompressibleFluid<Dim>& on, const InflowZone<Dim>& by, SameParticles, Real time, Real dt) {
  auto& particles = on.particles();
  auto v = particles.field(on.velocity_field());
  const auto& x = particles.position;
  const auto& velocity = by.settings().velocity;
  const Real end = time + dt;
  parallel_for(x.size(), [&](std::size_t i) {
    if (by.inside(x[i])) v[i] = velocity(x[i], end);
  });
}

template <int Dim>
std::size_t InflowZone<Dim>::emit() {
  if (!settings_.emit) return 0;
  auto& particles = fluid_.particles();
  auto flag = particles.field(in_buffer_);
  const Real length = settings_.upper[0] - settings_.lower[0];
  const std::size_t n = particles.n_particles();
  order_.resize(n);
  for (std::size_t i = 0; i < n; ++i) order_[i] = static_cast<Index>(i);
  std::vector<std::size_t> crossed;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& xi = particles.position[i];
    if (flag[i] > 0 && xi[0] >= settings_.upper[0]) crossed.push_back(i);
  }
  for (const std::size_t i : crossed) order_.push_back(static_cast<Index>(i));
  if (!crossed.empty()) {
    particles.select(order_);
    flag = particles.field(in_buffer_);
    for (std::size_t k = 0; k < crossed.size(); ++k) particles.position[n + k][0] -= length;
  }
  for (std::size_t i = 0; i < particles.n_particles(); ++i) flag[i] = inside(particles.position[i]) ? Real(1) : Real(0);
  emitted_ += crossed.size();
  return crossed.size();
}

template <int Dim>
std::size_t OutflowZone<Dim>::remove() {
  auto& particles = fluid_.particles();
  order_.clear();
  for (std::size_t i = 0; i < particles.n_particles(); ++i)
    if (!(particles.position[i][0] > outlet_)) order_.push_back(static_cast<Index>(i));
  const std::size_t gone = particles.n_particles() - order_.size();
  if (gone > 0) particles.select(order_);
  removed_ += gone;
  return gone;
}

template class InflowZone<2>;
template class InflowZone<3>;
template class OutflowZone<2>;
template class OutflowZone<3>;
template void interact<2>(WeaklyCompressibleFluid<2>&, const InflowZone<2>&, SameParticles, Real, Real);
template void interact<3>(WeaklyCompressibleFluid<3>&, const InflowZone<3>&, SameParticles, Real, Real);

}  // namespace sph
