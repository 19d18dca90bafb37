#pragma once
// A small solid with closed tetrahedral cavities whose vertices move with single particles, for the
// tests of the cavities, the boundary springs and the circulation coupling.

#include <array>
#include <stdexcept>

#include "cardio/cavity.hpp"
#include "geometry/lattice.hpp"
#include "libsph/core/neighbour_relation.hpp"
#include "libsph/solid/elastic_solid.hpp"

namespace tetrahedral_cavity {

using sph::Real;
using Vec3 = sph::Vec<3>;

/// A 4 x 4 x 4 lattice of unit spacing with a neo-Hookean solid on it.
struct Block {
  sph::ParticleSet<3> body = geometry::lattice_box<3>("block", Vec3::Zero(), Vec3::Constant(4), Real(1));
  sph::InnerRelation<3> relation = sph::build_inner_relation<3>(body.position, sph::make_kernel<3>("wendland_c2"), Real(1.3));
  sph::ElasticSolid<3> solid{body, relation, settings()};
  static sph::ElasticSolid<3>::Settings settings() {
    sph::ElasticSolid<3>::Settings s;
    s.material = sph::NeoHookean<3>{Real(1), Real(1)};
    return s;
  }
};

/// The closed surface of the tetrahedron on particles p, its faces oriented into the cavity (outward
/// of the "myocardium" around it, as cardio::cavity_surfaces orients them), each vertex moved by its
/// particle alone.
inline cardio::CavitySurface tetrahedron(const sph::ParticleSet<3>& body, std::array<sph::Index, 4> p, cardio::SurfaceLabel label) {
  cardio::CavitySurface s;
  s.label = label;
  for (const auto i : p) s.reference_vertices.push_back(body.position[i]);
  s.faces = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
  s.stencil_offsets = {0, 1, 2, 3, 4};
  s.stencil_particle = {p[0], p[1], p[2], p[3]};
  s.stencil_weight = {1, 1, 1, 1};
  s.loaded_particles = {p[0], p[1]};
  s.area_normals = {Vec3(0, 0, -2), Vec3(3, 4, 0)};  // |A| 2 and 5
  s.reference_volume = cardio::closed_cavity_volume(s.reference_vertices, s.faces, s.border);
  return s;
}

inline sph::Index at(const sph::ParticleSet<3>& body, const Vec3& x) {
  for (std::size_t i = 0; i < body.n_particles(); ++i)
    if ((body.position[i] - x).norm() < 1e-9) return static_cast<sph::Index>(i);
  throw std::logic_error("no particle there");
}

/// The particles at c, c + 2 e_x, c + 2 e_y and c + 2 e_z, c = (0.5, 0.5, 0.5) + offset.
inline std::array<sph::Index, 4> corners(const sph::ParticleSet<3>& body, const Vec3& offset = Vec3::Zero()) {
  const Vec3 c = Vec3::Constant(Real(0.5)) + offset;
  return {at(body, c), at(body, c + Vec3(2, 0, 0)), at(body, c + Vec3(0, 2, 0)), at(body, c + Vec3(0, 0, 2))};
}

}  // namespace tetrahedral_cavity
