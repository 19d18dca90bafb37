// A triangle mesh as a Shape: CGAL AABB tree over the triangles (Epick kernel) for the closest
// point, ray parity on the same tree for inside/outside.
//
// The ray parity is CGAL's internal::Point_inside_vertical_ray_cast, which is what
// CGAL::Side_of_triangle_mesh runs when it is given a tree. Side_of_triangle_mesh itself cannot
// take our tree in CGAL 5.5: its operator() also holds the code that builds a tree of
// AABB_face_graph_triangle_primitive from a face graph, which does not compile for a tree of
// plain triangles (and a face graph needs a manifold mesh, which an open surface need not be).
// The cast shoots a vertical ray and counts crossings, retrying with seeded random rays when the
// ray grazes an edge or vertex; exact predicates (Epick) decide each crossing.
//
// Thread safety: the tree and its internal KD-tree for distance queries are built in the
// constructor (rebuild(), accelerate_distance_queries()), so every query afterwards only reads
// shared state and may run on many threads. The ray cast keeps its random generator on the stack.

#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>  // cross
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/internal/Side_of_triangle_mesh/Point_inside_vertical_ray_cast.h>

#include "geometry/mesh.hpp"

namespace geometry {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
using RayCast = CGAL::internal::Point_inside_vertical_ray_cast<Kernel, Tree>;

Point point(const Vec3& v) { return {v.x(), v.y(), v.z()}; }
Vec3 vec(const Point& p) { return {p.x(), p.y(), p.z()}; }

}  // namespace

struct MeshShape::Impl {
  TriangleMesh mesh;
  bool closed;
  std::string name;
  Aabb box;
  double enclosed_volume = 0;
  double on_surface_distance = 0;  // below this distance, normal() takes the face normal
  std::vector<Triangle> triangles;        // the non-degenerate faces, in the tree
  std::vector<std::size_t> face_of;       // triangles[k] is mesh face face_of[k]
  std::vector<Vec3> face_normal;          // unit normal of each tree triangle
  Tree tree;
  CGAL::Bbox_3 tree_box;

  CGAL::Bounded_side side(const Point& q) const {
    const CGAL::Bbox_3& b = tree_box;  // outside the box: outside (as Side_of_triangle_mesh does)
    if (q.x() < b.xmin() || q.x() > b.xmax() || q.y() < b.ymin() || q.y() > b.ymax() || q.z() < b.zmin() ||
        q.z() > b.zmax())
      return CGAL::ON_UNBOUNDED_SIDE;
    return RayCast()(q, tree);
  }

  void require_closed(const char* query) const {
    if (!closed)
      throw std::logic_error("MeshShape::" + std::string(query) + ": mesh '" + name +
                             "' was not declared closed, so it has no inside");
  }

  std::size_t triangle_nearest(const Point& q, Point& closest) const {
    const auto [c, id] = tree.closest_point_and_primitive(q);
    closest = c;
    return static_cast<std::size_t>(id - triangles.cbegin());
  }
};

MeshShape::MeshShape(TriangleMesh mesh, bool closed, std::string name) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.mesh = std::move(mesh);
  m.closed = closed;
  m.name = std::move(name);
  require_well_formed(m.mesh, m.name);
  m.box = m.mesh.bounding_box();
  m.on_surface_distance = 1e-12 * m.box.extent().norm();

  const Vec3 centre = 0.5 * (m.box.lower + m.box.upper);
  double six_volume = 0;  // divergence theorem, as in check_mesh
  m.triangles.reserve(m.mesh.faces.size());
  for (std::size_t f = 0; f < m.mesh.faces.size(); ++f) {
    const auto& face = m.mesh.faces[f];
    const Vec3 &a = m.mesh.vertices[face[0]], &b = m.mesh.vertices[face[1]], &c = m.mesh.vertices[face[2]];
    six_volume += (a - centre).dot((b - centre).cross(c - centre));
    const Triangle triangle(point(a), point(b), point(c));
    if (triangle.is_degenerate()) continue;  // has no closest point of its own; its edges belong to neighbours
    m.triangles.push_back(triangle);
    m.face_of.push_back(f);
    m.face_normal.push_back((b - a).cross(c - a).normalized());
  }
  m.enclosed_volume = six_volume / 6;
  if (m.triangles.empty()) throw MeshError("mesh '" + m.name + "': no face of non-zero area");

  m.tree.rebuild(m.triangles.cbegin(), m.triangles.cend());
  m.tree.accelerate_distance_queries();
  m.tree_box = m.tree.bbox();
}

MeshShape::~MeshShape() = default;

double MeshShape::signed_distance(const Vec3& p) const {
  impl_->require_closed("signed_distance");
  const Point q = point(p);
  const double distance = std::sqrt(impl_->tree.squared_distance(q));
  switch (impl_->side(q)) {
    case CGAL::ON_BOUNDED_SIDE: return -distance;
    case CGAL::ON_BOUNDARY: return 0.0;
    default: return distance;
  }
}

Vec3 MeshShape::normal(const Vec3& p) const {
  impl_->require_closed("normal");
  const Point q = point(p);
  Point closest;
  const std::size_t k = impl_->triangle_nearest(q, closest);
  const Vec3 away = p - vec(closest);
  const double distance = away.norm();
  if (distance <= impl_->on_surface_distance) return impl_->face_normal[k];
  switch (impl_->side(q)) {
    case CGAL::ON_BOUNDED_SIDE: return -away / distance;
    case CGAL::ON_BOUNDARY: return impl_->face_normal[k];
    default: return away / distance;
  }
}

Aabb MeshShape::bounding_box() const { return impl_->box; }

std::optional<double> MeshShape::volume() const {
  impl_->require_closed("volume");
  return impl_->enclosed_volume;
}

std::string MeshShape::describe() const {
  return "mesh '" + impl_->name + "' (" + std::to_string(impl_->mesh.n_faces()) + " faces" +
         (impl_->closed ? ")" : ", open surface)");
}

double MeshShape::unsigned_distance(const Vec3& p) const { return std::sqrt(impl_->tree.squared_distance(point(p))); }

std::size_t MeshShape::nearest_face(const Vec3& p) const {
  Point closest;
  return impl_->face_of[impl_->triangle_nearest(point(p), closest)];
}

const TriangleMesh& MeshShape::mesh() const { return impl_->mesh; }

}  // namespace geometry
