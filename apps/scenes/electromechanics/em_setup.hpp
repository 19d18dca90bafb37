#pragma once
// What the mesh-based electromechanics scenes share when they build the solid.

#include <string>
#include <vector>

#include "cardio/heart_geometry.hpp"
#include "libsph/solid/elastic_solid.hpp"

namespace cardiosph {

/// Copies the geometry's fibres and sheets into the solid and clamps the particles labelled base
/// (clamp_depth = 0) or every particle within clamp_depth of the base plane (the outermost point
/// x + depth n of the base particles along the base normal n); returns
/// them as indices of the whole set (global ids on a distributed body, whose fibres are set on
/// every local particle) (fixed only with `clamp`; otherwise the caller holds them, e.g. by springs). Throws
/// std::invalid_argument naming `scene` when no particle is labelled base.
std::vector<sph::Index> attach_heart_geometry(sph::ElasticSolid<3>& solid, const cardio::HeartGeometry& geometry,
                                              const std::string& scene, sph::Real clamp_depth = 0,
                                              bool clamp = true);

}  // namespace cardiosph
