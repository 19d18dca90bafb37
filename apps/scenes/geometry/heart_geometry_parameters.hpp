#pragma once
// Parameters of the cached heart-geometry stage (cardio/heart_geometry.hpp), declared the same way
// by every scene that starts from a mesh.

#include <filesystem>
#include <string>

#include "cardio/heart_geometry.hpp"
#include "libsph/core/particles.hpp"
#include "libsph/io/parameters.hpp"

namespace cardiosph {

/// Three numbers "x,y,z" (commas or spaces) of parameter `key`; throws sph::ParameterError naming
/// it when malformed, or when zero unless allow_zero (directions).
geometry::Vec3 parse_vector(const std::string& key, const std::string& text, bool allow_zero = false);

/// The shipped meshes (meshes/ of the source tree).
std::filesystem::path shipped_mesh(const std::string& file);

struct HeartGeometryParameters {
  std::string mesh;           ///< path; default set by the scene
  double scale = 1.0;
  bool repair = false;
  double dp = 0.5;
  bool dp_from_preset = false;  ///< declare dp = 0 as "from the scene's preset"
  long relaxation_steps = 100;
  std::string epi_surface, lv_surface, rv_surface, base_surface;
  std::string fibres = "ldrb";
  double alpha_endo = 60, alpha_epi = -60, beta_endo = 0, beta_epi = 0;
  std::string uniform_fibre = "1,0,0", uniform_sheet = "0,1,0";
  std::string fibre_file;
  std::string cache;          ///< folder; "" = default, "none" = no cache

  void declare(sph::Parameters& p);
  /// Checks and converts; throws sph::ParameterError naming the parameter.
  cardio::HeartGeometrySettings settings() const;
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
