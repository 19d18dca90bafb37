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

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "cardio/cavity.hpp"
#include "cardio/cavity_pressure.hpp"
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

 private:
  const sph::ElasticSolid<3>& solid_;
  std::vector<CavitySurface> surfaces_;
  std::vector<CavityPressure> pressures_;
  std::vector<std::optional<VolumePenalty>> penalties_;
};

/// The pressure of every active cavity on the wall of the solid over the mechanics sub-step
/// [time, time + dt], at its midpoint (see above), added to the solid's external force in the
/// order of the cavities. `on` must be the solid the cavities were built on.
void interact(sph::ElasticSolid<3>& on, const Cavities& by, sph::SameParticles, Real time, Real dt);

}  // namespace cardio
