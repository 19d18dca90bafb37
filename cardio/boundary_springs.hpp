#pragma once
// The pericardium and the base of a ventricular body as springs on its surface particles: a system
// on the solid's particles whose interaction (libsph/core/interaction.hpp),
//   solid <- springs   the spring forces on the epicardium and the base,
// runs in the solid's loads slot (sph::ElasticSolid::loads_slot). Per reference area A_i n_i of the
// mesh faces nearest to each surface particle (CavitySurface::area_normals), on the displacement
// u = x - X:
//   epicardium: f_i = -k_peri (u_i . n_i) n_i |A_i|   (normal Robin condition: the pericardial sac
//               resists motion along the normal and lets the wall slide along it);
//   base:       f_i = -k_base u_i |A_i|               (every direction).
// As in the pericardium model of Pfaller et al. 2019 (Biomech. Model. Mechanobiol. 18:503) and
// Regazzoni et al. 2022 (J. Comput. Phys. 457:111083), without their damping term (the solid's
// velocity damping stands for it).
// On a distributed solid each rank adds the forces on the surface particles it owns.

#include <vector>

#include "cardio/cavity.hpp"
#include "libsph/core/distribution.hpp"
#include "libsph/core/interaction.hpp"
#include "libsph/solid/elastic_solid.hpp"

namespace cardio {

class BoundarySprings {
 public:
  struct Spring {
    const CavitySurface* surface = nullptr;
    Real stiffness = 0;        ///< [force / length^3]: k per area
    bool normal_only = false;  ///< the epicardium: along the normal only
    /// Per entry of the surface's loaded_particles: its owned local index on this rank, or
    /// sph::SharedSelection<3>::not_owned.
    std::vector<sph::Index> owned;
  };

  /// The epicardium (label_epi) and base (label_base) surfaces of cardio::cavity_surfaces, with
  /// k_peri = pericardium_stiffness and k_base = base_stiffness (a spring of stiffness 0 is left
  /// out). With a spring, registers the solid's external force field. Throws std::invalid_argument if no surface is
  /// labelled base. The solid must outlive the system.
  BoundarySprings(sph::ElasticSolid<3>& solid, std::vector<CavitySurface> surfaces, Real pericardium_stiffness,
                  Real base_stiffness);
  BoundarySprings(const BoundarySprings&) = delete;  // the springs point into the surfaces

  /// The springs in the order their forces are added: the epicardium, then the base.
  const std::vector<Spring>& springs() const { return springs_; }
  const sph::ElasticSolid<3>& solid() const { return solid_; }

 private:
  const sph::ElasticSolid<3>& solid_;
  std::vector<CavitySurface> surfaces_;
  std::vector<Spring> springs_;
};

/// Adds the spring forces (see above) at the current positions to the solid's external force.
/// `on` must be the solid the springs were built on.
void interact(sph::ElasticSolid<3>& on, const BoundarySprings& by, sph::SameParticles, Real time, Real dt);

}  // namespace cardio
