#include "apps/scenes/electromechanics/em_setup.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include "libsph/core/distribution.hpp"

namespace cardiosph {

std::vector<sph::Index> attach_heart_geometry(sph::ElasticSolid<3>& solid, const cardio::HeartGeometry& geometry,
                                              const std::string& scene, sph::Real clamp_depth, bool clamp) {
  auto& body = solid.particles();
  const std::size_t n = geometry.labels.size();  // the whole set (every rank's particles)
  if (geometry.fibres.fibre.size() != n || geometry.fibres.sheet.size() != n || (!body.partition() && body.n_particles() != n))
    throw std::invalid_argument(scene + ": the geometry has no fibre and sheet per particle");
  auto f = body.field(solid.fibre_field());
  auto s = body.field(solid.sheet_field());
  for (std::size_t i = 0; i < body.n_particles(); ++i) {
    const auto id = sph::global_index(body, i);
    f[i] = geometry.fibres.fibre[id].cast<sph::Real>().normalized();
    s[i] = geometry.fibres.sheet[id].cast<sph::Real>().normalized();
  }
  // The base in global ids, found on the whole set (the same on every rank).
  const auto& x = geometry.body.positions;
  std::vector<sph::Index> base;
  for (std::size_t i = 0; i < n; ++i)
    if (geometry.labels[i] == cardio::label_base) base.push_back(static_cast<sph::Index>(i));
  if (base.empty()) throw std::invalid_argument(scene + ": no particle is labelled base, so the base cannot be fixed");
  if (clamp_depth > 0) {
    const sph::Vec<3> normal = geometry.base_normal.cast<sph::Real>();
    sph::Real plane = -std::numeric_limits<sph::Real>::infinity();
    for (const auto i : base) plane = std::max(plane, normal.dot(x[i].cast<sph::Real>()) + sph::Real(geometry.body.depth[i]));
    base.clear();
    for (std::size_t i = 0; i < n; ++i)
      if (normal.dot(x[i].cast<sph::Real>()) >= plane - clamp_depth) base.push_back(static_cast<sph::Index>(i));
  }
  if (clamp) solid.clamp(sph::local_indices(body, std::span<const sph::Index>(base), false));
  return base;
}

}  // namespace cardiosph
