#include "cardio/cavities.hpp"

#include <stdexcept>

namespace cardio {

Cavities::Cavities(sph::ElasticSolid<3>& solid, std::vector<CavitySurface> surfaces, const CavityPressureSettings& settings)
    : solid_(solid), surfaces_(std::move(surfaces)), penalties_(surfaces_.size()) {
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

double Cavities::volume(std::size_t c) const {
  const auto& body = solid_.particles();
  return surfaces_[c].volume(body.position, body.field(solid_.deformation_gradient_field()),
                             body.field(solid_.reference_position_field()));
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
  auto& body = on.particles();
  const auto F = body.field(on.deformation_gradient_field());
  const auto X = body.field(on.reference_position_field());
  const auto force = body.field(on.external_force_field());
  const Real t = time + dt / 2;
  for (std::size_t c = 0; c < by.size(); ++c) {
    if (!by.pressure(c).active()) continue;
    if (const auto& penalty = by.penalty(c))
      by.surface(c).add_pressure_forces(
          [&penalty](double V) { return Real(penalty->reference_pressure + (penalty->blood_volume - V) / penalty->compliance); },
          body.position, F, X, force);
    else
      by.surface(c).add_pressure_forces(Real(by.pressure(c).at(double(t))), body.position, F, X, force);
  }
}

}  // namespace cardio
