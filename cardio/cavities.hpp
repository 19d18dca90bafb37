#pragma once
// The cavities of a ventricular body as one system on the solid's particles: the cavity surfaces
// (cardio/cavity.hpp), carried by the solid's particles, and the pressure on each wall
// (cardio/cavity_pressure.hpp). Its interaction with the solid (libsph/core/interaction.hpp),
//   solid <- cavities   the follower pressure load of every active cavity on the wall,
// runs in the solid's loads slot (sph::ElasticSolid::loads_slot) at every mechanics sub-step, at
// the mid-step positions and F. The pressure of cavity c is
//   - p(t) of its CavityPressure (none, constant, ramp, or the value a circulation last set),
//     evaluated at the mid-step time t + dt/2; or,
//   - coupled to a 0D circulation (cardio/circulation_coupling.hpp), the penalty
//       p = p_ref + (V_b - V) / C_c
//     of the circulation's coupled ventricle (cardio/circulation.hpp) at the cavity's current volume V,
//     taken from the same moved surface (CavitySurface::add_pressure_forces with a pressure of the
//     volume), so the stiff penalty acts without the lag of a coupling step.
// On a distributed solid (libsph/core/distribution.hpp) a cavity's surface spans the ranks: every
// rank gathers the positions and F of the particles under the surface (sph::SharedSelection, one
// all-gather per load or volume), moves the whole surface as a serial run does, and adds the load
// to the particles it owns, each in the serial order: volumes, pressures and forces are bitwise
// those of one rank.

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "cardio/cavity.hpp"
#include "cardio/cavity_pressure.hpp"
#include "libsph/core/distribution.hpp"
#include "libsph/core/interaction.hpp"
#include "libsph/solid/elastic_solid.hpp"

namespace cardio {

class Cavities {
 public:
  /// The penalty p = reference_pressure + (blood_volume - V) / compliance of a coupled cavity.
  struct VolumePenalty {
    double reference_pressure = 0;  ///< p_ref [kPa]
    double blood_volume = 0;        ///< V_b [mm^3]
    double compliance = 1;          ///< C_c [mm^3/kPa]
  };

  /// `surfaces` (cardio::cavity_surfaces on the solid's reference positions) with the pressure of
  /// `settings`: lv_pressure on the LV endocardium, rv_pressure on any other. When loaded(),
  /// registers the solid's external force field, which the interaction adds to. The solid must outlive the system.
  Cavities(sph::ElasticSolid<3>& solid, std::vector<CavitySurface> surfaces, const CavityPressureSettings& settings);

  std::size_t size() const { return surfaces_.size(); }
  /// True if some cavity has a pressure (a mode other than none): the interaction has loads to add.
  bool loaded() const;
  /// The surface as built (its particle indices are those of the whole set: global ids).
  const CavitySurface& surface(std::size_t c) const { return surfaces_[c]; }
  /// "lv" for the LV endocardium, "rv" otherwise.
  std::string name(std::size_t c) const { return surfaces_[c].label == label_lv_endo ? "lv" : "rv"; }
  /// The index of the cavity with this label, if any.
  std::optional<std::size_t> find(SurfaceLabel label) const;
  /// The cavity volume at the solid's current positions and deformation gradient [mm^3].
  double volume(std::size_t c) const;
  CavityPressure& pressure(std::size_t c) { return pressures_[c]; }
  const CavityPressure& pressure(std::size_t c) const { return pressures_[c]; }
  /// Cavity c takes its pressure from the penalty from now on (see above).
  void couple(std::size_t c, const VolumePenalty& penalty) { penalties_[c] = penalty; }
  const std::optional<VolumePenalty>& penalty(std::size_t c) const { return penalties_[c]; }
  const sph::ElasticSolid<3>& solid() const { return solid_; }
  /// Saves or loads the pressures and the penalties (checkpoints).
  void checkpoint(sph::StateArchive& archive);
  /// Adds the pressure loads at the solid's current positions and F to `force` (see interact).
  void add_loads(Real mid_step_time, std::span<sph::Vec<3>> force) const;

 private:
  /// Positions and F of the particles under the surfaces, in selection order (gathered).
  void gather_state() const;

  const sph::ElasticSolid<3>& solid_;
  std::vector<CavitySurface> surfaces_;
  sph::SharedSelection<3> under_;       // the particles of every vertex stencil
  std::vector<CavitySurface> on_under_;  // the surfaces with their stencils indexed into under_
  std::vector<sph::Vec<3>> X_under_;
  mutable std::vector<sph::Vec<3>> x_under_, force_under_;
  mutable std::vector<sph::Mat<3>> F_under_;
  std::vector<CavityPressure> pressures_;
  std::vector<std::optional<VolumePenalty>> penalties_;
};

/// The pressure of every active cavity on the wall of the solid over the mechanics sub-step
/// [time, time + dt], at its midpoint (see above), added to the solid's external force in the
/// order of the cavities. `on` must be the solid the cavities were built on.
void interact(sph::ElasticSolid<3>& on, const Cavities& by, sph::SameParticles, Real time, Real dt);

}  // namespace cardio
