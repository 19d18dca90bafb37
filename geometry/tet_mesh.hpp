#pragma once
// Tetrahedral meshes as cardiac users have them, with fibres, sheets and region tags:
//  - VTK XML unstructured grids (.vtu): tetrahedra (other cells are ignored), a fibre and a sheet
//    array on the points or on the cells, and a region array on the cells (names below);
//  - the openCARP triple: `<base>.pts` (count, then x y z per line), `<base>.elem` (count, then
//    "Tt n0 n1 n2 n3 tag" per line; other element types are refused), and the optional `<base>.lon`
//    (first line 1 or 2: fibre, or fibre and sheet, per element; then one line per element).
//    Triangle cells of a .vtu that carry the region array tag the boundary faces they cover.
// Coordinates are multiplied by the caller's scale (units: um 1e-3, mm 1, cm 10, m 1000; the scenes
// work in mm). The boundary surface (faces used by one tetrahedron, oriented outwards) feeds the
// triangle-mesh pipeline of the particle generation; a locator finds the tetrahedron holding a
// point, for interpolating the fibres to the particles. No VTK type appears here.

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "geometry/mesh.hpp"

namespace geometry {

struct TetMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<std::uint32_t, 4>> tets;
  std::vector<int> tet_region;   ///< region tag per tetrahedron (0 when the file has none)

  enum class FibreLocation { none, points, cells };
  FibreLocation fibre_location = FibreLocation::none;
  std::vector<Vec3> fibre;       ///< per point or per cell (see fibre_location); empty when none
  std::vector<Vec3> sheet;       ///< same size as fibre, or empty when the file has no sheets

  /// Tagged boundary triangles given in the file (triangle cells of a .vtu with the region array);
  /// boundary_surface gives the faces they match their tags.
  std::vector<std::array<std::uint32_t, 3>> tagged_faces;
  std::vector<int> tagged_face_region;

  std::size_t n_tets() const { return tets.size(); }
  /// Six times the signed volume of tetrahedron t (positive for VTK's ordering: n3 on the side of
  /// the face n0 n1 n2 that its right-hand normal points to).
  double signed_volume6(std::size_t t) const;
};

/// The factor from `units` (um, mm, cm, m) to mm. Throws MeshError naming `units` otherwise.
double millimetres_per_unit(const std::string& units);

/// True for the extensions read by read_tet_mesh (.vtu, .pts, .elem, .lon).
bool is_tet_mesh_file(const std::filesystem::path& path);

/// The files an openCARP mesh `path` (any of .pts, .elem, .lon, or the base name) consists of:
/// .pts, .elem, and .lon when it exists. Empty vector for other files.
std::vector<std::filesystem::path> tet_mesh_files(const std::filesystem::path& path);

/// Reads a .vtu or openCARP mesh and multiplies the coordinates by `scale`. Array names in a .vtu,
/// case-insensitive: fibre | fiber | fibres | fibers | f0 | fibre_direction | fiber_direction;
/// sheet | sheets | s0 | sheet_direction; region | regions | tag | tags | elemtag | material |
/// gmsh:physical | cell_region. Throws MeshError naming the file and, where there is one, the line
/// or element: missing or unreadable file, no tetrahedra, an element type that is not a
/// tetrahedron (openCARP), a vertex index out of range, non-finite coordinates or fibres, a zero
/// fibre, a fibre array whose length is neither the number of points nor of cells, a .lon with the
/// wrong number of lines.
TetMesh read_tet_mesh(const std::filesystem::path& path, double scale = 1.0);

/// What check_tet_mesh found and did.
struct TetMeshCheck {
  std::size_t vertices = 0, tets = 0, unused_vertices = 0;
  double volume = 0;              ///< total volume
  double min_quality = 0;         ///< smallest 6 sqrt(2) V / l_max^3 (1 for a regular tetrahedron)
  bool reoriented = false;        ///< every tetrahedron was negative: all were flipped
};

/// Checks a mesh and orients it: throws MeshError naming `name` and the first bad element (0-based
/// index, its vertices and the value): degenerate (6 |V| <= 1e-9 l_max^3 or a repeated vertex),
/// inverted (negative while most are positive, or positive while most are negative: a mesh whose
/// tetrahedra are all negative is flipped as a whole), a non-manifold face (shared by three
/// tetrahedra or more), a non-finite or zero fibre.
TetMeshCheck check_tet_mesh(TetMesh& mesh, const std::string& name);

/// The boundary surface: faces used by exactly one tetrahedron, oriented away from it, with the
/// vertices renumbered. Face regions are named "tag N": N is the tag of the matching tagged
/// triangle, else that of the face's tetrahedron; one region "" when all faces have one tag.
TriangleMesh boundary_surface(const TetMesh& mesh);

/// Vertex indices from an openCARP .vtx file (first line the count, an optional line "intra" or
/// "extra", then one index per line), each below `n_vertices`. Throws MeshError naming the file
/// and line: missing file, a count that does not match, an index out of range or not an integer.
std::vector<std::size_t> read_vertex_list(const std::filesystem::path& path, std::size_t n_vertices);

/// Writes a .vtu (VTK, the fibres and sheets under "fibre" and "sheet", tags under "region") or an
/// openCARP triple (path ending in .pts, .elem or without extension: base name; coordinates
/// divided by `scale`, e.g. 1e-3 to write um; a .lon only for cell fibres), atomically.
void write_tet_mesh(const TetMesh& mesh, const std::filesystem::path& path, double scale = 1.0);

/// Finds the tetrahedron that holds a point, through a uniform grid of the tetrahedra's boxes.
/// Thread-safe queries.
class TetLocator {
 public:
  explicit TetLocator(const TetMesh& mesh);
  struct Hit {
    std::size_t tet = 0;
    std::array<double, 4> weights{};  ///< barycentric coordinates (clamped to >= 0, sum 1)
    bool inside = true;               ///< false: the point lies outside; nearest tetrahedron
  };
  Hit locate(const Vec3& p) const;

 private:
  const TetMesh& mesh_;
  Vec3 lower_;
  double cell_ = 1;
  std::array<long, 3> cells_{};
  std::vector<std::vector<std::uint32_t>> bins_;
  long cell_of(double x, int d) const;
};

}  // namespace geometry
