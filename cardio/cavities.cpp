#include "cardio/cavities.hpp"

#include <algorithm>
#include <stdexcept>

namespace cardio {
namespace {

/// The particles of every vertex stencil of the surfaces, ascending.
std::vector<sph::Index> stencil_particles(const std::vector<CavitySurface>& surfaces) {
  std::vector<sph::Index> ids;
  for (const auto& s : surfaces) ids.insert(ids.end(), s.stencil_particle.begin(), s.stencil_particle.end());
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

}  // namespace

Cavities::Cavities(sph::ElasticSolid<3>& solid, std::vector<CavitySurface> surfaces, const CavityPressureSettings& settings)
    : solid_(solid), surfaces_(std::move(surfaces)), under_(solid.particles(), stencil_particles(surfaces_)),
      on_under_(surfaces_), penalties_(surfaces_.size()) {
  const auto& body = solid.particles();
  const std::size_t n_global = body.partition() ? body.partition()->n_global : body.n_particles();
  for (auto& s : on_under_)
    for (auto& i : s.stencil_particle) {
      if (i >= n_global) throw std::invalid_argument("cavities: a vertex stencil names particle " + std::to_string(i) + " of " + std::to_string(n_global));
      i = static_cast<sph::Index>(std::lower_bound(under_.ids().begin(), under_.ids().end(), i) - under_.ids().begin());
    }
  under_.gather(std::span<const sph::Vec<3>>(body.field(solid.reference_position_field())), X_under_);
  for (const auto& c : surfaces_)
    pressures_.emplace_back(settings, c.label == label_lv_endo ? settings.lv_pressure : settings.rv_pressure);
  if (loaded()) (void)solid.external_force_field();
}

bool Cavities::loaded() const {
  for (const auto& p : pressures_)
    if (p.active()) return true;
  return false;
}

std::optional<std::size_t> Cavities::find(SurfaceLabel label) const {
  for (std::size_t c = 0; c < surfaces_.size(); ++c)
    if (surfaces_[c].label == label) return c;
  return std::nullopt;
}

void Cavities::gather_state() const {
  const auto& body = solid_.particles();
  under_.gather(std::span<const sph::Vec<3>>(body.position), x_under_);
  under_.gather(std::span<const sph::Mat<3>>(body.field(solid_.deformation_gradient_field())), F_under_);
}

double Cavities::volume(std::size_t c) const {
  gather_state();
  return on_under_[c].volume(x_under_, F_under_, X_under_);
}

void Cavities::add_loads(Real t, std::span<sph::Vec<3>> force) const {
  gather_state();
  // The load lands in a copy of the force of the particles under the surfaces (this rank's owned
  // ones; the others' entries are discarded), added in the serial order, then written back.
  force_under_.assign(under_.size(), sph::Vec<3>::Zero());
  for (std::size_t k = 0; k < under_.size(); ++k)
    if (under_.owned(k) != under_.not_owned) force_under_[k] = force[under_.owned(k)];
  for (std::size_t c = 0; c < size(); ++c) {
    if (!pressure(c).active()) continue;
    if (const auto& p = penalty(c))
      on_under_[c].add_pressure_forces(
          [&p](double V) { return Real(p->reference_pressure + (p->blood_volume - V) / p->compliance); }, x_under_, F_under_,
          X_under_, force_under_);
    else
      on_under_[c].add_pressure_forces(Real(pressure(c).at(double(t))), x_under_, F_under_, X_under_, force_under_);
  }
  for (std::size_t k = 0; k < under_.size(); ++k)
    if (under_.owned(k) != under_.not_owned) force[under_.owned(k)] = force_under_[k];
}

void Cavities::checkpoint(sph::StateArchive& archive) {
  for (std::size_t c = 0; c < surfaces_.size(); ++c) {
    auto pressure = archive.part("pressure" + std::to_string(c));
    pressures_[c].checkpoint(pressure);
    bool coupled = penalties_[c].has_value();
    VolumePenalty penalty = penalties_[c].value_or(VolumePenalty{});
    pressure.io("coupled", coupled);
    pressure.io("reference_pressure", penalty.reference_pressure);
    pressure.io("blood_volume", penalty.blood_volume);
    pressure.io("compliance", penalty.compliance);
    if (archive.loading()) penalties_[c] = coupled ? std::optional<VolumePenalty>(penalty) : std::nullopt;
  }
}

void interact(sph::ElasticSolid<3>& on, const Cavities& by, sph::SameParticles, Real time, Real dt) {
  if (&on != &by.solid()) throw std::invalid_argument("cavity pressure: the cavities were built on another solid");
  if (!by.loaded()) return;
  by.add_loads(time + dt / 2, on.particles().field(on.external_force_field()));
}

}  // namespace cardio
