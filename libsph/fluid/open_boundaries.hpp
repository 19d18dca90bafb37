#pragma once
// Open boundaries of a channel flow along +x (axis 0).
//
// Inflow zone (buffer): an axis-aligned box [lower, upper] in which the fluid's velocity is imposed,
// v = u(x, t) (e.g. a parabolic profile ramped up in time), at the end of every acoustic step: the
// interaction of the zone on the fluid, interact(fluid, zone, same_particles, t, dt), in the fluid's
// acoustic slot (WeaklyCompressibleFluid::acoustic_slot). With
// emission on, the zone is also an emitter (the "emitter inflow injection" of SPHinXsys, Zhang et
// al. 2021, Comput. Phys. Commun. 267:108066): at each advection step, a buffer particle that has
// crossed the downstream face x = upper_x becomes an ordinary fluid particle and a copy of it (same
// density, mass and velocity) enters at x - (upper_x - lower_x), so every row of the lattice in the
// buffer stays full. Without emission the zone serves a periodic channel (the particles leaving the
// outlet come back through the periodic seam into the buffer).
//
// Outflow zone: the particles beyond x = outlet are deleted at each advection step.
//
// Both change the number of fluid particles only at the start of an advection step, before the
// neighbour search (emit() and remove() as phases of the fluid's particles slot,
// WeaklyCompressibleFluid::particles_slot), through ParticleSet::select, which keeps every field
// consistent; the relations are rebuilt right after. They change the fluid's particle set itself
// (and count what they did), which is the fluid's own bookkeeping rather than an interaction:
//
//   step.fill(fluid.particles_slot(), "inflow emission", [&](Real, Real) { inlet.emit(); });
//   step.fill(fluid.particles_slot(), "outflow", [&](Real, Real) { outlet.remove(); });
//   step.fill(fluid.acoustic_slot(), "inflow velocity", sph::coupling(fluid, inlet, sph::same_particles));
//
// Check: an inflow faster than c0 / 10 (Mach 0.1 in the mean speed through the inlet, the
// weakly-compressible limit of the fluid's sound speed) is refused at the set-up. The peak of a
// parabolic profile is 1.5 times its mean, and the flow accelerates past obstacles: the fluid's own
// state check stops a run whose density then leaves its bounds.

#include <functional>
#include <string>

#include "libsph/core/interaction.hpp"
#include "libsph/fluid/weakly_compressible_fluid.hpp"

namespace sph {

template <int Dim>
class InflowZone {
 public:
  using Profile = std::function<Vec<Dim>(const Vec<Dim>& position, Real time)>;
  struct Settings {
    Vec<Dim> lower = Vec<Dim>::Zero(), upper = Vec<Dim>::Zero();  ///< the buffer box
    Profile velocity;        ///< imposed velocity
    Real mean_speed = 0;     ///< the mean speed through the inlet (flux / area; checked against c0 / 10)
    bool emit = true;        ///< create particles (open inlet); false: periodic channel (emit() does nothing)
  };

  /// Throws std::invalid_argument for an empty box, no profile, or a mean speed above c0 / 10.
  InflowZone(WeaklyCompressibleFluid<Dim>& fluid, Settings settings);

  /// Emits a particle for each buffer particle that has left through the downstream face; returns
  /// the number emitted.
  std::size_t emit();
  std::size_t emitted() const { return emitted_; }
  /// Saves or loads the count emitted (checkpoints); which particle is in the buffer is a field.
  void checkpoint(StateArchive& archive) { archive.io("emitted", emitted_); }
  /// True for a point inside the buffer box.
  bool inside(const Vec<Dim>& x) const;
  const Settings& settings() const { return settings_; }

 private:

  WeaklyCompressibleFluid<Dim>& fluid_;
  Settings settings_;
  FieldHandle<Real> in_buffer_;  // 1 for a particle inside the box at the last emission pass
  std::size_t emitted_ = 0;
  std::vector<Index> order_;
};

template <int Dim>
class OutflowZone {
 public:
  OutflowZone(WeaklyCompressibleFluid<Dim>& fluid, Real outlet) : fluid_(fluid), outlet_(outlet) {}
  /// Deletes the fluid particles with x > outlet; returns the number deleted.
  std::size_t remove();
  std::size_t removed() const { return removed_; }
  /// Saves or loads the count removed (checkpoints).
  void checkpoint(StateArchive& archive) { archive.io("removed", removed_); }

 private:
  WeaklyCompressibleFluid<Dim>& fluid_;
  Real outlet_;
  std::size_t removed_ = 0;
  std::vector<Index> order_;
};

/// The inflow zone on the fluid it was built on: v = u(x, time + dt) on the fluid particles inside
/// the box (the profile at the end of the acoustic step [time, time + dt]).
template <int Dim>
void interact(WeaklyCompressibleFluid<Dim>& on, const InflowZone<Dim>& by, SameParticles, Real time, Real dt);

extern template class InflowZone<2>;
extern template class InflowZone<3>;
extern template class OutflowZone<2>;
extern template class OutflowZone<3>;

}  // namespace sph
