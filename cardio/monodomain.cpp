#include "cardio/monodomain.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "libsph/core/distribution.hpp"
#include "libsph/core/parallel.hpp"
#include "libsph/io/parameters.hpp"

namespace cardio {

void declare_parameters(sph::Parameters& p, MonodomainNumerics& n, const std::string& time_unit) {
  p.add_enum("reaction_scheme", n.scheme, sph::reaction_scheme_names(),
             "cell integrator: reaction-by-reaction Strang splitting with QSS updates, generalised Rush-Larsen, or "
             "explicit Euler");
  p.add("ep_time_step", n.time_step, time_unit, "splitting step of the monodomain (reaction half step, diffusion, reaction half step)",
        sph::Range::positive());
  p.add("reaction_quiescent_step", n.quiescent_step, time_unit,
        "longest reaction step of a quiescent block of cells (one whose potential changes slower than "
        "reaction_quiescent_rate; e.g. in diastole); 0: every cell at every half step",
        sph::Range::non_negative());
  p.add("reaction_quiescent_rate", n.quiescent_rate, time_unit == "-" ? "-" : "mV/" + time_unit,
        "|dV/dt| below which a block of cells is quiescent (and a drift of rate x step that wakes it)",
        sph::Range::positive());
  sph::declare_parameters(p, n.diffusion);
}

namespace {
template <int Dim>
typename sph::ScalarDiffusionSystem<Dim>::Settings diffusion_settings(const typename Monodomain<Dim>::Settings& s,
                                                                     sph::FieldHandle<Real> potential) {
  typename sph::ScalarDiffusionSystem<Dim>::Settings d;
  d.field = potential;  // the cell model's potential, passed on by handle
  d.diffusion_tensor = s.diffusion_tensor;
  d.numerics = s.numerics.diffusion;
  return d;
}

}  // namespace

template <int Dim>
typename Monodomain<Dim>::Reaction Monodomain<Dim>::make_reaction(sph::ParticleSet<Dim>& particles, const Settings& settings) {
  const bool variants = !settings.cell_variants.empty();
  return std::visit(
      [&](const auto& first) -> Reaction {
        using M = std::decay_t<decltype(first)>;
        std::vector<M> models;
        for (const auto& any : variants ? settings.cell_variants : std::vector<sph::AnyCellModel>{settings.cell_model}) {
          const M* model = std::get_if<M>(&any);
          if (!model)
            throw std::invalid_argument("monodomain on '" + particles.name() + "': every cell variant must be of the same model");
          models.push_back(*model);
        }
        return sph::ReactionSystem<Dim, M>(particles, std::move(models),
                                           variants ? settings.cell_variant : std::vector<std::uint16_t>{},
                                           {settings.numerics.scheme, settings.write_states, settings.numerics.quiescent_step,
                                            settings.numerics.quiescent_rate});
      },
      variants ? settings.cell_variants.front() : settings.cell_model);
}

template <int Dim>
sph::FieldHandle<Real> Monodomain<Dim>::calcium_field() const {
  if (const auto* ttp = std::get_if<sph::ReactionSystem<Dim, sph::TenTusscherPanfilov2006>>(&reaction_))
    return ttp->state_field(sph::TenTusscherPanfilov2006::StateIndex::Ca_i);
  return {};
}

template <int Dim>
Monodomain<Dim>::Monodomain(sph::ParticleSet<Dim>& particles, const sph::InnerRelation<Dim>& relation, Settings settings)
    : particles_(particles),
      settings_(std::move(settings)),
      reaction_(make_reaction(particles, settings_)),
      relation_(relation),
      diffusion_(particles, relation,
                 diffusion_settings<Dim>(settings_, std::visit([](const auto& r) { return r.potential_field(); }, reaction_))) {
  if (!(settings_.numerics.time_step > 0 && std::isfinite(settings_.numerics.time_step)))
    throw std::invalid_argument("monodomain on '" + particles.name() + "': the time step must be positive");
  const std::size_t n = particles.n_owned();  // stimuli name owned particles (local indices)
  for (const auto& region : settings_.stimuli)
    for (std::size_t i : region.particles)
      if (i >= n)
        throw std::invalid_argument("monodomain on '" + particles.name() + "': stimulus region '" + region.name +
                                    "' names particle " + std::to_string(i) + " of " + std::to_string(n));
  potential_ = diffusion_.value_field();
  activation_ = particles.template register_field<Real>("activation_time", Real(-1));
  if (settings_.repolarisation_percent != 0)
    maps_ = std::make_unique<ActionPotentialMaps<Dim>>(particles, settings_.repolarisation_percent,
                                                       settings_.activation_threshold);
  if (maps_) conduction_velocity_ = particles.template register_field<Real>("conduction_velocity", Real(-1));
  stimulus_.assign(particles.n_particles(), 0);
  previous_potential_.assign(particles.n_particles(), 0);
  step_ = stage();
}

template <int Dim>
sph::Stage Monodomain<Dim>::stage(std::string name) {
  sph::Stage step{std::move(name), [this] { return settings_.numerics.time_step; }, {}};
  sph::Stage diffusion{"diffusion", [this] { return diffusion_.stable_time_step(); }, {}};
  diffusion.then("diffusion", timers_.timed("diffusion", [this](Real t, Real dt) { diffusion_.advance(t, dt); }));
  step.then("store potential",
            [this](Real, Real) {
              const auto V = particles_.field(potential_);
              std::copy(V.begin(), V.end(), previous_potential_.begin());
            })
      .then("reaction", timers_.timed("reaction", [this](Real t, Real dt) { react(t, dt / 2); }))
      .sub_cycle(std::move(diffusion))
      .then("reaction", timers_.timed("reaction", [this](Real t, Real dt) { react(t + dt / 2, dt / 2); }))
      .then("activation", [this](Real t, Real dt) { record_activation(t, dt); });
  if (maps_)
    step.then("maps", timers_.timed("maps", [this](Real t, Real dt) {
      maps_->record(previous_potential_, particles_.field(potential_), t, dt);
    }));
  return step;
}

template <int Dim>
void Monodomain<Dim>::react(Real time, Real dt) {
  bool any = false;
  for (const auto& region : settings_.stimuli) any = any || region.protocol.average(time, dt) != 0;
  if (any) {
    std::fill(stimulus_.begin(), stimulus_.end(), Real(0));
    for (const auto& region : settings_.stimuli) {
      const auto s = static_cast<Real>(region.protocol.average(time, dt));
      for (std::size_t i : region.particles) stimulus_[i] += s;
    }
  }
  std::visit([&](auto& r) { r.advance(time, dt, any ? std::span<const Real>(stimulus_) : std::span<const Real>()); },
             reaction_);
}

template <int Dim>
void Monodomain<Dim>::record_activation(Real time, Real dt) {
  // The first upward crossing of the threshold, interpolated linearly in the step.
  const Real threshold = settings_.activation_threshold;
  const auto V = particles_.field(potential_);
  auto activation = particles_.field(activation_);
  sph::parallel_for(particles_.n_owned(), [&](std::size_t i) {
    if (activation[i] >= 0 || !(previous_potential_[i] < threshold && V[i] >= threshold)) return;
    const Real fraction = (threshold - previous_potential_[i]) / (V[i] - previous_potential_[i]);
    activation[i] = time + fraction * dt;
  });
}

template <int Dim>
void Monodomain<Dim>::update_conduction_velocity() {
  if (!maps_) return;
  sph::update_ghosts(particles_, particles_.field(activation_));
  conduction_velocity<Dim>(relation_, particles_.volume, particles_.field(activation_), particles_.field(conduction_velocity_));
}

template <int Dim>
bool Monodomain<Dim>::all_activated() const {
  const auto activation = particles_.field(activation_);
  const std::size_t n = particles_.n_owned();
  const bool here = sph::first_index_where(n, [&](std::size_t i) { return activation[i] < 0; }) >= n;
  const auto* comm = sph::communicator_of(particles_);
  return comm ? !comm->any(!here) : here;
}

template <int Dim>
Real Monodomain<Dim>::latest_activation() const {
  if (!all_activated()) return -1;
  const auto activation = particles_.field(activation_);
  const Real latest = sph::parallel_max(particles_.n_owned(), Real(-1), [&](std::size_t i) { return activation[i]; });
  const auto* comm = sph::communicator_of(particles_);
  return comm ? static_cast<Real>(comm->max(double(latest))) : latest;
}

template class Monodomain<2>;
template class Monodomain<3>;

}  // namespace cardio
