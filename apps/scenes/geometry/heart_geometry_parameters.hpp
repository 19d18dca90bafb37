#pragma once
// Parameters of the cached heart-geometry stage (cardio/heart_geometry.hpp), declared the same way
// by every scene that starts from a mesh.

#include <filesystem>
#include <string>

#include "cardio/heart_geometry.hpp"
#include "libsph/core/particles.hpp"
#include "libsph/io/parameters.hpp"

namespace cardiosph {

/// The shipped meshes (meshes/ of the source tree).
std::filesystem::path shipped_mesh(const std::string& file);
/// Third-party meshes that the project does not ship: $CARDIOSPH_SHARED_MESHES, else
/// ../shared/meshes beside the source tree.
std::filesystem::path shared_mesh(const std::string& file);

/// The parameters of the geometry stage: the members of its settings (cardio::HeartGeometrySettings)
/// bound directly, and the cache folder.
struct HeartGeometryParameters {
  cardio::HeartGeometrySettings settings;  ///< mesh: set by the scene; spacing is the parameter dp
  std::string cache;                       ///< folder; "" = default, "none" = no cache
  std::string units = "mm";                ///< of the mesh files; resolved() folds it into the scale
  bool dp_from_preset = false;             ///< declare dp = 0 as "from the scene's preset"

  void declare(sph::Parameters& p);
  /// The settings with dp = 0 replaced by `preset_spacing`, after checking the files and the
  /// combinations; throws sph::ParameterError naming the parameter.
  cardio::HeartGeometrySettings resolved(double preset_spacing = 0) const;
  std::filesystem::path cache_folder() const;
};

/// The particles of a prepared geometry (positions and volumes) as a particle set.
sph::ParticleSet<3> make_particle_set(const cardio::HeartGeometry& geometry, const std::string& name);

/// Face labels of the mesh for cardio::cavity_surfaces: the mesh's own (regions or the geometric
/// rule), or none (nearest labelled particle) when the geometry was labelled by separate surfaces.
std::vector<cardio::SurfaceLabel> cavity_face_labels(const geometry::TriangleMesh& mesh, const cardio::HeartGeometry& geometry);

/// The mesh of the geometry settings, read (and repaired) the way the geometry stage reads it.
geometry::TriangleMesh read_geometry_mesh(const cardio::HeartGeometrySettings& settings);

}  // namespace cardiosph
