#include "libsph/fluid/weakly_compressible_fluid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "libsph/core/correction_matrix.hpp"
#include "libsph/core/numerical_failure.hpp"
#include "libsph/core/parallel.hpp"
#include "libsph/core/particle_sorting.hpp"
#include "libsph/io/parameters.hpp"

namespace sph {

const std::vector<std::pair<std::string, FluidScheme>>& fluid_scheme_names() {
  static const std::vector<std::pair<std::string, FluidScheme>> names{
      {"riemann", FluidScheme::riemann}, {"pressure_diffusion", FluidScheme::pressure_diffusion}, {"plain", FluidScheme::plain},
      {"artificial_viscosity", FluidScheme::artificial_viscosity}};
  return names;
}

const std::vector<std::pair<std::string, DensityReinitialisation>>& density_reinitialisation_names() {
  static const std::vector<std::pair<std::string, DensityReinitialisation>> names{
      {"free_surface", DensityReinitialisation::free_surface},
      {"internal", DensityReinitialisation::internal},
      {"none", DensityReinitialisation::none}};
  return names;
}

void declare_parameters(Parameters& p, FluidNumerics& n) {
  p.add_enum("fluid_scheme", n.scheme, fluid_scheme_names(),
             "pair interaction: riemann (low-dissipation limiter, Zhang et al. 2017), pressure_diffusion (the Riemann "
             "pressure jump in the continuity equation only, unlimited: internal flows), plain (no dissipation) or "
             "artificial_viscosity (Monaghan 1992)");
  p.add("riemann_limiter", n.limiter_strength, "-", "eta of the low-dissipation limiter beta = min(eta du / c0, 1)",
        Range::non_negative());
  p.add("artificial_viscosity", n.artificial_viscosity, "-", "alpha of Monaghan's artificial viscosity",
        Range::non_negative());
  p.add("advection_cfl", n.advection_cfl, "-", "advection step as a fraction of h / max speed", {0, 1, true, false});
  p.add("acoustic_cfl", n.acoustic_cfl, "-", "acoustic step as a fraction of h / (c0 + max speed)", {0, 1, true, false});
  p.add_enum("density_reinitialisation", n.density_reinitialisation, density_reinitialisation_names(),
             "density from the particle number density at each advection step");
  p.add("transport_velocity", n.transport_velocity, "-",
        "kappa of the transport-velocity shift x -= 2 kappa h^2 grad sigma (internal flows; 0: off)", Range::non_negative());
  p.add("kernel_correction", n.kernel_correction,
        "pressure force through the corrected kernel gradient (Bonet & Lok 1999; internal flows, one MPI rank)");
  p.add("sort_interval", n.sort_interval, "-", "advection steps between re-sorts along the cell list (0: never)",
        Range::non_negative());
}

template <int Dim>
struct WeaklyCompressibleFluid<Dim>::WallContact {
  const FluidWall<Dim>* wall;
  ContactRelation<Dim> relation;
  bool record = false;
  std::vector<Vec<Dim>> pressure_pairs, viscous_pairs;  // force of each pair on the fluid particle
  // The relation transposed: the pair slots of each wall particle, in increasing fluid index.
  std::vector<std::size_t> wall_offsets, wall_slots;

  void transpose() {
    const std::size_t n_wall = wall->particles().n_particles();
    wall_offsets.assign(n_wall + 1, 0);
    for (const Index j : relation.neighbour) ++wall_offsets[j + 1];
    for (std::size_t j = 0; j < n_wall; ++j) wall_offsets[j + 1] += wall_offsets[j];
    wall_slots.resize(relation.neighbour.size());
    std::vector<std::size_t> next(wall_offsets.begin(), wall_offsets.end() - 1);
    for (std::size_t k = 0; k < relation.neighbour.size(); ++k) wall_slots[next[relation.neighbour[k]]++] = k;
    pressure_pairs.assign(relation.neighbour.size(), Vec<Dim>::Zero());
    viscous_pairs.assign(relation.neighbour.size(), Vec<Dim>::Zero());
  }
};

namespace {

/// Row i's part of B_i^-1 = -sum_j V_j r_ij dW_ij e_ij (x) e_ij (libsph/core/correction_matrix.hpp).
template <int Dim, class Relation>
Mat<Dim> correction_moment(const Relation& rel, std::size_t i, std::span<const Real> volume) {
  Mat<Dim> moment = Mat<Dim>::Zero();
  for (std::size_t k = rel.offsets[i]; k < rel.offsets[i + 1]; ++k) {
    const Vec<Dim>& e = rel.unit_vector[k];
    moment -= (volume[rel.neighbour[k]] * rel.distance[k] * rel.kernel_derivative[k]) * (e * e.transpose());
  }
  return moment;
}

template <int Dim>
Real kernel_at_zero(const AnyKernel<Dim>& kernel, Real h) {
  return std::visit([h](const auto& k) { return k.value(Real(0), h); }, kernel);
}

/// sigma0 = sum over a full lattice of spacing dp (the particle itself included) of dp^Dim W(r).
template <int Dim>
Real lattice_number_density(const AnyKernel<Dim>& kernel, Real h, Real dp) {
  const Real support = Real(2) * h;
  const int reach = static_cast<int>(std::ceil(support / dp)) + 1;
  Real volume = 1;
  for (int d = 0; d < Dim; ++d) volume *= dp;
  double sum = 0;
  std::array<int, Dim> k;
  k.fill(-reach);
  while (true) {
    Vec<Dim> x;
    for (int d = 0; d < Dim; ++d) x[d] = Real(k[d]) * dp;
    sum += std::visit([&](const auto& kern) { return double(kern.value(x.norm(), h)); }, kernel);
    int d = 0;
    while (d < Dim && ++k[d] > reach) k[d++] = -reach;
    if (d == Dim) break;
  }
  return static_cast<Real>(sum * volume);
}

}  // namespace

template <int Dim>
WeaklyCompressibleFluid<Dim>::WeaklyCompressibleFluid(ParticleSet<Dim>& particles, Settings settings)
    : particles_(particles), settings_(std::move(settings)) {
  const std::string body = "fluid '" + particles_.name() + "'";
  const auto& eos = settings_.equation_of_state;
  const auto& n = settings_.numerics;
  if (!(eos.reference_density > 0)) throw std::invalid_argument(body + ": density must be positive");
  if (!(eos.sound_speed > 0)) throw std::invalid_argument(body + ": sound speed must be positive");
  if (!(settings_.viscosity >= 0)) throw std::invalid_argument(body + ": viscosity must be >= 0");
  if (!(settings_.smoothing_length > 0)) throw std::invalid_argument(body + ": smoothing length must be positive");
  if (!(settings_.particle_spacing > 0)) throw std::invalid_argument(body + ": particle spacing must be positive");
  if (!(n.advection_cfl > 0 && n.advection_cfl <= 1) || !(n.acoustic_cfl > 0 && n.acoustic_cfl <= 1))
    throw std::invalid_argument(body + ": CFL numbers must lie in (0, 1]");
  if (n.sort_interval < 0) throw std::invalid_argument(body + ": sort interval must be >= 0");

  const std::size_t count = particles_.n_particles();
  velocity_ = particles_.template register_field<Vec<Dim>>("velocity", Vec<Dim>::Zero());
  density_ = particles_.template register_field<Real>("density", eos.reference_density);
  pressure_ = particles_.template register_field<Real>("pressure", Real(0));
  mass_ = particles_.template register_field<Real>("mass", Real(0), false);
  density_rate_ = particles_.template register_field<Real>("density_change_rate", Real(0), false);
  acceleration_ = particles_.template register_field<Vec<Dim>>("acceleration", Vec<Dim>::Zero(), false);
  prior_acceleration_ = particles_.template register_field<Vec<Dim>>("prior_acceleration", Vec<Dim>::Zero(), false);
  auto m = particles_.field(mass_);
  for (std::size_t i = 0; i < count; ++i) m[i] = eos.reference_density * particles_.volume[i];
  sigma0_ = lattice_number_density<Dim>(settings_.kernel, settings_.smoothing_length, settings_.particle_spacing);
}

template <int Dim>
WeaklyCompressibleFluid<Dim>::~WeaklyCompressibleFluid() = default;

template <int Dim>
void WeaklyCompressibleFluid<Dim>::distribute(std::size_t rebalance_interval) {
  const std::string body = "fluid '" + particles_.name() + "'";
  if (partition_) throw std::logic_error(body + " is already distributed");
  if (Communicator::world().size() == 1) return;
  if (settings_.periodic.any()) throw std::invalid_argument(body + ": periodic axes do not run on several MPI ranks yet");
  if (settings_.numerics.kernel_correction)
    throw std::invalid_argument(body + ": the kernel correction does not run on several MPI ranks yet");
  for (const auto& w : walls_)
    if (w->record)
      throw std::invalid_argument(body + ": the forces on wall '" + w->wall->particles().name() +
                                  "' are recorded (a body in the fluid), which does not run on several MPI ranks yet");
  // Ghosts out to the kernel support: the pair list is rebuilt at every advection step, and the
  // particles a row reads are fixed in between.
  const Real support = std::visit([&](const auto& k) { return k.support_radius(settings_.smoothing_length); }, settings_.kernel);
  partition_ = std::make_unique<MovingPartition<Dim>>(support, rebalance_interval);
  partition_->update(particles_);
}

template <int Dim>
std::size_t WeaklyCompressibleFluid<Dim>::add_wall(const FluidWall<Dim>& wall, WallForces forces) {
  if (partition_ && forces == WallForces::record)
    throw std::invalid_argument("fluid '" + particles_.name() + "': the forces on wall '" + wall.particles().name() +
                                "' cannot be recorded on several MPI ranks yet");
  walls_.push_back(std::make_unique<WallContact>());
  auto& contact = *walls_.back();
  contact.wall = &wall;
  contact.record = forces == WallForces::record;
  // The wall's fields as spans, once: walls are not re-sorted or resized, so the spans stay valid.
  const auto& particles = wall.particles();
  views_.push_back({&contact.relation, particles.volume, particles.field(wall.velocity_field()),
                    particles.field(wall.acceleration_field()), particles.field(wall.normal_field()),
                    wall.slip() == WallSlip::no_slip, contact.record ? &contact.pressure_pairs : nullptr,
                    contact.record ? &contact.viscous_pairs : nullptr});
  return walls_.size() - 1;
}

template <int Dim>
void WeaklyCompressibleFluid<Dim>::wall_forces(std::size_t k, std::span<Vec<Dim>> pressure,
                                               std::span<Vec<Dim>> viscous) const {
  const auto& contact = *walls_.at(k);
  const std::size_t n_wall = contact.wall->particles().n_particles();
  if (!contact.record)
    throw std::logic_error("fluid '" + particles_.name() + "': the forces on wall '" +
                           contact.wall->particles().name() + "' are not recorded");
  if (pressure.size() != n_wall || viscous.size() != n_wall)
    throw std::invalid_argument("fluid '" + particles_.name() + "': one force per wall particle is needed");
  if (contact.wall_offsets.size() != n_wall + 1) {  // before the first neighbour search
    std::fill(pressure.begin(), pressure.end(), Vec<Dim>::Zero());
    std::fill(viscous.begin(), viscous.end(), Vec<Dim>::Zero());
    return;
  }
  parallel_for(n_wall, [&](std::size_t j) {
    Vec<Dim> fp = Vec<Dim>::Zero(), fv = Vec<Dim>::Zero();
    for (std::size_t s = contact.wall_offsets[j]; s < contact.wall_offsets[j + 1]; ++s) {
      fp -= contact.pressure_pairs[contact.wall_slots[s]];
      fv -= contact.viscous_pairs[contact.wall_slots[s]];
    }
    pressure[j] = fp;
    viscous[j] = fv;
  });
}


template <int Dim>
const ContactRelation<Dim>& WeaklyCompressibleFluid<Dim>::wall_relation(std::size_t k) const {
  return walls_.at(k)->relation;
}

template <int Dim>
void WeaklyCompressibleFluid<Dim>::update_neighbours() {
  auto& x = particles_.position;
  const auto& box = settings_.periodic;
  const Real h = settings_.smoothing_length;
  if (partition_) {
    partition_->update(particles_);  // migration and new ghosts; owned particles in global-id order
  } else {
    if (box.any()) parallel_for(x.size(), [&](std::size_t i) { x[i] = box.wrap(x[i]); });
    if (settings_.numerics.sort_interval > 0 && rebuilds_ % static_cast<std::size_t>(settings_.numerics.sort_interval) == 0)
      sort_particles(particles_, Real(2) * h);
  }
  rebuild_inner_relation<Dim>(inner_, particles_, settings_.kernel, h, box, SourceOrder::by_position);
  const std::span<const Vec<Dim>> owned = std::span<const Vec<Dim>>(x).first(particles_.n_owned());
  for (auto& w : walls_) {
    // (wall particles keep their places and are the same on every rank: sources by index)
    rebuild_contact_relation<Dim>(w->relation, owned, w->wall->particles().position, settings_.kernel, h, box);
    if (w->record) w->transpose();
  }
  ++rebuilds_;
}

template <int Dim>
void WeaklyCompressibleFluid<Dim>::reinitialise_density() {
  const auto& views = views_;
  const auto mode = settings_.numerics.density_reinitialisation;
  if (mode == DensityReinitialisation::none) return;
  const Real rho0 = settings_.equation_of_state.reference_density;
  const auto m = particles_.field(mass_);
  auto rho = particles_.field(density_);
  const Real w0 = kernel_at_zero<Dim>(settings_.kernel, settings_.smoothing_length);
  parallel_for(particles_.n_owned(), [&](std::size_t i) {
    // sigma_i = sum_j V0_j W_ij with V0 = m / rho0 (fluid) and the wall particles' volumes.
    Real sigma = m[i] / rho0 * w0;
    for (std::size_t k = inner_.offsets[i]; k < inner_.offsets[i + 1]; ++k)
      sigma += m[inner_.neighbour[k]] / rho0 * inner_.kernel_value[k];
    for (const auto& w : views) {
      const auto& rel = *w.relation;
      for (std::size_t k = rel.offsets[i]; k < rel.offsets[i + 1]; ++k) sigma += w.volume[rel.neighbour[k]] * rel.kernel_value[k];
    }
    const Real summed = rho0 * sigma / sigma0_;
    rho[i] = mode == DensityReinitialisation::free_surface ? std::max(rho[i], summed) : summed;
  });
  update_ghosts(particles_, rho);
  update_pressure();
}

template <int Dim>
void WeaklyCompressibleFluid<Dim>::update_pressure() {
  const auto& eos = settings_.equation_of_state;
  const auto rho = particles_.field(density_);
  const auto m = particles_.field(mass_);
  auto p = particles_.field(pressure_);
  auto& V = particles_.volume;
  parallel_for(particles_.n_particles(), [&](std::size_t i) {
    p[i] = eos.pressure(rho[i]);
    V[i] = m[i] / rho[i];
  });
}

template <int Dim>
void WeaklyCompressibleFluid<Dim>::compute_prior_acceleration() {
  const auto& views = views_;
  const auto m = particles_.field(mass_);
  const auto v = particles_.field(velocity_);
  const auto rho = particles_.field(density_);
  const auto& V = particles_.volume;
  auto a = particles_.field(prior_acceleration_);
  const Real eta = settings_.viscosity;
  const Real h = settings_.smoothing_length;
  const Vec<Dim> g = settings_.body_force;
  const Real kappa = settings_.numerics.transport_velocity;
  const Real guard = Real(0.01) * h;  // keeps 1 / r finite for near-coincident pairs
  const std::size_t owned = particles_.n_owned();
  const bool correct = settings_.numerics.kernel_correction;
  if (kappa > 0) shift_.resize(owned);
  if (correct) correction_.resize(owned);
  parallel_for(owned, [&](std::size_t i) {
    Vec<Dim> force = Vec<Dim>::Zero();
    Vec<Dim> grad_sigma = Vec<Dim>::Zero();
    Real moment = 0;  // sum_j V_j r_ij dW_ij, -Dim for a full, exact neighbourhood
    Mat<Dim> moment_matrix = Mat<Dim>::Zero();  // B_i^-1 (kernel correction)
    for (std::size_t k = inner_.offsets[i]; k < inner_.offsets[i + 1]; ++k) {
      const Index j = inner_.neighbour[k];
      const Real dW = inner_.kernel_derivative[k];
      if (eta > 0) force += (V[j] * dW / (inner_.distance[k] + guard)) * (v[i] - v[j]);
      grad_sigma += (V[j] * dW) * inner_.unit_vector[k];
      moment += V[j] * inner_.distance[k] * dW;
    }
    if (correct) moment_matrix = correction_moment<Dim>(inner_, i, std::span<const Real>(V));
    for (const auto& w : views) {
      const auto& rel = *w.relation;
      const auto& vw = w.velocity;
      const bool no_slip = w.no_slip;
      for (std::size_t k = rel.offsets[i]; k < rel.offsets[i + 1]; ++k) {
        const Index j = rel.neighbour[k];
        const Real dW = rel.kernel_derivative[k];
        // The ghost velocity 2 v_w - v_i: v_i - v_ghost = 2 (v_i - v_w).
        if (eta > 0 && no_slip) {
          const Vec<Dim> pair = (Real(2) * w.volume[j] * dW / (rel.distance[k] + guard)) * (v[i] - vw[j]);
          force += pair;
          if (w.viscous_pairs) (*w.viscous_pairs)[k] = pair;  // scaled to a force below
        }
        grad_sigma += (w.volume[j] * dW) * rel.unit_vector[k];
        moment += w.volume[j] * rel.distance[k] * dW;
      }
      if (correct) moment_matrix += correction_moment<Dim>(rel, i, w.volume);
    }
    if (correct) correction_[i] = correction_from_moment<Dim>(moment_matrix);
    // Renormalised Laplacian: on a lattice at h = 1.3 dp the moment is 2.6 % short of -Dim, which
    // leaves the viscous force 2.6 % weak at any resolution (Poiseuille 3 % fast). Dividing by it
    // makes the operator exact on quadratic fields in a full neighbourhood; the factor is held in
    // [1, 1.1] so that a free surface (a truncated support) is not amplified.
    const Real renormalisation = moment < 0 ? std::clamp(-Real(Dim) / moment, Real(1), Real(1.1)) : Real(1);
    const Real factor = Real(2) * eta * renormalisation / rho[i];
    a[i] = g + factor * force;
    for (const auto& w : views) {  // the recorded pairs as forces m_i a_pair on the fluid particle
      if (!w.viscous_pairs) continue;
      const auto& rel = *w.relation;
      for (std::size_t k = rel.offsets[i]; k < rel.offsets[i + 1]; ++k)
        (*w.viscous_pairs)[k] = (eta > 0 && w.no_slip) ? ((m[i] * factor) * (*w.viscous_pairs)[k]).eval() : Vec<Dim>::Zero();
    }
    if (kappa > 0) shift_[i] = -Real(2) * kappa * h * h * grad_sigma;
  });
  if (kappa > 0) {
    auto& x = particles_.position;
    parallel_for(owned, [&](std::size_t i) { x[i] += shift_[i]; });
  }
}

template <int Dim>
void WeaklyCompressibleFluid<Dim>::first_half(Real dt) {
  const auto& views = views_;
  const auto& eos = settings_.equation_of_state;
  const auto& numerics = settings_.numerics;
  auto rho = particles_.field(density_);
  auto p = particles_.field(pressure_);
  auto v = particles_.field(velocity_);
  auto a = particles_.field(acceleration_);
  const auto a_prior = particles_.field(prior_acceleration_);
  const auto drho = particles_.field(density_rate_);
  const auto m = particles_.field(mass_);
  auto& x = particles_.position;
  auto& V = particles_.volume;
  const std::size_t n = particles_.n_particles();
  state_.resize(n);
  parallel_for(n, [&](std::size_t i) {
    rho[i] += Real(0.5) * dt * drho[i];
    p[i] = eos.pressure(rho[i]);
    V[i] = m[i] / rho[i];
    x[i] += Real(0.5) * dt * v[i];
    state_[i] = {v[i], p[i], V[i]};
  });

  // The dissipative terms use the reference impedance rho0 c0 (the density varies by about 1 %).
  const Real c0 = eos.sound_speed;
  const Real rho_c = eos.reference_density * c0;
  const Real h = settings_.smoothing_length;
  const Real limiter_slope = numerics.limiter_strength / c0;
  const bool riemann = numerics.scheme == FluidScheme::riemann;
  const bool viscous = numerics.scheme == FluidScheme::artificial_viscosity;
  const Real alpha = numerics.artificial_viscosity;
  const Vec<Dim> g = settings_.body_force;
  // Dissipative pressure of a compressing pair: 1/2 beta rho0 c0 (u_L - u_R), zero for an expanding
  // one (written without branches: the sign of the jump is unpredictable pair by pair).
  const Real dissipation = riemann ? Real(0.5) * rho_c : Real(0);
  auto limited = [&](Real jump) {
    const Real compression = std::max(jump, Real(0));
    return dissipation * std::min(limiter_slope * compression, Real(1)) * compression;
  };
  // Monaghan's Pi_ij for approaching pairs (relative velocity w = v_i - v_other along e at distance r).
  auto monaghan = [&](Real w_dot_e, Real r, Real rho_avg) {
    if (!viscous || !(w_dot_e < 0)) return Real(0);
    const Real mu = h * w_dot_e * r / (r * r + Real(0.01) * h * h);
    return -alpha * c0 * mu / rho_avg;
  };
  const std::size_t owned = particles_.n_owned();
  // (the corrected and the plain force as two instantiations: the plain one compiles as it did
  // before the option existed, to the bit)
  auto pressure_force = [&](auto corrected) {
    parallel_for(owned, [&](std::size_t i) {
      constexpr bool correct = decltype(corrected)::value;
      Vec<Dim> force = Vec<Dim>::Zero();
      const Real two_over_rho = Real(2) / rho[i];
      const Vec<Dim> vi = v[i];
      const Real p_i = p[i];
      for (std::size_t k = inner_.offsets[i]; correct && k < inner_.offsets[i + 1]; ++k) {
        // 2 P*_ij e -> (p_i B_i + p_j B_j) e + 2 (dissipative part) e
        const PairState& sj = state_[inner_.neighbour[k]];
        const Vec<Dim>& e = inner_.unit_vector[k];
        const Vec<Dim> pressure = p_i * (correction_[i] * e) + sj.pressure * (correction_[inner_.neighbour[k]] * e);
        const Real dissipative = limited(-(vi - sj.velocity).dot(e));
        force -= (sj.volume * inner_.kernel_derivative[k] / rho[i]) * (pressure + (Real(2) * dissipative) * e);
      }
      for (std::size_t k = inner_.offsets[i]; !correct && k < inner_.offsets[i + 1]; ++k) {
        const Index j = inner_.neighbour[k];
        const PairState& sj = state_[j];
        const Vec<Dim>& e = inner_.unit_vector[k];
        const Real w_dot_e = (vi - sj.velocity).dot(e);
        const Real p_star = Real(0.5) * (p_i + sj.pressure) + limited(-w_dot_e);
        Real pair = two_over_rho * p_star * sj.volume;
        if (viscous) pair += rho[j] * V[j] * monaghan(w_dot_e, inner_.distance[k], Real(0.5) * (rho[i] + rho[j]));
        force -= (pair * inner_.kernel_derivative[k]) * e;
      }
      for (const auto& w : views) {
        const auto& rel = *w.relation;
        const auto& vw = w.velocity;
        const auto& aw = w.acceleration;
        const auto& nw = w.normal;
        for (std::size_t k = rel.offsets[i]; k < rel.offsets[i + 1]; ++k) {
          const Index j = rel.neighbour[k];
          const Vec<Dim>& e = rel.unit_vector[k];
          // x_w - x_i = -r e: the pressure extrapolated to the wall particle (Adami et al. 2012).
          const Real p_wall = p_i + rho[i] * rel.distance[k] * (g - aw[j]).dot(-e);
          const Real jump = Real(2) * (vw[j] - vi).dot(nw[j]);
          const Real p_star = Real(0.5) * (p_i + p_wall) + limited(jump);
          Real pair = two_over_rho * p_star * w.volume[j];
          if (viscous) pair += rho[i] * w.volume[j] * monaghan(Real(2) * (vi - vw[j]).dot(e), rel.distance[k], rho[i]);
          if constexpr (correct) {  // the wall particle takes B_i: the pair force along B_i e
            const Vec<Dim> direction = correction_[i] * e;
            force -= (pair * rel.kernel_derivative[k]) * direction;
            if (w.pressure_pairs) (*w.pressure_pairs)[k] = (-(m[i] * pair * rel.kernel_derivative[k])) * direction;
          } else {
            force -= (pair * rel.kernel_derivative[k]) * e;
            if (w.pressure_pairs) (*w.pressure_pairs)[k] = (-(m[i] * pair * rel.kernel_derivative[k])) * e;
          }
        }
      }
      a[i] = force;
    });
  };
  if (numerics.kernel_correction)
    pressure_force(std::true_type{});
  else
    pressure_force(std::false_type{});
  parallel_for(owned, [&](std::size_t i) { v[i] += dt * (a[i] + a_prior[i]); });
  update_ghosts(particles_, v);
  parallel_for(n, [&](std::size_t i) { state_[i].velocity = v[i]; });
  ++acoustic_steps_;
}

template <int Dim>
void WeaklyCompressibleFluid<Dim>::second_half(Real dt) {
  const auto& views = views_;
  const auto& eos = settings_.equation_of_state;
  auto rho = particles_.field(density_);
  const auto p = particles_.field(pressure_);
  const auto v = particles_.field(velocity_);
  auto drho = particles_.field(density_rate_);
  const auto m = particles_.field(mass_);
  auto& x = particles_.position;
  auto& V = particles_.volume;
  const std::size_t n = particles_.n_particles();
  const std::size_t owned = particles_.n_owned();
  parallel_for(owned, [&](std::size_t i) { x[i] += Real(0.5) * dt * v[i]; });
  const auto scheme = settings_.numerics.scheme;
  const bool diffusion = scheme == FluidScheme::pressure_diffusion;
  const Real c0 = eos.sound_speed;
  // pressure_diffusion: beta = 1 for every pair (a slope so steep that the limiter is always 1).
  const Real limiter_slope = diffusion ? std::numeric_limits<Real>::max() : settings_.numerics.limiter_strength / c0;
  const Real jump_scale =
      scheme == FluidScheme::riemann || diffusion ? Real(1) / (eos.reference_density * c0) : Real(0);
  const Real wall_jump_scale = diffusion ? jump_scale : Real(0);
  const Vec<Dim> g = settings_.body_force;
  parallel_for(owned, [&](std::size_t i) {
    Real rate = 0;
    const Vec<Dim> vi = v[i];
    const Real p_i = p[i];
    for (std::size_t k = inner_.offsets[i]; k < inner_.offsets[i + 1]; ++k) {
      const Index j = inner_.neighbour[k];
      // 2 (U* - u_L) = (v_i - v_j).e_ij + beta (p_i - p_j) / (rho0 c0)
      const PairState& sj = state_[j];
      const Real w_dot_e = (vi - sj.velocity).dot(inner_.unit_vector[k]);
      const Real beta = diffusion ? Real(1) : std::min(limiter_slope * std::max(-w_dot_e, Real(0)), Real(1));
      const Real flux = w_dot_e + beta * (p_i - sj.pressure) * jump_scale;
      rate += sj.volume * flux * inner_.kernel_derivative[k];
    }
    for (const auto& w : views) {
      const auto& rel = *w.relation;
      const auto& vw = w.velocity;
      const auto& aw = w.acceleration;
      for (std::size_t k = rel.offsets[i]; k < rel.offsets[i + 1]; ++k) {
        const Index j = rel.neighbour[k];
        const Vec<Dim>& e = rel.unit_vector[k];
        // mirrored velocity 2 v_w - v_i: v_i - v_ghost = 2 (v_i - v_w); with pressure_diffusion also
        // the jump p_i - p_w = rho_i r (g - a_w).e to the extrapolated wall pressure
        const Real jump = rho[i] * rel.distance[k] * (g - aw[j]).dot(e) * wall_jump_scale;
        rate += w.volume[j] * (Real(2) * (v[i] - vw[j]).dot(e) + jump) * rel.kernel_derivative[k];
      }
    }
    drho[i] = rho[i] * rate;
  });
  update_ghosts(particles_, drho);
  parallel_for(n, [&](std::size_t i) {
    rho[i] += Real(0.5) * dt * drho[i];
    V[i] = m[i] / rho[i];
  });
}

template <int Dim>
Real WeaklyCompressibleFluid<Dim>::max_speed() const {
  const auto v = particles_.field(velocity_);
  return std::sqrt(global_max(particles_, parallel_max(particles_.n_owned(), Real(0), [&](std::size_t i) { return v[i].squaredNorm(); })));
}

template <int Dim>
Real WeaklyCompressibleFluid<Dim>::advection_time_step() const {
  const Real h = settings_.smoothing_length;
  const Real speed = std::max(max_speed(), settings_.reference_speed);
  Real dt = std::numeric_limits<Real>::infinity();
  if (speed > 0) dt = h / speed;
  const Real nu = settings_.viscosity / settings_.equation_of_state.reference_density;
  if (nu > 0) dt = std::min(dt, h * h / nu);
  const Real g = settings_.body_force.norm();
  if (g > 0) dt = std::min(dt, std::sqrt(h / g));
  if (!std::isfinite(dt)) dt = h / settings_.equation_of_state.sound_speed;  // nothing moves: one acoustic scale
  return settings_.numerics.advection_cfl * dt;
}

template <int Dim>
Real WeaklyCompressibleFluid<Dim>::plan_advection_step() {
  planned_acoustic_step_ = acoustic_time_step();
  for (const auto& limit : acoustic_limits_) planned_acoustic_step_ = std::min(planned_acoustic_step_, limit());
  const Real steps = std::max(Real(1), std::round(advection_time_step() / planned_acoustic_step_));
  return steps * planned_acoustic_step_;
}

template <int Dim>
Real WeaklyCompressibleFluid<Dim>::acoustic_time_step() const {
  return settings_.numerics.acoustic_cfl * settings_.smoothing_length /
         (settings_.equation_of_state.sound_speed + max_speed());
}

template <int Dim>
void WeaklyCompressibleFluid<Dim>::check_state(Real time) const {
  const auto rho = particles_.field(density_);
  const auto v = particles_.field(velocity_);
  const auto& x = particles_.position;
  const Real rho0 = settings_.equation_of_state.reference_density;
  const Real margin = Real(2) * settings_.smoothing_length;
  auto outside = [&](std::size_t i) {
    for (int d = 0; d < Dim; ++d) {
      if (settings_.periodic.periodic[d]) continue;
      if (!(x[i][d] >= settings_.domain_lower[d] - margin && x[i][d] <= settings_.domain_upper[d] + margin)) return true;
    }
    return false;
  };
  const std::size_t bad = first_index_where(particles_.n_owned(), [&](std::size_t i) {
    return !(rho[i] >= Real(0.5) * rho0 && rho[i] <= Real(2) * rho0) || !v[i].allFinite() || outside(i);
  });
  const auto first = first_over_ranks(particles_, bad);  // (the lowest global id on several ranks)
  if (!first.found) return;
  const bool mine = bad < particles_.n_owned();
  const double kind = value_of_owner(particles_, first, bad,
                                     !mine ? 0.0 : !v[bad].allFinite() || !x[bad].allFinite() ? 1.0 : outside(bad) ? 2.0 : 3.0);
  const double density = value_of_owner(particles_, first, bad, mine ? double(rho[bad]) : 0.0);
  const std::string where = NumericalFailure::format_position(first.position);
  if (kind == 1) throw NumericalFailure(particles_.name(), first.id, where, time, "velocity", "is not finite");
  if (kind == 2) throw NumericalFailure(particles_.name(), first.id, where, time, "position", "left the domain box");
  throw NumericalFailure(particles_.name(), first.id, where, time, "density",
                         std::to_string(density) + " left [0.5, 2] rho0 = [" + std::to_string(0.5 * rho0) + ", " +
                             std::to_string(2 * rho0) + "]");
}

template <int Dim>
typename WeaklyCompressibleFluid<Dim>::Energies WeaklyCompressibleFluid<Dim>::energies() const {
  const auto v = particles_.field(velocity_);
  const auto rho = particles_.field(density_);
  const auto m = particles_.field(mass_);
  const auto& x = particles_.position;
  const Vec<Dim> g = settings_.body_force;
  const auto& eos = settings_.equation_of_state;
  Energies e;
  e.kinetic = global_exact_sum(particles_, [&](std::size_t i) { return 0.5 * m[i] * v[i].squaredNorm(); });
  e.potential = global_exact_sum(particles_, [&](std::size_t i) { return -double(m[i]) * g.dot(x[i]); });
  e.internal = global_exact_sum(particles_, [&](std::size_t i) { return m[i] * eos.internal_energy(rho[i]); });
  return e;
}

template <int Dim>
Stage WeaklyCompressibleFluid<Dim>::advection_stage(SectionTimers& timers) {
  Stage acoustic{"acoustic", [this] { return planned_acoustic_step_; }, {}};
  acoustic.then("pressure force", timers.timed("fluid_pressure_force", [this](Real, Real dt) { first_half(dt); }))
      .then("continuity", timers.timed("fluid_continuity", [this](Real, Real dt) { second_half(dt); }))
      .slot(acoustic_slot());
  Stage advection{"advection", [this] { return plan_advection_step(); }, {}};
  advection.slot(particles_slot())
      .then("neighbours", timers.timed("fluid_neighbours", [this](Real, Real) { update_neighbours(); }))
      .then("density and forces", timers.timed("fluid_density_and_viscous", [this](Real, Real) {
        reinitialise_density();
        compute_prior_acceleration();
      }))
      .slot(forces_slot())
      .sub_cycle(std::move(acoustic))
      .then("checks", [this](Real t, Real dt) {
        ++advection_steps_;
        check_state(t + dt);
      });
  return advection;
}

template class WeaklyCompressibleFluid<2>;
template class WeaklyCompressibleFluid<3>;

}  // namespace sph
