#include "cardio/surface_labels.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <numeric>
#include <unordered_map>

#include "libsph/core/parallel.hpp"

namespace cardio {
namespace {

using geometry::MeshError;
using geometry::TriangleMesh;
using geometry::Vec3;

Vec3 face_vertex(const TriangleMesh& mesh, std::size_t f, int k) { return mesh.vertices[mesh.faces[f][k]]; }
Vec3 face_area_vector(const TriangleMesh& mesh, std::size_t f) {
  return 0.5 * (face_vertex(mesh, f, 1) - face_vertex(mesh, f, 0)).cross(face_vertex(mesh, f, 2) - face_vertex(mesh, f, 0));
}
Vec3 face_centroid(const TriangleMesh& mesh, std::size_t f) {
  return (face_vertex(mesh, f, 0) + face_vertex(mesh, f, 1) + face_vertex(mesh, f, 2)) / 3.0;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}


// Edge-connected components of the faces with keep[f] (the mesh is welded, so shared edges are
// shared vertex pairs).
std::vector<int> face_components(const TriangleMesh& mesh, const std::vector<bool>& keep, int& count) {
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> edge_faces;
  auto key = [](std::uint32_t a, std::uint32_t b) {
    return (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
  };
  for (std::uint32_t f = 0; f < mesh.n_faces(); ++f)
    if (keep[f])
      for (int k = 0; k < 3; ++k) edge_faces[key(mesh.faces[f][k], mesh.faces[f][(k + 1) % 3])].push_back(f);
  std::vector<int> component(mesh.n_faces(), -1);
  count = 0;
  std::vector<std::uint32_t> stack;
  for (std::uint32_t seed = 0; seed < mesh.n_faces(); ++seed) {
    if (!keep[seed] || component[seed] >= 0) continue;
    component[seed] = count;
    stack.assign(1, seed);
    while (!stack.empty()) {
      const std::uint32_t f = stack.back();
      stack.pop_back();
      for (int k = 0; k < 3; ++k)
        for (std::uint32_t g : edge_faces[key(mesh.faces[f][k], mesh.faces[f][(k + 1) % 3])])
          if (component[g] < 0) {
            component[g] = count;
            stack.push_back(g);
          }
    }
    ++count;
  }
  return component;
}

// Volume enclosed by the faces of component c closed by a fan from the centroid of its border
// vertices (or of its vertices when it is closed), and its area.
std::pair<double, double> cavity_volume_and_area(const TriangleMesh& mesh, const std::vector<int>& component, int c) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  Vec3 all_sum = Vec3::Zero();
  std::size_t all_count = 0;
  for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
    if (component[f] != c) continue;
    for (int k = 0; k < 3; ++k) {
      const auto a = mesh.faces[f][k], b = mesh.faces[f][(k + 1) % 3];
      directed[{a, b}] += 1;
      all_sum += mesh.vertices[a];
      ++all_count;
    }
  }
  Vec3 border_sum = Vec3::Zero();
  std::size_t border_count = 0;
  for (const auto& [edge, n] : directed)
    if (!directed.count({edge.second, edge.first})) {
      border_sum += mesh.vertices[edge.first];
      ++border_count;
    }
  const Vec3 centre = border_count ? Vec3(border_sum / double(border_count)) : Vec3(all_sum / double(all_count));
  double volume = 0, area = 0;
  for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
    if (component[f] != c) continue;
    const Vec3 a = face_vertex(mesh, f, 0) - centre, b = face_vertex(mesh, f, 1) - centre, d = face_vertex(mesh, f, 2) - centre;
    volume += a.dot(b.cross(d)) / 6;
    area += face_area_vector(mesh, f).norm();
  }
  return {std::abs(volume), area};
}

}  // namespace

SurfaceLabel label_of_surface_name(const std::string& name) {
  static const std::map<std::string, SurfaceLabel> names{
      {"epi", label_epi},           {"epicardium", label_epi},          {"lv_endo", label_lv_endo},
      {"lv", label_lv_endo},        {"endo_lv", label_lv_endo},         {"lv_endocardium", label_lv_endo},
      {"rv_endo", label_rv_endo},   {"rv", label_rv_endo},              {"endo_rv", label_rv_endo},
      {"rv_endocardium", label_rv_endo}, {"base", label_base}};
  const auto it = names.find(lower(name));
  return it == names.end() ? label_none : it->second;
}

std::string_view surface_label_name(SurfaceLabel label) {
  switch (label) {
    case label_epi: return "epicardium";
    case label_lv_endo: return "lv_endocardium";
    case label_rv_endo: return "rv_endocardium";
    case label_base: return "base";
    default: return "none";
  }
}

std::size_t FaceLabels::count(SurfaceLabel label) const { return std::size_t(std::count(face.begin(), face.end(), label)); }

FaceLabels face_labels_from_regions(const TriangleMesh& mesh) {
  FaceLabels labels;
  std::vector<SurfaceLabel> region_label;
  std::string unknown;
  for (const auto& name : mesh.region_names) {
    region_label.push_back(label_of_surface_name(name));
    if (region_label.back() == label_none) unknown += (unknown.empty() ? "'" : ", '") + name + "'";
  }
  const bool any = std::any_of(region_label.begin(), region_label.end(), [](SurfaceLabel l) { return l != label_none; });
  if (!any) return labels;
  if (!unknown.empty())
    throw MeshError("mesh regions " + unknown + " are not surface names (epi, lv_endo, rv_endo, base)");
  labels.method = "regions";
  labels.face.resize(mesh.n_faces());
  Vec3 base_normal = Vec3::Zero();
  for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
    labels.face[f] = region_label[static_cast<std::size_t>(mesh.face_region[f])];
    if (labels.face[f] == label_base) base_normal += face_area_vector(mesh, f);
  }
  labels.has_base = base_normal.norm() > 0;
  if (labels.has_base) labels.base_normal = base_normal.normalized();
  if (!labels.count(label_epi) || !labels.count(label_lv_endo))
    throw MeshError("mesh regions name no epicardium or no LV endocardium (need epi and lv_endo)");
  return labels;
}

FaceLabels face_labels_by_rule(const TriangleMesh& mesh) {
  FaceLabels labels;
  labels.method = "geometric rule";
  const std::size_t n = mesh.n_faces();
  labels.face.assign(n, label_none);
  double total_area = 0;
  for (std::size_t f = 0; f < n; ++f) total_area += face_area_vector(mesh, f).norm();
  const auto box = mesh.bounding_box();
  const double diagonal = box.extent().norm();

  // 1. Base: the flat cut holding the largest area at an extreme of an axis direction.
  const double cos_tolerance = std::cos(20.0 * std::acos(-1.0) / 180.0);
  double best_area = 0;
  int best = -1;
  for (int d = 0; d < 6; ++d) {
    Vec3 direction = Vec3::Zero();
    direction[d / 2] = d % 2 ? -1.0 : 1.0;
    double extreme = -1e300;
    for (const auto& v : mesh.vertices) extreme = std::max(extreme, v.dot(direction));
    double area = 0;
    for (std::size_t f = 0; f < n; ++f) {
      const Vec3 a = face_area_vector(mesh, f);
      if (a.normalized().dot(direction) > cos_tolerance && face_centroid(mesh, f).dot(direction) > extreme - 0.01 * diagonal)
        area += a.norm();
    }
    if (area > best_area) {
      best_area = area;
      best = d;
    }
  }
  std::vector<bool> keep(n, true);
  if (best >= 0 && best_area > 0.01 * total_area) {
    Vec3 direction = Vec3::Zero();
    direction[best / 2] = best % 2 ? -1.0 : 1.0;
    double extreme = -1e300;
    for (const auto& v : mesh.vertices) extreme = std::max(extreme, v.dot(direction));
    for (std::size_t f = 0; f < n; ++f) {
      const Vec3 a = face_area_vector(mesh, f);
      if (a.normalized().dot(direction) > cos_tolerance && face_centroid(mesh, f).dot(direction) > extreme - 0.01 * diagonal) {
        labels.face[f] = label_base;
        keep[f] = false;
      }
    }
    labels.has_base = true;
    labels.base_normal = direction;
  }

  // 2. Components; the largest is the epicardium.
  int count = 0;
  const auto component = face_components(mesh, keep, count);
  std::vector<double> area(static_cast<std::size_t>(count), 0.0);
  for (std::size_t f = 0; f < n; ++f)
    if (component[f] >= 0) area[static_cast<std::size_t>(component[f])] += face_area_vector(mesh, f).norm();
  if (count == 0) throw MeshError("surface labels: the mesh has no faces besides the base");
  const int epi = int(std::max_element(area.begin(), area.end()) - area.begin());

  // 3. Endocardia by compactness of the closed cavity.
  std::vector<std::pair<double, int>> cavities;  // (compactness, component)
  for (int c = 0; c < count; ++c) {
    if (c == epi || area[static_cast<std::size_t>(c)] < 0.005 * total_area) continue;
    const auto [volume, a] = cavity_volume_and_area(mesh, component, c);
    cavities.emplace_back(36 * std::acos(-1.0) * volume * volume / (a * a * a), c);
  }
  if (cavities.empty())
    throw MeshError("surface labels: no endocardium found (after removing the base, the surface is one piece); "
                    "give the surfaces separately or as named regions");
  std::sort(cavities.rbegin(), cavities.rend());
  std::vector<SurfaceLabel> component_label(static_cast<std::size_t>(count), label_epi);
  for (std::size_t k = 0; k < cavities.size(); ++k) {
    component_label[static_cast<std::size_t>(cavities[k].second)] = k == 1 ? label_rv_endo : label_lv_endo;
    labels.cavity_compactness.push_back(cavities[k].first);
  }
  for (std::size_t f = 0; f < n; ++f)
    if (component[f] >= 0) labels.face[f] = component_label[static_cast<std::size_t>(component[f])];
  return labels;
}

FaceLabels label_faces(const TriangleMesh& mesh) {
  FaceLabels labels = face_labels_from_regions(mesh);
  return labels.face.empty() ? face_labels_by_rule(mesh) : labels;
}

std::vector<std::int8_t> label_particles(const std::vector<Vec3>& positions, const std::vector<std::uint8_t>& surface,
                                         const geometry::MeshShape& mesh, const FaceLabels& labels) {
  std::vector<std::int8_t> result(positions.size(), label_none);
  sph::parallel_for(positions.size(), [&](std::size_t i) {
    if (surface[i]) result[i] = labels.face[mesh.nearest_face(positions[i])];
  });
  return result;
}

std::vector<std::int8_t> label_particles_by_surfaces(const std::vector<Vec3>& positions,
                                                     const std::vector<std::uint8_t>& surface,
                                                     const std::vector<LabelledSurface>& surfaces) {
  std::vector<std::int8_t> result(positions.size(), label_none);
  sph::parallel_for(positions.size(), [&](std::size_t i) {
    if (!surface[i]) return;
    double nearest = 1e300;
    for (const auto& s : surfaces) {
      const double d = s.mesh->unsigned_distance(positions[i]);
      if (d < nearest) {
        nearest = d;
        result[i] = s.label;
      }
    }
  });
  return result;
}

}  // namespace cardio
