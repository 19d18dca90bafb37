#include "cardio/boundary_springs.hpp"

#include <stdexcept>

namespace cardio {

BoundarySprings::BoundarySprings(sph::ElasticSolid<3>& solid, std::vector<CavitySurface> surfaces, Real pericardium_stiffness,
                                 Real base_stiffness)
    : solid_(solid), surfaces_(std::move(surfaces)) {
  bool has_base = false;
  for (const auto& surface : surfaces_) {
    const bool normal_only = surface.label == label_epi;
    has_base = has_base || surface.label == label_base;
    const Real k = normal_only ? pericardium_stiffness : base_stiffness;
    if (k == 0) continue;
    Spring spring{&surface, k, normal_only, {}};
    const sph::SharedSelection<3> loaded(solid.particles(), surface.loaded_particles);
    for (std::size_t m = 0; m < loaded.size(); ++m) spring.owned.push_back(loaded.owned(m));
    springs_.push_back(std::move(spring));
  }
  if (!has_base)
    throw std::invalid_argument("boundary springs: no mesh face is labelled base, so the springs have no base to hold "
                                "(use base_condition = clamp)");
  if (!springs_.empty()) (void)solid.external_force_field();
}

void interact(sph::ElasticSolid<3>& on, const BoundarySprings& by, sph::SameParticles, Real, Real) {
  if (&on != &by.solid()) throw std::invalid_argument("boundary springs: the springs were built on another solid");
  auto& body = on.particles();
  const auto X = body.field(on.reference_position_field());
  const auto force = body.field(on.external_force_field());
  for (const auto& [surface, k, normal_only, owned] : by.springs())
    for (std::size_t m = 0; m < surface->loaded_particles.size(); ++m) {
      const auto i = owned[m];
      if (i == sph::SharedSelection<3>::not_owned) continue;
      const sph::Vec<3> u = body.position[i] - X[i], A = surface->area_normals[m];
      force[i] -= normal_only ? sph::Vec<3>(k * u.dot(A) / A.norm() * A) : sph::Vec<3>(k * A.norm() * u);
    }
}

}  // namespace cardio
