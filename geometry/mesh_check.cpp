// Mesh checks and repair.
//
// check_mesh works on any triangle soup: edges are counted in a hash map (plain C++), the volume is
// the divergence-theorem sum, and self-intersections are found by a bounding-box sweep
// (CGAL::box_self_intersection_d) followed by exact predicates (Epick) on each candidate pair, with
// the same rules as CGAL's PMP::self_intersections (CGAL 5.5 has no soup version and needs a valid
// Surface_mesh, which an open or non-manifold input is not):
//   - faces sharing an edge intersect only if the four points are coplanar and the two triangles
//     lie on the same side of the edge (they overlap);
//   - faces sharing one vertex intersect if the edge opposite that vertex in one triangle meets
//     the other triangle;
//   - faces sharing nothing intersect if the triangles do;
//   - faces on the same three vertices (a duplicated face) intersect.
// Source: CGAL 5.5, Polygon_mesh_processing/self_intersections.h, internal::do_faces_intersect.
//
// repair_mesh uses CGAL: orient_polygon_soup, polygon_soup_to_polygon_mesh, triangulate_hole,
// orient_to_bound_a_volume.

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <sstream>
#include <unordered_map>

#include <Eigen/Geometry>  // cross
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Intersections_3/Segment_3_Triangle_3.h>
#include <CGAL/Intersections_3/Triangle_3_Triangle_3.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/box_intersection_d.h>

#include "geometry/mesh.hpp"
#include "libsph/core/union_find.hpp"

namespace geometry {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Face = std::array<std::uint32_t, 3>;

Point point(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

bool has_repeated_vertex(const Face& f) { return f[0] == f[1] || f[1] == f[2] || f[2] == f[0]; }

bool is_degenerate(const TriangleMesh& mesh, const Face& f) {
  return has_repeated_vertex(f) ||
         CGAL::collinear(point(mesh.vertices[f[0]]), point(mesh.vertices[f[1]]), point(mesh.vertices[f[2]]));
}

// Signed volume enclosed by the faces, sum of det(v0 - o, v1 - o, v2 - o) / 6 (divergence theorem).
// o, the centre of the bounding box, does not change the result for a closed surface but keeps the
// determinants small, so the sum loses fewer digits far from the origin.
double signed_volume(const TriangleMesh& mesh) {
  const Aabb box = mesh.bounding_box();
  const Vec3 o = 0.5 * (box.lower + box.upper);
  double six_volume = 0;
  for (const Face& f : mesh.faces)
    six_volume += (mesh.vertices[f[0]] - o).dot((mesh.vertices[f[1]] - o).cross(mesh.vertices[f[2]] - o));
  return six_volume / 6;
}

// Uses of one undirected edge {lower, upper} of the soup.
struct EdgeUse {
  std::uint32_t from_lower = 0;  // faces traversing it lower -> upper
  std::uint32_t from_upper = 0;  // faces traversing it upper -> lower
  std::size_t first_face = 0;
  std::uint32_t faces() const { return from_lower + from_upper; }
};

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
  return (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
}

// True when faces f and g intersect other than along a shared edge or at a shared vertex (see the
// rules at the top of the file).
bool faces_intersect(const TriangleMesh& mesh, const Face& f, const Face& g) {
  int n_shared = 0;
  int f_shared[3], g_shared[3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (f[i] == g[j]) {
        f_shared[n_shared] = i;
        g_shared[n_shared] = j;
        ++n_shared;
      }
  auto p = [&](std::uint32_t v) { return point(mesh.vertices[v]); };
  if (n_shared == 3) return true;
  if (n_shared == 2) {
    const Point u = p(f[f_shared[0]]), v = p(f[f_shared[1]]);
    const Point f_apex = p(f[3 - f_shared[0] - f_shared[1]]);
    const Point g_apex = p(g[3 - g_shared[0] - g_shared[1]]);
    return CGAL::coplanar(u, v, f_apex, g_apex) && CGAL::coplanar_orientation(u, v, f_apex, g_apex) == CGAL::POSITIVE;
  }
  const Kernel::Triangle_3 tf(p(f[0]), p(f[1]), p(f[2])), tg(p(g[0]), p(g[1]), p(g[2]));
  if (n_shared == 1) {
    const int i = f_shared[0], j = g_shared[0];
    const Kernel::Segment_3 f_opposite(p(f[(i + 1) % 3]), p(f[(i + 2) % 3]));
    const Kernel::Segment_3 g_opposite(p(g[(j + 1) % 3]), p(g[(j + 2) % 3]));
    return CGAL::do_intersect(tf, g_opposite) || CGAL::do_intersect(tg, f_opposite);
  }
  return CGAL::do_intersect(tf, tg);
}

// Number of faces that take part in at least one intersecting pair. Degenerate faces are skipped
// (they are counted as degenerate).
std::size_t count_self_intersecting_faces(const TriangleMesh& mesh, const std::vector<char>& degenerate) {
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t,
                                                        CGAL::Box_intersection_d::ID_FROM_BOX_ADDRESS>;
  std::vector<Box> boxes;
  boxes.reserve(mesh.faces.size());
  for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
    if (degenerate[i]) continue;
    const Face& f = mesh.faces[i];
    boxes.emplace_back(point(mesh.vertices[f[0]]).bbox() + point(mesh.vertices[f[1]]).bbox() +
                           point(mesh.vertices[f[2]]).bbox(),
                       i);
  }
  std::vector<const Box*> box_pointers;
  box_pointers.reserve(boxes.size());
  for (const Box& b : boxes) box_pointers.push_back(&b);

  std::vector<char> intersecting(mesh.faces.size(), 0);
  CGAL::box_self_intersection_d<CGAL::Sequential_tag>(
      box_pointers.begin(), box_pointers.end(), [&](const Box* a, const Box* b) {
        if (faces_intersect(mesh, mesh.faces[a->info()], mesh.faces[b->info()]))
          intersecting[a->info()] = intersecting[b->info()] = 1;
      });
  return static_cast<std::size_t>(std::count(intersecting.begin(), intersecting.end(), 1));
}

std::vector<std::string> problem_list(const MeshCheckReport& r) {
  std::vector<std::string> problems;
  if (r.faces == 0) problems.emplace_back("empty: no faces");
  if (r.degenerate_faces > 0)
    problems.push_back("degenerate: " + std::to_string(r.degenerate_faces) +
                       " faces with zero area or a repeated vertex");
  if (r.border_edges > 0) problems.push_back("open: " + std::to_string(r.border_edges) + " border edges (holes)");
  if (r.non_manifold_edges > 0)
    problems.push_back("non-manifold: " + std::to_string(r.non_manifold_edges) + " edges shared by three faces or more");
  if (r.inconsistent_edges > 0)
    problems.push_back("inconsistently oriented: " + std::to_string(r.inconsistent_edges) +
                       " edges traversed in the same direction by both of their faces");
  if (r.self_intersecting_faces > 0)
    problems.push_back("self-intersecting: " + std::to_string(r.self_intersecting_faces) + " faces");
  if (r.faces > 0 && !(r.volume > 0)) {
    std::ostringstream text;
    text << r.volume;
    if (r.volume < 0)
      problems.push_back("inverted: enclosed volume is negative (" + text.str() + "): normals point inwards");
    else
      problems.push_back("flat: enclosed volume is " + text.str());
  }
  return problems;
}

}  // namespace

bool MeshCheckReport::ok() const { return problem_list(*this).empty(); }

std::string MeshCheckReport::problems() const {
  std::string text;
  for (const std::string& problem : problem_list(*this)) text += (text.empty() ? "" : "\n") + problem;
  return text;
}

MeshCheckReport check_mesh(const TriangleMesh& mesh) {
  require_well_formed(mesh, "");
  MeshCheckReport report;
  report.vertices = mesh.vertices.size();
  report.faces = mesh.faces.size();

  std::vector<char> degenerate(mesh.faces.size(), 0);
  std::unordered_map<std::uint64_t, EdgeUse> edges;
  edges.reserve(2 * mesh.faces.size());
  sph::UnionFind components(mesh.faces.size());
  for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
    const Face& f = mesh.faces[i];
    degenerate[i] = is_degenerate(mesh, f);
    if (has_repeated_vertex(f)) continue;  // no proper edges; counted as degenerate
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t a = f[c], b = f[(c + 1) % 3];
      const auto [it, inserted] = edges.try_emplace(edge_key(a, b));
      EdgeUse& use = it->second;
      if (inserted)
        use.first_face = i;
      else
        components.unite(i, use.first_face);
      (a < b ? use.from_lower : use.from_upper) += 1;
    }
  }
  report.degenerate_faces = static_cast<std::size_t>(std::count(degenerate.begin(), degenerate.end(), 1));
  for (const auto& [key, use] : edges) {
    if (use.faces() == 1) ++report.border_edges;
    if (use.faces() >= 3) ++report.non_manifold_edges;
    if (use.faces() == 2 && use.from_lower != 1) ++report.inconsistent_edges;
  }
  report.components = components.n_sets();
  report.self_intersecting_faces = count_self_intersecting_faces(mesh, degenerate);
  report.volume = signed_volume(mesh);
  return report;
}

MeshCheckReport require_valid_mesh(const TriangleMesh& mesh, const std::string& name) {
  MeshCheckReport report = check_mesh(mesh);
  const auto problems = problem_list(report);
  if (!problems.empty()) {
    std::string text = "mesh '" + name + "': ";
    for (std::size_t i = 0; i < problems.size(); ++i) text += (i > 0 ? "; " : "") + problems[i];
    throw MeshError(text);
  }
  return report;
}

TriangleMesh repair_mesh(const TriangleMesh& mesh) {
  namespace PMP = CGAL::Polygon_mesh_processing;
  using SurfaceMesh = CGAL::Surface_mesh<Point>;
  require_well_formed(mesh, "");

  // 1. Soup without degenerate faces, with vertices welded by exact position.
  std::vector<Point> points;
  std::vector<std::uint32_t> welded(mesh.vertices.size());
  {
    std::map<std::array<double, 3>, std::uint32_t> index;
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
      const Vec3& x = mesh.vertices[v];
      const auto [it, inserted] =
          index.try_emplace({x.x() + 0.0, x.y() + 0.0, x.z() + 0.0}, static_cast<std::uint32_t>(points.size()));
      if (inserted) points.push_back(point(x));
      welded[v] = it->second;
    }
  }
  const bool has_regions = mesh.face_region.size() == mesh.faces.size();
  std::vector<std::vector<std::size_t>> polygons;
  std::vector<int> polygon_region;
  for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
    const Face f{welded[mesh.faces[i][0]], welded[mesh.faces[i][1]], welded[mesh.faces[i][2]]};
    if (has_repeated_vertex(f) || CGAL::collinear(points[f[0]], points[f[1]], points[f[2]])) continue;
    polygons.push_back({f[0], f[1], f[2]});
    polygon_region.push_back(has_regions ? mesh.face_region[i] : 0);
  }
  std::vector<std::string> region_names = has_regions ? mesh.region_names : std::vector<std::string>{""};
  if (polygons.empty()) return TriangleMesh{{}, {}, {}, region_names};
  {  // drop the points no face uses (orient_to_bound_a_volume crashes on isolated vertices)
    constexpr auto unused = std::numeric_limits<std::size_t>::max();
    std::vector<std::size_t> new_index(points.size(), unused);
    std::vector<Point> used_points;
    for (auto& polygon : polygons)
      for (std::size_t& v : polygon) {
        if (new_index[v] == unused) {
          new_index[v] = used_points.size();
          used_points.push_back(points[v]);
        }
        v = new_index[v];
      }
    points = std::move(used_points);
  }

  // 2. Consistent orientation; vertices where the surface is pinched get duplicated so that the
  //    soup becomes a valid polygon mesh. The order of the polygons is kept.
  PMP::orient_polygon_soup(points, polygons);
  SurfaceMesh surface;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, surface);
  auto region = surface.add_property_map<SurfaceMesh::Face_index, int>("f:region", 0).first;
  for (std::size_t i = 0; i < polygons.size(); ++i)
    region[SurfaceMesh::Face_index(static_cast<SurfaceMesh::size_type>(i))] = polygon_region[i];

  // 3. Fill each hole; the new faces take the region of the face next to the hole.
  std::vector<SurfaceMesh::Halfedge_index> hole_starts;
  {
    std::vector<char> seen(surface.number_of_halfedges(), 0);
    for (auto h : surface.halfedges()) {
      if (!surface.is_border(h) || seen[h.idx()]) continue;
      hole_starts.push_back(h);
      for (auto g : CGAL::halfedges_around_face(h, surface)) seen[g.idx()] = 1;
    }
  }
  for (auto h : hole_starts) {
    const int neighbour_region = region[surface.face(surface.opposite(h))];
    std::vector<SurfaceMesh::Face_index> patch;
    PMP::triangulate_hole(surface, h, std::back_inserter(patch));
    for (auto f : patch) region[f] = neighbour_region;
  }

  // 4. Outward: orient_to_bound_a_volume needs a closed surface; if a hole could not be filled, at
  //    least make the signed volume positive.
  if (CGAL::is_closed(surface)) {
    PMP::orient_to_bound_a_volume(surface);
  } else {
    double six_volume = 0;
    for (auto f : surface.faces()) {
      std::array<Vec3, 3> x;
      int c = 0;
      for (auto v : CGAL::vertices_around_face(surface.halfedge(f), surface)) {
        const Point& q = surface.point(v);
        x[c++] = Vec3(q.x(), q.y(), q.z());
      }
      six_volume += x[0].dot(x[1].cross(x[2]));
    }
    if (six_volume < 0) PMP::reverse_face_orientations(surface);
  }

  // 5. Back to a TriangleMesh: faces in surface order (the kept faces first, in their input order,
  //    then the hole patches); vertices in first-use order.
  TriangleMesh repaired;
  repaired.region_names = region_names;
  std::vector<std::uint32_t> vertex_index(surface.number_of_vertices() + surface.number_of_removed_vertices(),
                                          std::numeric_limits<std::uint32_t>::max());
  for (auto f : surface.faces()) {
    Face face{};
    int c = 0;
    for (auto v : CGAL::vertices_around_face(surface.halfedge(f), surface)) {
      std::uint32_t& index = vertex_index[v.idx()];
      if (index == std::numeric_limits<std::uint32_t>::max()) {
        index = static_cast<std::uint32_t>(repaired.vertices.size());
        const Point& q = surface.point(v);
        repaired.vertices.emplace_back(q.x(), q.y(), q.z());
      }
      face[c++] = index;
    }
    repaired.faces.push_back(face);
    repaired.face_region.push_back(region[f]);
  }
  return repaired;
}

}  // namespace geometry
