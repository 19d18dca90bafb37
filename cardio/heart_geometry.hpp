#pragma once
// The preprocessing stage of every scene that starts from a heart mesh, as one cached step:
// mesh (read, weld, check or repair) -> particles (lattice + relaxation) -> surface labels ->
// fibres and sheets. The result is stored under a hash of the inputs (the bytes of every file read
// and every setting), so a second run with the same inputs reads it back and any change regenerates
// it. There is no separate relax-then-reload step.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "cardio/fibres.hpp"
#include "cardio/surface_labels.hpp"
#include "geometry/mesh.hpp"
#include "geometry/particle_generation.hpp"
#include "geometry/tet_mesh.hpp"

namespace cardio {

struct HeartGeometrySettings {
  /// Myocardium: a closed surface (STL, OBJ, PLY) or a tetrahedral mesh (.vtu, or openCARP
  /// .pts/.elem/.lon; geometry/tet_mesh.hpp) whose boundary is the surface.
  std::filesystem::path mesh;
  double scale = 1.0;             ///< multiplies the mesh coordinates (1: the file is in mm)
  /// Names of the region tags of a tetrahedral mesh's boundary, "epi=1,lv_endo=2,rv_endo=3,base=4"
  /// (empty: the geometric rule labels the surface).
  std::string surface_tags;
  bool repair = false;            ///< repair orientation and holes instead of rejecting the mesh
  double spacing = 0.5;           ///< particle spacing dp [mm]
  long relaxation_steps = 100;
  /// Separate surfaces labelling the particles by the nearest one (all empty: use the mesh's
  /// regions or the geometric rule). The base may be left empty: it is then found by the rule.
  std::filesystem::path epi_surface, lv_surface, rv_surface, base_surface;
  /// auto (the tetrahedral mesh's fibres when it has them, else ldrb) | ldrb | mesh | uniform | file | none
  std::string fibres = "auto";
  LdrbSettings ldrb;
  geometry::Vec3 uniform_fibre = geometry::Vec3::UnitX(), uniform_sheet = geometry::Vec3::UnitY();
  std::filesystem::path fibre_file;
};

struct HeartGeometry {
  geometry::BodyParticles body;
  std::vector<std::int8_t> labels;   ///< SurfaceLabel per particle
  FibreField fibres;                 ///< empty vectors when settings.fibres == "none"
  geometry::MeshCheckReport mesh_check;
  std::string label_method;          ///< regions | geometric rule | surfaces
  std::string fibre_method;          ///< ldrb | mesh (points) | mesh (cells) | uniform | file | none
  std::size_t tets = 0;              ///< tetrahedra of the mesh (0: a surface mesh)
  std::size_t fibre_particles_outside = 0;  ///< fibres = mesh: particles outside every tetrahedron
  geometry::Vec3 base_normal = geometry::Vec3::UnitZ();
  std::string hash;                  ///< of the inputs (hex)
  bool from_cache = false;
  double seconds = 0;                ///< wall time of this call (reading the cache or generating)
};

/// The myocardium's closed surface: the mesh file itself (read, welded, repaired if asked) or the
/// boundary of a tetrahedral mesh (checked and oriented; `tets` receives it when not null) with
/// its region tags named by `surface_tags`. Not yet checked for closedness (require_valid_mesh).
/// Throws geometry::MeshError / std::invalid_argument naming the file.
geometry::TriangleMesh read_heart_surface(const HeartGeometrySettings& settings, geometry::TetMesh* tets = nullptr);

/// Runs the stage, or reads its result from `cache_folder` (empty: no cache). `log` receives one
/// line per step. Throws geometry::MeshError / std::invalid_argument on bad input (nothing is
/// cached then).
HeartGeometry prepare_heart_geometry(const HeartGeometrySettings& settings, const std::filesystem::path& cache_folder,
                                     const std::function<void(const std::string&)>& log = {});

/// The default cache folder: $CARDIOSPH_CACHE, else $XDG_CACHE_HOME/cardiosph, else ~/.cache/cardiosph.
std::filesystem::path default_cache_folder();

}  // namespace cardio
