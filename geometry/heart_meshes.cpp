// Idealised ventricles as triangle meshes and analytic shapes (see heart_meshes.hpp).
// LV: Land et al. 2015, Proc. R. Soc. A 471:20150641, doi:10.1098/rspa.2015.0641, problem 2.
//
// Surfaces of revolution (and axis-aligned ellipsoids) are tessellated as a chain of rings of
// vertices: each ring is a closed polygon at one meridian parameter u, consecutive rings are joined
// by a strip of triangles ("zipper" by polar angle, so that two rings need not have the same number
// of vertices), and a pole is a ring of one vertex. The rings are spaced by equal arc length along the
// meridian, h sqrt(3)/2 apart, and each ring has about perimeter / h vertices, offset by half a
// segment from its neighbour: the triangles are close to equilateral with edges about h, from the
// equator to the pole. Every ring edge is shared by the two strips on either side of it, so the chain
// is conforming and closed, whatever the vertex counts.
//
// Orientation: a strip from ring A to ring B emits (A_i, B_j, A_i+1) and (A_i, B_j, B_j+1), with both
// rings counter-clockwise about +z. Its normal points away from the axis when B lies below A (an
// outer surface walked from top to bottom), towards the axis when B lies above A, and along +z when
// both lie in one horizontal plane with B outside A. One chain from the endocardial apex up to the
// base, across the base annulus and down the epicardium to its apex is therefore outward everywhere
// (on the endocardium "outward" from the wall is into the cavity).
//
// The biventricular mesh is made from closed ellipsoid meshes E1..E4 and a box below the base by
// CGAL corefinement booleans in exact arithmetic (Epeck). A corefinement visitor carries the surface
// each face comes from (E1..E4 or the base plane) through the booleans, so the regions follow from
// the construction rather than from a guess by position (a guess by the nearest implicit function
// labels E1 faces as E4 near (20, 0, 0), where the default E4, centre x = -14 and r_x = 34, touches
// E1 from inside the LV wall, and as E3 where E3 crosses the LV cavity). The result is rounded to double and remeshed isotropically
// patch by patch, because corefinement leaves slivers (edges down to 1e-13 mm) wherever an
// intersection curve passes near a vertex and triangulates the base plane by the intersection curves
// alone; then it is checked (closed, manifold, outward, no self-intersection, no degenerate face).
// CGAL stays in this file.

#include "geometry/heart_meshes.hpp"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/manifoldness.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/shape_predicates.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <memory>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace geometry {

namespace {

constexpr double pi = std::numbers::pi;

// ---------------------------------------------------------------------------------------------
// Rings and strips

/// `count` consecutive vertices of the mesh, counter-clockwise about +z; vertex i sits at the polar
/// angle 2 pi (i + offset) / count (offset in segments, 0 or 0.5). A pole has count 1.
struct Ring {
  std::uint32_t first = 0;
  std::uint32_t count = 0;
  double offset = 0;
};

/// Joins ring a to ring b by triangles of `region` (orientation in the file comment).
void stitch(const Ring& a, const Ring& b, int region, TriangleMesh& mesh) {
  assert(a.count >= 1 && b.count >= 1 && (a.count > 1 || b.count > 1));
  const auto id = [](const Ring& r, std::uint32_t i) { return r.first + i % r.count; };
  const auto turns = [](const Ring& r, std::uint32_t i) { return (i + r.offset) / r.count; };
  // A pole does not advance: its "edge" would be a degenerate triangle.
  std::uint32_t i = a.count == 1 ? 1 : 0;
  std::uint32_t j = b.count == 1 ? 1 : 0;
  while (i < a.count || j < b.count) {
    const bool advance_a = j >= b.count || (i < a.count && turns(a, i + 1) <= turns(b, j + 1));
    if (advance_a) {
      mesh.faces.push_back({id(a, i), id(b, j), id(a, i + 1)});
      ++i;
    } else {
      mesh.faces.push_back({id(a, i), id(b, j), id(b, j + 1)});
      ++j;
    }
    mesh.face_region.push_back(region);
  }
}

/// Number of segments of a closed curve of length `perimeter` with segments about `edge_length`.
std::uint32_t segments_for(double perimeter, double edge_length) {
  return static_cast<std::uint32_t>(std::max(3.0, std::ceil(perimeter / edge_length)));
}

/// Perimeter of the ellipse with semi-axes a, b (Ramanujan's second approximation; relative error
/// at most 4.1e-4, for a flat ellipse; far below what a segment count needs).
double ellipse_perimeter(double a, double b) {
  const double h = ((a - b) * (a - b)) / ((a + b) * (a + b));
  return pi * (a + b) * (1 + 3 * h / (10 + std::sqrt(4 - 3 * h)));
}

/// Appends a ring of vertices centre + (rx s cos v, ry s sin v, z) with s the sine factor.
Ring add_ring(TriangleMesh& mesh, const Vec3& centre, double rx, double ry, double z, std::uint32_t count,
              double offset) {
  Ring ring{static_cast<std::uint32_t>(mesh.vertices.size()), count, offset};
  for (std::uint32_t i = 0; i < count; ++i) {
    const double v = 2 * pi * (i + offset) / count;
    mesh.vertices.emplace_back(centre.x() + rx * std::cos(v), centre.y() + ry * std::sin(v), z);
  }
  return ring;
}

Ring add_pole(TriangleMesh& mesh, const Vec3& position) {
  Ring ring{static_cast<std::uint32_t>(mesh.vertices.size()), 1, 0};
  mesh.vertices.push_back(position);
  return ring;
}

/// Meridian parameters u_0 = u_begin < ... < u_n = u_end of the ellipse (r_s sin u, r_l cos u) at
/// equal arc length, n = ceil(length / spacing). Arc length by the midpoint rule on a fine table,
/// inverted by linear interpolation (the spacing needs no more accuracy; the vertices themselves are
/// placed exactly on the surface).
std::vector<double> equal_arc_parameters(double r_s, double r_l, double u_begin, double u_end, double spacing) {
  constexpr int n_table = 4096;
  std::vector<double> length(n_table + 1, 0.0);
  const double du = (u_end - u_begin) / n_table;
  for (int k = 0; k < n_table; ++k) {
    const double u = u_begin + (k + 0.5) * du;
    length[k + 1] = length[k] + du * std::hypot(r_s * std::cos(u), r_l * std::sin(u));
  }
  const int n = std::max(2, static_cast<int>(std::ceil(length.back() / spacing)));
  std::vector<double> u(n + 1);
  u.front() = u_begin;
  u.back() = u_end;
  int k = 0;
  for (int i = 1; i < n; ++i) {
    const double target = length.back() * i / n;
    while (length[k + 1] < target) ++k;
    const double t = (target - length[k]) / (length[k + 1] - length[k]);
    u[i] = u_begin + (k + t) * du;
  }
  return u;
}

/// Spacing of the rings along the meridian for triangles of edge h: the height of an equilateral
/// triangle.
double ring_spacing(double edge_length) { return edge_length * std::sqrt(3.0) / 2; }

void require_positive(double value, const char* name) {
  if (!(value > 0) || !std::isfinite(value)) {
    std::ostringstream message;
    message << name << " = " << value << ": expected a positive length";
    throw std::invalid_argument(message.str());
  }
}

int add_region(TriangleMesh& mesh, const char* name) {
  mesh.region_names.emplace_back(name);
  return static_cast<int>(mesh.region_names.size()) - 1;
}

// ---------------------------------------------------------------------------------------------
// LV

void validate(const LvEllipsoid& lv) {
  require_positive(lv.endo_rs, "LvEllipsoid.endo_rs");
  require_positive(lv.endo_rl, "LvEllipsoid.endo_rl");
  require_positive(lv.epi_rs, "LvEllipsoid.epi_rs");
  require_positive(lv.epi_rl, "LvEllipsoid.epi_rl");
  if (!(lv.endo_rs < lv.epi_rs) || !(lv.endo_rl < lv.epi_rl)) {
    std::ostringstream message;
    message << "LvEllipsoid: endocardial radii (" << lv.endo_rs << ", " << lv.endo_rl
            << ") must be smaller than the epicardial ones (" << lv.epi_rs << ", " << lv.epi_rl << ")";
    throw std::invalid_argument(message.str());
  }
  if (!(std::abs(lv.base_z) < lv.endo_rl)) {
    std::ostringstream message;
    message << "LvEllipsoid.base_z = " << lv.base_z << ": the base plane must cut the endocardium, |base_z| < endo_rl = "
            << lv.endo_rl;
    throw std::invalid_argument(message.str());
  }
}

/// V(r_s, r_l) = pi r_s^2 [z - z^3 / (3 r_l^2)] from z = -r_l to z = base_z.
double truncated_ellipsoid_volume(double r_s, double r_l, double base_z) {
  const auto primitive = [&](double z) { return z - z * z * z / (3 * r_l * r_l); };
  return pi * r_s * r_s * (primitive(base_z) - primitive(-r_l));
}

// ---------------------------------------------------------------------------------------------
// Closed ellipsoid meshes and CGAL

using ExactKernel = CGAL::Exact_predicates_exact_constructions_kernel;
using ExactMesh = CGAL::Surface_mesh<ExactKernel::Point_3>;
using InexactKernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using InexactMesh = CGAL::Surface_mesh<InexactKernel::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;

/// Closed outward mesh of the axis-aligned ellipsoid: a chain of rings from the top pole to the
/// bottom pole.
TriangleMesh ellipsoid_mesh(const Vec3& centre, const Vec3& radii, double edge_length) {
  TriangleMesh mesh;
  const int region = add_region(mesh, "");
  const double r_s = 0.5 * (radii.x() + radii.y());  // meridian spacing from the mean equatorial radius
  const std::vector<double> u = equal_arc_parameters(r_s, radii.z(), 0, pi, ring_spacing(edge_length));
  Ring previous = add_pole(mesh, centre + Vec3(0, 0, radii.z()));
  for (std::size_t k = 1; k + 1 < u.size(); ++k) {
    const double s = std::sin(u[k]);
    const std::uint32_t n = segments_for(ellipse_perimeter(radii.x() * s, radii.y() * s), edge_length);
    const Ring ring = add_ring(mesh, centre, radii.x() * s, radii.y() * s, centre.z() + radii.z() * std::cos(u[k]), n,
                               0.5 * (k % 2));
    stitch(previous, ring, region, mesh);
    previous = ring;
  }
  stitch(previous, add_pole(mesh, centre - Vec3(0, 0, radii.z())), region, mesh);
  return mesh;
}

/// Closed outward mesh of the box [lower, upper], 12 triangles.
TriangleMesh box_mesh(const Vec3& lower, const Vec3& upper) {
  TriangleMesh mesh;
  for (int k = 0; k < 8; ++k) {
    mesh.vertices.emplace_back((k & 1) ? upper.x() : lower.x(), (k & 2) ? upper.y() : lower.y(),
                               (k & 4) ? upper.z() : lower.z());
  }
  // Each face as a quad (a, b, c, d) counter-clockwise seen from outside.
  const std::uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    mesh.faces.push_back({q[0], q[1], q[2]});
    mesh.faces.push_back({q[0], q[2], q[3]});
  }
  mesh.face_region.assign(mesh.faces.size(), add_region(mesh, ""));
  return mesh;
}

/// The analytic surface each face of the biventricular construction lies on, kept through the
/// booleans as the face property "f:source".
enum Source { source_e1, source_e2, source_e3, source_e4, source_base_plane };
constexpr const char* source_property = "f:source";

using SourceMap = ExactMesh::Property_map<ExactMesh::Face_index, int>;

SourceMap source_map(const ExactMesh& mesh) {
  const auto [map, found] = mesh.property_map<ExactMesh::Face_index, int>(source_property);
  assert(found);
  return map;
}

ExactMesh to_exact(const TriangleMesh& mesh, Source source) {
  ExactMesh out;
  std::vector<ExactMesh::Vertex_index> index;
  index.reserve(mesh.vertices.size());
  for (const Vec3& p : mesh.vertices) index.push_back(out.add_vertex(ExactKernel::Point_3(p.x(), p.y(), p.z())));
  for (const auto& f : mesh.faces) {
    [[maybe_unused]] const auto face = out.add_face(index[f[0]], index[f[1]], index[f[2]]);
    assert(face != ExactMesh::null_face());
  }
  out.add_property_map<ExactMesh::Face_index, int>(source_property, source);
  return out;
}

/// Corefinement visitor that hands the source of a face on to the faces it is split into and to
/// its copies in the result.
class SourceTracker : public PMP::Corefinement::Default_visitor<ExactMesh> {
 public:
  void before_subface_creations(ExactMesh::Face_index split, ExactMesh& mesh) { *current_ = source_map(mesh)[split]; }
  void after_subface_created(ExactMesh::Face_index created, ExactMesh& mesh) { source_map(mesh)[created] = *current_; }
  void after_face_copy(ExactMesh::Face_index from, const ExactMesh& from_mesh, ExactMesh::Face_index to,
                       ExactMesh& to_mesh) {
    source_map(to_mesh)[to] = source_map(from_mesh)[from];
  }

 private:
  std::shared_ptr<int> current_ = std::make_shared<int>(-1);  // shared: CGAL copies the visitor
};

/// Rounds the exact mesh to double (vertices renumbered, faces in the mesh's order); `source`
/// receives the source of each face.
TriangleMesh to_double(const ExactMesh& mesh, std::vector<int>& source) {
  TriangleMesh out;
  const SourceMap source_of = source_map(mesh);
  std::vector<std::uint32_t> index(mesh.number_of_vertices() + mesh.number_of_removed_vertices(), 0);
  for (const auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    index[v.idx()] = static_cast<std::uint32_t>(out.vertices.size());
    out.vertices.emplace_back(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
  }
  source.clear();
  for (const auto f : mesh.faces()) {
    std::array<std::uint32_t, 3> face{};
    int k = 0;
    for (const auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      if (k == 3) throw std::logic_error("biventricular_mesh: CGAL returned a face that is not a triangle");
      face[k++] = index[v.idx()];
    }
    if (k != 3) throw std::logic_error("biventricular_mesh: CGAL returned a face that is not a triangle");
    if (source_of[f] < 0) throw std::logic_error("biventricular_mesh: a face of the result has lost its source");
    out.faces.push_back(face);
    source.push_back(source_of[f]);
  }
  return out;
}

InexactMesh to_inexact(const TriangleMesh& mesh) {
  InexactMesh out;
  std::vector<InexactMesh::Vertex_index> index;
  index.reserve(mesh.vertices.size());
  for (const Vec3& p : mesh.vertices) index.push_back(out.add_vertex(InexactKernel::Point_3(p.x(), p.y(), p.z())));
  for (const auto& f : mesh.faces) {
    if (out.add_face(index[f[0]], index[f[1]], index[f[2]]) == InexactMesh::null_face()) {
      throw MeshError("biventricular_mesh: the rounded result is not an oriented 2-manifold");
    }
  }
  return out;
}

/// One corefinement boolean, keeping the source of every face; CGAL returns false when the result
/// would not be manifold.
enum class Boolean { union_, difference, intersection };

ExactMesh boolean(ExactMesh a, ExactMesh b, Boolean operation, const char* what) {
  ExactMesh result;
  result.add_property_map<ExactMesh::Face_index, int>(source_property, -1);
  const auto tracking = CGAL::parameters::visitor(SourceTracker());
  bool ok = false;
  switch (operation) {
    case Boolean::union_: ok = PMP::corefine_and_compute_union(a, b, result, tracking); break;
    case Boolean::difference: ok = PMP::corefine_and_compute_difference(a, b, result, tracking); break;
    case Boolean::intersection: ok = PMP::corefine_and_compute_intersection(a, b, result, tracking); break;
  }
  if (!ok) {
    throw MeshError(std::string("biventricular_mesh: the boolean ") + what +
                    " is not a manifold (tangent surfaces? change the Biventricular dimensions slightly)");
  }
  return result;
}

/// Throws MeshError naming every problem of the rounded mesh.
void require_clean(const TriangleMesh& mesh) {
  const InexactMesh sm = to_inexact(mesh);
  std::ostringstream problems;
  if (!CGAL::is_closed(sm)) problems << " open;";
  // (non_manifold_vertices is linear; is_non_manifold_vertex scans the whole mesh per vertex)
  std::vector<InexactMesh::Halfedge_index> umbrellas;
  PMP::non_manifold_vertices(sm, std::back_inserter(umbrellas));
  std::vector<std::size_t> pinched;
  for (const auto h : umbrellas) pinched.push_back(sm.target(h).idx());
  std::sort(pinched.begin(), pinched.end());
  const auto non_manifold = static_cast<std::size_t>(std::unique(pinched.begin(), pinched.end()) - pinched.begin());
  if (non_manifold > 0) problems << ' ' << non_manifold << " non-manifold vertices;";
  std::size_t degenerate = 0;
  for (const auto f : sm.faces()) degenerate += PMP::is_degenerate_triangle_face(f, sm) ? 1 : 0;
  if (degenerate > 0) problems << ' ' << degenerate << " degenerate faces;";
  if (problems.str().empty()) {
    if (!PMP::is_outward_oriented(sm)) problems << " inward oriented;";
    if (PMP::does_self_intersect(sm)) problems << " self-intersecting;";
  }
  if (!problems.str().empty()) {
    throw MeshError("biventricular_mesh: the result is" + problems.str() +
                    " change the Biventricular dimensions or the edge length slightly");
  }
}

// ---------------------------------------------------------------------------------------------
// Biventricular

/// The analytic surfaces the faces of the biventricular mesh come from (E2 in two parts).
enum class Surface { e1, e2_epi, e2_septum, e3, e4, base_plane };
constexpr int n_surfaces = 6;

/// Isotropic remeshing (Botsch & Kobbelt 2004, CGAL) of each analytic surface patch separately,
/// with target edge `edge_length`. The corefinement leaves slivers where an intersection curve
/// passes close to a vertex (edges down to 1e-13 mm, which collapse when written as float STL) and
/// triangulates the base plane by the intersection curves alone (triangles across the whole wall).
/// Edges between patches are constrained (split or collapsed along the curve, never flipped), the
/// vertices where three patches meet are fixed, and moved vertices are projected back onto the
/// boolean's own surface patch. `surface` (one entry per face) is updated to the new faces.
TriangleMesh remesh_surfaces(const TriangleMesh& mesh, std::vector<int>& surface, double edge_length) {
  InexactMesh sm = to_inexact(mesh);
  auto patch = sm.add_property_map<InexactMesh::Face_index, int>("f:surface", -1).first;
  for (const auto f : sm.faces()) patch[f] = surface[f.idx()];
  auto edge_constrained = sm.add_property_map<InexactMesh::Edge_index, bool>("e:constrained", false).first;
  auto vertex_constrained = sm.add_property_map<InexactMesh::Vertex_index, bool>("v:constrained", false).first;
  for (const auto e : sm.edges()) {
    const auto h = sm.halfedge(e);
    edge_constrained[e] = patch[sm.face(h)] != patch[sm.face(sm.opposite(h))];
  }
  for (const auto v : sm.vertices()) {
    int n_constrained = 0;
    for (const auto h : CGAL::halfedges_around_target(sm.halfedge(v), sm)) n_constrained += edge_constrained[sm.edge(h)];
    vertex_constrained[v] = n_constrained != 0 && n_constrained != 2;
  }
  PMP::isotropic_remeshing(sm.faces(), edge_length, sm,
                           CGAL::parameters::number_of_iterations(3)
                               .edge_is_constrained_map(edge_constrained)
                               .vertex_is_constrained_map(vertex_constrained)
                               .face_patch_map(patch)
                               .relax_constraints(true));
  sm.collect_garbage();

  TriangleMesh out;
  std::vector<std::uint32_t> index(sm.number_of_vertices(), 0);
  for (const auto v : sm.vertices()) {
    index[v.idx()] = static_cast<std::uint32_t>(out.vertices.size());
    const auto& p = sm.point(v);
    out.vertices.emplace_back(p.x(), p.y(), p.z());
  }
  surface.clear();
  for (const auto f : sm.faces()) {
    std::array<std::uint32_t, 3> face{};
    int k = 0;
    for (const auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) face[k++] = index[v.idx()];
    out.faces.push_back(face);
    surface.push_back(patch[f]);
  }
  return out;
}

void validate(const Biventricular& biv) {
  const auto positive = [](const Vec3& radii, const char* name) {
    for (int k = 0; k < 3; ++k) require_positive(radii[k], name);
  };
  positive(biv.lv_endo_radii, "Biventricular.lv_endo_radii");
  positive(biv.lv_epi_radii, "Biventricular.lv_epi_radii");
  positive(biv.rv_endo_radii, "Biventricular.rv_endo_radii");
  positive(biv.rv_epi_radii, "Biventricular.rv_epi_radii");
  const auto inside = [](const Vec3& inner, const Vec3& outer, const char* inner_name, const char* outer_name) {
    if (!(inner.array() < outer.array()).all()) {
      std::ostringstream message;
      message << "Biventricular." << inner_name << " = (" << inner.transpose() << ") must be smaller than "
              << outer_name << " = (" << outer.transpose() << ") in every direction";
      throw std::invalid_argument(message.str());
    }
  };
  inside(biv.lv_endo_radii, biv.lv_epi_radii, "lv_endo_radii", "lv_epi_radii");
  inside(biv.rv_endo_radii, biv.rv_epi_radii, "rv_endo_radii", "rv_epi_radii");
  const double lv_top = biv.lv_centre.z() + biv.lv_endo_radii.z();
  const double lv_bottom = biv.lv_centre.z() - biv.lv_endo_radii.z();
  if (!(biv.base_z > lv_bottom && biv.base_z < lv_top)) {
    std::ostringstream message;
    message << "Biventricular.base_z = " << biv.base_z << ": the base plane must cut the LV cavity, between "
            << lv_bottom << " and " << lv_top;
    throw std::invalid_argument(message.str());
  }
}

/// F(c) = (|(c - centre) / radii| - 1) min(radii): the implicit function of the ellipsoid scaled to
/// a length (the signed distance along the shortest axis), negative inside.
double ellipsoid_function(const Vec3& c, const Vec3& centre, const Vec3& radii) {
  return ((c - centre).cwiseQuotient(radii).norm() - 1) * radii.minCoeff();
}

}  // namespace

// -------------------------------------------------------------------------------------------------

TriangleMesh lv_ellipsoid_mesh(const LvEllipsoid& lv, double edge_length) {
  validate(lv);
  require_positive(edge_length, "edge_length");
  TriangleMesh mesh;
  const int epi = add_region(mesh, region_epi);
  const int lv_endo = add_region(mesh, region_lv_endo);
  const int base = add_region(mesh, region_base);

  const double spacing = ring_spacing(edge_length);
  // Meridian parameter of the base ring: z = r_l cos u = base_z.
  const double endo_u_base = std::acos(lv.base_z / lv.endo_rl);
  const double epi_u_base = std::acos(lv.base_z / lv.epi_rl);
  const std::vector<double> endo_u = equal_arc_parameters(lv.endo_rs, lv.endo_rl, endo_u_base, pi, spacing);
  const std::vector<double> epi_u = equal_arc_parameters(lv.epi_rs, lv.epi_rl, epi_u_base, pi, spacing);
  // Ring radius at u, with the base rings' sine from base_z so that their z is base_z exactly.
  const auto sine = [&](const std::vector<double>& u, std::size_t k, double r_l) {
    return k == 0 ? std::sqrt(1 - (lv.base_z / r_l) * (lv.base_z / r_l)) : std::sin(u[k]);
  };
  const auto height = [&](const std::vector<double>& u, std::size_t k, double r_l) {
    return k == 0 ? lv.base_z : r_l * std::cos(u[k]);
  };
  int parity = 0;  // alternates the half-segment offset of consecutive rings
  const auto surface_ring = [&](double r_s, double r_l, const std::vector<double>& u, std::size_t k) {
    const double r = r_s * sine(u, k, r_l);
    return add_ring(mesh, Vec3::Zero(), r, r, height(u, k, r_l), segments_for(2 * pi * r, edge_length),
                    0.5 * (parity++ % 2));
  };

  // Endocardium from its apex up to the base ring (normals into the cavity).
  Ring previous = add_pole(mesh, Vec3(0, 0, -lv.endo_rl));
  for (std::size_t k = endo_u.size() - 2;; --k) {
    const Ring ring = surface_ring(lv.endo_rs, lv.endo_rl, endo_u, k);
    stitch(previous, ring, lv_endo, mesh);
    previous = ring;
    if (k == 0) break;
  }
  // Base annulus from the endocardial to the epicardial ring, in the plane z = base_z (normals +z).
  const double endo_base_radius = lv.endo_rs * sine(endo_u, 0, lv.endo_rl);
  const double epi_base_radius = lv.epi_rs * sine(epi_u, 0, lv.epi_rl);
  const int n_annulus = std::max(1, static_cast<int>(std::ceil((epi_base_radius - endo_base_radius) / spacing)));
  for (int k = 1; k < n_annulus; ++k) {
    const double r = endo_base_radius + (epi_base_radius - endo_base_radius) * k / n_annulus;
    const Ring ring = add_ring(mesh, Vec3::Zero(), r, r, lv.base_z, segments_for(2 * pi * r, edge_length),
                               0.5 * (parity++ % 2));
    stitch(previous, ring, base, mesh);
    previous = ring;
  }
  // Epicardium from the base ring down to its apex (normals away from the wall).
  for (std::size_t k = 0; k + 1 < epi_u.size(); ++k) {
    const Ring ring = surface_ring(lv.epi_rs, lv.epi_rl, epi_u, k);
    stitch(previous, ring, k == 0 ? base : epi, mesh);
    previous = ring;
  }
  stitch(previous, add_pole(mesh, Vec3(0, 0, -lv.epi_rl)), epi, mesh);
  return mesh;
}

TriangleMesh biventricular_mesh(const Biventricular& biv, double edge_length) {
  validate(biv);
  require_positive(edge_length, "edge_length");
  const ExactMesh e1 = to_exact(ellipsoid_mesh(biv.lv_centre, biv.lv_endo_radii, edge_length), source_e1);
  const ExactMesh e2 = to_exact(ellipsoid_mesh(biv.lv_centre, biv.lv_epi_radii, edge_length), source_e2);
  const ExactMesh e3 = to_exact(ellipsoid_mesh(biv.rv_centre, biv.rv_endo_radii, edge_length), source_e3);
  const ExactMesh e4 = to_exact(ellipsoid_mesh(biv.rv_centre, biv.rv_epi_radii, edge_length), source_e4);
  // The half-space z <= base_z as a box around everything.
  const Vec3 lower = (biv.lv_centre - biv.lv_epi_radii).cwiseMin(biv.rv_centre - biv.rv_epi_radii) - Vec3::Constant(10);
  const Vec3 upper = (biv.lv_centre + biv.lv_epi_radii).cwiseMax(biv.rv_centre + biv.rv_epi_radii) + Vec3::Constant(10);
  const ExactMesh below_base = to_exact(box_mesh(lower, Vec3(upper.x(), upper.y(), biv.base_z)), source_base_plane);

  // Myocardium = ((E2 u E4) \ E1) \ (E3 \ E2), cut by the base plane.
  const ExactMesh walls = boolean(e2, e4, Boolean::union_, "E2 u E4");
  const ExactMesh lv_opened = boolean(walls, e1, Boolean::difference, "(E2 u E4) \\ E1");
  const ExactMesh rv_cavity = boolean(e3, e2, Boolean::difference, "E3 \\ E2");
  const ExactMesh closed_heart = boolean(lv_opened, rv_cavity, Boolean::difference, "((E2 u E4) \\ E1) \\ (E3 \\ E2)");
  const ExactMesh myocardium = boolean(closed_heart, below_base, Boolean::intersection, "myocardium n {z <= base_z}");

  // The surface of each face: its source, with E2 split into the septal wall of the RV cavity (the
  // faces inside E3) and the epicardium.
  std::vector<int> source;
  TriangleMesh mesh = to_double(myocardium, source);
  std::vector<int> surface(mesh.faces.size());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const Vec3 c = (mesh.vertices[mesh.faces[f][0]] + mesh.vertices[mesh.faces[f][1]] + mesh.vertices[mesh.faces[f][2]]) / 3;
    const bool in_e3 = ellipsoid_function(c, biv.rv_centre, biv.rv_endo_radii) < 0;
    const Surface of_source[5] = {Surface::e1, in_e3 ? Surface::e2_septum : Surface::e2_epi, Surface::e3, Surface::e4,
                                  Surface::base_plane};
    surface[f] = static_cast<int>(of_source[source[f]]);
  }

  mesh = remesh_surfaces(mesh, surface, edge_length);
  require_clean(mesh);

  const int epi = add_region(mesh, region_epi);
  const int lv_endo = add_region(mesh, region_lv_endo);
  const int rv_endo = add_region(mesh, region_rv_endo);
  const int base = add_region(mesh, region_base);
  const int region_of[n_surfaces] = {lv_endo, epi, rv_endo, rv_endo, epi, base};  // in the order of Surface
  mesh.face_region.resize(mesh.faces.size());
  std::vector<std::size_t> region_faces(mesh.region_names.size(), 0);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    mesh.face_region[f] = region_of[surface[f]];
    ++region_faces[mesh.face_region[f]];
  }
  for (std::size_t r = 0; r < region_faces.size(); ++r) {
    if (region_faces[r] == 0) {
      throw MeshError("biventricular_mesh: region \"" + mesh.region_names[r] +
                      "\" is empty; check the Biventricular dimensions");
    }
  }
  return mesh;
}

ShapePtr lv_ellipsoid_shape(const LvEllipsoid& lv) {
  validate(lv);
  // The wall: (epicardial ellipsoid n {z <= base_z}) \ endocardial ellipsoid. The endocardial
  // ellipsoid reaches above the base plane, so the cavity is open at the base.
  const ShapePtr epi = make_ellipsoid(Vec3::Zero(), Vec3(lv.epi_rs, lv.epi_rs, lv.epi_rl));
  const ShapePtr endo = make_ellipsoid(Vec3::Zero(), Vec3(lv.endo_rs, lv.endo_rs, lv.endo_rl));
  const ShapePtr below_base = make_half_space(Vec3(0, 0, lv.base_z), Vec3(0, 0, 1));
  return make_difference(make_intersection(epi, below_base), endo);
}

ShapePtr biventricular_shape(const Biventricular& biv) {
  validate(biv);
  const ShapePtr e1 = make_ellipsoid(biv.lv_centre, biv.lv_endo_radii);
  const ShapePtr e2 = make_ellipsoid(biv.lv_centre, biv.lv_epi_radii);
  const ShapePtr e3 = make_ellipsoid(biv.rv_centre, biv.rv_endo_radii);
  const ShapePtr e4 = make_ellipsoid(biv.rv_centre, biv.rv_epi_radii);
  const ShapePtr below_base = make_half_space(Vec3(0, 0, biv.base_z), Vec3(0, 0, 1));
  // Myocardium = ((E2 u E4) \ E1) \ (E3 \ E2), cut by the base plane.
  const ShapePtr myocardium = make_difference(make_difference(make_union(e2, e4), e1), make_difference(e3, e2));
  return make_intersection(myocardium, below_base);
}

double lv_ellipsoid_volume(const LvEllipsoid& lv) {
  validate(lv);
  return truncated_ellipsoid_volume(lv.epi_rs, lv.epi_rl, lv.base_z) -
         truncated_ellipsoid_volume(lv.endo_rs, lv.endo_rl, lv.base_z);
}

std::vector<std::filesystem::path> write_heart_mesh_files(const TriangleMesh& mesh, const std::filesystem::path& folder,
                                                          const std::string& stem) {
  std::filesystem::create_directories(folder);
  std::vector<std::filesystem::path> written;
  for (const char* extension : {".stl", ".obj"}) {
    written.push_back(folder / (stem + extension));
    write_mesh(mesh, written.back());
  }
  for (std::size_t r = 0; r < mesh.region_names.size(); ++r) {
    const TriangleMesh surface = extract_region(mesh, static_cast<int>(r));
    if (surface.faces.empty()) continue;
    written.push_back(folder / (stem + "_" + mesh.region_names[r] + ".stl"));
    write_mesh(surface, written.back());
  }
  return written;
}

}  // namespace geometry
