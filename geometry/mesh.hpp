#pragma once
// Triangle meshes: reading (STL ascii/binary, OBJ, PLY through assimp), welding by position,
// checks (closed, manifold, consistently and outwardly oriented, free of self-intersections,
// positive volume; CGAL), optional repair, writing, and the mesh as a Shape with an AABB tree for
// signed distance and nearest-face queries. No assimp or CGAL type appears here.

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>  // Vec3::cross, which every user of face normals needs

#include "geometry/shape.hpp"

namespace geometry {

/// Bad mesh input (unreadable, empty, open, inverted, self-intersecting...). The message names the
/// file and the problem; applications turn it into exit code 2.
class MeshError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<std::uint32_t, 3>> faces;
  /// Region of each face (index into region_names), from the file's named parts (OBJ groups or
  /// objects, ASCII STL solids); one region "" when the file has no parts. Same size as faces.
  std::vector<int> face_region;
  std::vector<std::string> region_names;

  std::size_t n_faces() const { return faces.size(); }
  Aabb bounding_box() const;
};

/// Reads `path`, multiplies coordinates by `scale` (e.g. 1000 for a file in metres when the scene
/// works in mm) and welds vertices that share a position (assimp's own joining keys on normals too,
/// which leaves an STL open). Throws MeshError: missing or unreadable file, not a mesh, no faces,
/// truncated binary STL, non-finite coordinates.
TriangleMesh read_mesh(const std::filesystem::path& path, double scale = 1.0);

/// What check_mesh found. Counts are of edges (undirected) and faces.
struct MeshCheckReport {
  std::size_t vertices = 0, faces = 0;
  std::size_t degenerate_faces = 0;        ///< zero area or repeated vertex
  std::size_t border_edges = 0;            ///< used by one face: the mesh is open
  std::size_t non_manifold_edges = 0;      ///< used by three faces or more
  std::size_t inconsistent_edges = 0;      ///< two faces traversing the edge in the same direction
  std::size_t self_intersecting_faces = 0; ///< faces involved in at least one intersecting pair
  std::size_t components = 0;              ///< connected components (shells)
  double volume = 0;                       ///< signed enclosed volume (negative: inward normals)
  /// True when closed, manifold, consistently oriented, without self-intersection or degenerate
  /// face, and the volume is positive.
  bool ok() const;
  /// The problems found, one per line ("" when ok()).
  std::string problems() const;
};

/// Throws MeshError if a face refers to a vertex that does not exist or a coordinate is not finite
/// (a mesh built in code; read_mesh never returns one). check_mesh, repair_mesh and MeshShape call
/// it first; `name` ("" for none) goes into the message.
void require_well_formed(const TriangleMesh& mesh, const std::string& name);

MeshCheckReport check_mesh(const TriangleMesh& mesh);

/// check_mesh, then a MeshError naming `name` and every problem with its count if it is not ok().
MeshCheckReport require_valid_mesh(const TriangleMesh& mesh, const std::string& name);

/// Repairs what can be repaired without guessing: removes degenerate faces, orients the faces
/// consistently and outwards, fills holes. Self-intersections are not repaired.
TriangleMesh repair_mesh(const TriangleMesh& mesh);

/// Writes binary STL (.stl), OBJ (.obj, one group per region) or OFF (.off, e.g. for TetGen) by
/// extension, atomically.
void write_mesh(const TriangleMesh& mesh, const std::filesystem::path& path);

/// Faces of `mesh` whose region is `region` (vertices renumbered), e.g. to write one surface.
TriangleMesh extract_region(const TriangleMesh& mesh, int region);

/// A triangle mesh with an AABB tree. As a Shape it must be closed and outward (signed distance by
/// the tree's closest point, sign by ray parity); as a surface (closed or not) it answers the
/// unsigned distance and the nearest face. Queries are thread-safe.
class MeshShape final : public Shape {
 public:
  /// `closed`: the mesh passed the checks and may be used for inside/outside.
  MeshShape(TriangleMesh mesh, bool closed, std::string name);
  ~MeshShape() override;
  MeshShape(const MeshShape&) = delete;
  MeshShape& operator=(const MeshShape&) = delete;

  double signed_distance(const Vec3& p) const override;
  Vec3 normal(const Vec3& p) const override;
  Aabb bounding_box() const override;
  std::optional<double> volume() const override;
  std::string describe() const override;

  double unsigned_distance(const Vec3& p) const;
  /// Index of the face nearest to p.
  std::size_t nearest_face(const Vec3& p) const;
  const TriangleMesh& mesh() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace geometry
