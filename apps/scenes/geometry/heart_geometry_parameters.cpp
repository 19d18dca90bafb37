#include <cstdlib>
#include "apps/scenes/geometry/heart_geometry_parameters.hpp"

#include <cmath>

namespace cardiosph {
namespace {

void require_file(const std::string& key, const std::filesystem::path& path) {
  if (path.empty()) return;
  if (!std::filesystem::is_regular_file(path))
    throw sph::ParameterError("parameter '" + key + "' = '" + path.string() + "': no such file");
}

}  // namespace

std::filesystem::path shipped_mesh(const std::string& file) { return std::filesystem::path(CARDIOSPH_MESH_DIR) / file; }

std::filesystem::path shared_mesh(const std::string& file) {
  if (const char* folder = std::getenv("CARDIOSPH_SHARED_MESHES"); folder && *folder) return std::filesystem::path(folder) / file;
  return std::filesystem::path(CARDIOSPH_SHARED_MESH_DIR) / file;
}

void HeartGeometryParameters::declare(sph::Parameters& p) {
  auto& s = settings;
  p.add_path("mesh", s.mesh,
             "myocardium: a closed surface (STL ascii or binary, OBJ, PLY) or a tetrahedral mesh (.vtu, or openCARP "
             ".pts/.elem with an optional .lon)");
  p.add_choice("units", units, {"um", "mm", "cm", "m"}, "length unit of the mesh files (openCARP meshes are usually in um)");
  p.add("scale", s.scale, "1", "multiplies the mesh coordinates after the units (e.g. to shrink a heart)", sph::Range::positive());
  p.add_text("surface_tags", s.surface_tags,
             "names of a tetrahedral mesh's boundary tags, e.g. 'epi=1,lv_endo=2,rv_endo=3,base=4' (empty: geometric rule)");
  p.add("repair", s.repair, "repair orientation and holes instead of rejecting a bad mesh");
  if (dp_from_preset)
    p.add("dp", s.spacing, "mm", "particle spacing (0: from the preset)", sph::Range::non_negative());
  else
    p.add("dp", s.spacing, "mm", "particle spacing", sph::Range::positive());
  p.add("relaxation_steps", s.relaxation_steps, "1", "particle relaxation steps (0: lattice)", sph::Range::non_negative());
  p.add_path("epi_surface", s.epi_surface, "separate epicardial surface mesh (labels by nearest surface)");
  p.add_path("lv_surface", s.lv_surface, "separate LV endocardial surface mesh");
  p.add_path("rv_surface", s.rv_surface, "separate RV endocardial surface mesh");
  p.add_path("base_surface", s.base_surface, "separate base surface mesh (default: the flat base found by the rule)");
  p.add_choice("fibres", s.fibres, {"auto", "ldrb", "mesh", "uniform", "file", "none"},
               "fibre rule (auto: interpolated from a tetrahedral mesh's fibre array when it has one, else ldrb)");
  p.add("alpha_endo", s.ldrb.alpha_endo_deg, "deg", "LDRB helix angle at the endocardium", sph::Range::closed(-90, 90));
  p.add("alpha_epi", s.ldrb.alpha_epi_deg, "deg", "LDRB helix angle at the epicardium", sph::Range::closed(-90, 90));
  p.add("beta_endo", s.ldrb.beta_endo_deg, "deg", "LDRB sheet angle at the endocardium", sph::Range::closed(-90, 90));
  p.add("beta_epi", s.ldrb.beta_epi_deg, "deg", "LDRB sheet angle at the epicardium", sph::Range::closed(-90, 90));
  p.add_vector("uniform_fibre", s.uniform_fibre, "-", "fibre direction x,y,z for fibres = uniform");
  p.add_vector("uniform_sheet", s.uniform_sheet, "-", "sheet direction x,y,z for fibres = uniform");
  p.add_path("fibre_file", s.fibre_file, "text file 'x y z fx fy fz [sx sy sz]' for fibres = file (nearest point)");
  p.add_text("cache", cache, "geometry cache folder ('' : $CARDIOSPH_CACHE or ~/.cache/cardiosph, 'none': off)");
}

cardio::HeartGeometrySettings HeartGeometryParameters::resolved(double preset_spacing) const {
  cardio::HeartGeometrySettings s = settings;
  if (s.spacing == 0) s.spacing = preset_spacing;
  s.scale *= geometry::millimetres_per_unit(units);
  if (s.mesh.empty()) throw sph::ParameterError("parameter 'mesh' is empty: give a mesh file");
  require_file("mesh", s.mesh);
  require_file("epi_surface", s.epi_surface);
  require_file("lv_surface", s.lv_surface);
  require_file("rv_surface", s.rv_surface);
  require_file("base_surface", s.base_surface);
  if (s.fibres == "file") {
    if (s.fibre_file.empty()) throw sph::ParameterError("parameter 'fibre_file' is empty but fibres = file");
    require_file("fibre_file", s.fibre_file);
  }
  const bool any_surface = !s.epi_surface.empty() || !s.lv_surface.empty() || !s.rv_surface.empty() || !s.base_surface.empty();
  if (any_surface && (s.epi_surface.empty() || s.lv_surface.empty()))
    throw sph::ParameterError("parameters 'epi_surface' and 'lv_surface' are both needed when surfaces are given separately");
  if (std::abs(s.uniform_fibre.normalized().dot(s.uniform_sheet.normalized())) > 1 - 1e-9)
    throw sph::ParameterError("parameters 'uniform_fibre' and 'uniform_sheet' are parallel");
  if (!(s.spacing > 0)) throw sph::ParameterError("parameter 'dp' must be positive");
  return s;
}

std::filesystem::path HeartGeometryParameters::cache_folder() const {
  if (cache == "none") return {};
  return cache.empty() ? cardio::default_cache_folder() : std::filesystem::path(cache);
}

sph::ParticleSet<3> make_particle_set(const cardio::HeartGeometry& geometry, const std::string& name) {
  const std::size_t n = geometry.body.size();
  std::vector<sph::Vec<3>> x(n);
  std::vector<sph::Real> v(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = geometry.body.positions[i].cast<sph::Real>();
    v[i] = sph::Real(geometry.body.volumes[i]);
  }
  return sph::ParticleSet<3>(name, std::move(x), std::move(v));
}

std::vector<cardio::SurfaceLabel> cavity_face_labels(const geometry::TriangleMesh& mesh, const cardio::HeartGeometry& geometry) {
  if (geometry.label_method == "surfaces") return {};
  return cardio::label_faces(mesh).face;
}

geometry::TriangleMesh read_geometry_mesh(const cardio::HeartGeometrySettings& settings) {
  return cardio::read_heart_surface(settings);
}

}  // namespace cardiosph
