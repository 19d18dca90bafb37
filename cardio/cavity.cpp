#include "cardio/cavity.hpp"

#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <variant>

#include "libsph/core/cell_linked_list.hpp"
#include "libsph/core/parallel.hpp"

namespace cardio {

double closed_cavity_volume(std::span<const sph::Vec<3>> vertices, std::span<const std::array<std::uint32_t, 3>> faces,
                            std::span<const std::uint32_t> border) {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  if (!border.empty()) {
    for (const auto v : border) centre += vertices[v].cast<double>();
    centre /= double(border.size());
  } else {
    for (const auto& v : vertices) centre += v.cast<double>();
    centre /= double(std::max<std::size_t>(vertices.size(), 1));
  }
  double volume = 0;
  for (const auto& f : faces) {
    const Eigen::Vector3d a = vertices[f[0]].cast<double>() - centre, b = vertices[f[1]].cast<double>() - centre,
                          d = vertices[f[2]].cast<double>() - centre;
    volume += a.dot(b.cross(d)) / 6;
  }
  return std::abs(volume);
}

std::vector<sph::Vec<3>> CavitySurface::moved_vertices(std::span<const sph::Vec<3>> x, std::span<const sph::Mat<3>> F,
                                                       std::span<const sph::Vec<3>> X) const {
  std::vector<sph::Vec<3>> moved;
  move_vertices(x, F, X, moved);
  return moved;
}

void CavitySurface::move_vertices(std::span<const sph::Vec<3>> x, std::span<const sph::Mat<3>> F,
                                  std::span<const sph::Vec<3>> X, std::vector<sph::Vec<3>>& moved) const {
  moved.resize(reference_vertices.size());
  sph::parallel_for(moved.size(), [&](std::size_t v) {
    const sph::Vec<3>& P = reference_vertices[v];
    sph::Vec<3> sum = sph::Vec<3>::Zero();
    for (std::size_t k = stencil_offsets[v]; k < stencil_offsets[v + 1]; ++k) {
      const sph::Index i = stencil_particle[k];
      sum += stencil_weight[k] * (x[i] + F[i] * (P - X[i]));
    }
    moved[v] = sum;
  });
}

void CavitySurface::add_pressure_forces(Real pressure, std::span<const sph::Vec<3>> x, std::span<const sph::Mat<3>> F,
                                        std::span<const sph::Vec<3>> X, std::span<sph::Vec<3>> force) const {
  if (pressure == 0) return;
  move_vertices(x, F, X, moved_scratch_);
  spread_pressure(pressure, force);
}

double CavitySurface::add_pressure_forces(const std::function<Real(double volume)>& pressure_of_volume,
                                          std::span<const sph::Vec<3>> x, std::span<const sph::Mat<3>> F,
                                          std::span<const sph::Vec<3>> X, std::span<sph::Vec<3>> force) const {
  move_vertices(x, F, X, moved_scratch_);
  const double V = closed_cavity_volume(moved_scratch_, faces, border);
  spread_pressure(pressure_of_volume(V), force);
  return V;
}

void CavitySurface::spread_pressure(Real pressure, std::span<sph::Vec<3>> force) const {
  const auto& moved = moved_scratch_;
  auto& vertex_force = vertex_force_scratch_;
  vertex_force.assign(moved.size(), sph::Vec<3>::Zero());
  for (const auto& f : faces) {
    const sph::Vec<3> load = -pressure / 6 * (moved[f[1]] - moved[f[0]]).cross(moved[f[2]] - moved[f[0]]);  // a third of -p a n_a
    for (int k = 0; k < 3; ++k) vertex_force[f[k]] += load;
  }
  for (std::size_t v = 0; v < moved.size(); ++v)
    for (std::size_t k = stencil_offsets[v]; k < stencil_offsets[v + 1]; ++k)
      force[stencil_particle[k]] += stencil_weight[k] * vertex_force[v];
}

double CavitySurface::volume(std::span<const sph::Vec<3>> x, std::span<const sph::Mat<3>> F,
                             std::span<const sph::Vec<3>> X) const {
  const auto moved = moved_vertices(x, F, X);
  return closed_cavity_volume(moved, faces, border);
}

std::vector<CavitySurface> cavity_surfaces(const geometry::TriangleMesh& mesh, std::span<const SurfaceLabel> face_labels,
                                           std::span<const sph::Vec<3>> positions,
                                           std::span<const Real> volumes, std::span<const std::int8_t> labels,
                                           Real spacing, const sph::AnyKernel<3>& kernel, Real smoothing_length,
                                           std::span<const SurfaceLabel> kept_labels) {
  const std::size_t n = positions.size();
  if (labels.size() != n || volumes.size() != n) throw std::invalid_argument("cavity surfaces: one label and volume per particle");
  if (!face_labels.empty() && face_labels.size() != mesh.n_faces())
    throw std::invalid_argument("cavity surfaces: one label per mesh face");
  std::vector<sph::Vec<3>> labelled_position;
  std::vector<sph::Index> labelled_index;
  for (std::size_t i = 0; i < n; ++i)
    if (labels[i] != label_none) {
      labelled_position.push_back(positions[i]);
      labelled_index.push_back(static_cast<sph::Index>(i));
    }
  if (labelled_index.empty()) throw std::invalid_argument("cavity surfaces: no labelled surface particle");
  const Real search = 3 * spacing;
  const sph::CellLinkedList<3> labelled_cells(labelled_position, search);

  // Label of every face, and the nearest particle of that label to its centroid.
  std::vector<SurfaceLabel> face_label(mesh.n_faces(), label_none);
  std::vector<sph::Index> nearest(mesh.n_faces());
  sph::parallel_for(mesh.n_faces(), [&](std::size_t f) {
    sph::Vec<3> c = sph::Vec<3>::Zero();
    for (int k = 0; k < 3; ++k) c += mesh.vertices[mesh.faces[f][k]].cast<Real>() / 3;
    const SurfaceLabel wanted = face_labels.empty() ? label_none : face_labels[f];
    Real best = std::numeric_limits<Real>::infinity(), best_any = best;
    sph::Index best_index = static_cast<sph::Index>(-1), best_any_index = best_index;
    labelled_cells.for_each_candidate(c, [&](std::size_t j) {
      const Real d = (labelled_position[j] - c).squaredNorm();
      if (d < best_any) best_any = d, best_any_index = labelled_index[j];
      if (labels[labelled_index[j]] == wanted && d < best) best = d, best_index = labelled_index[j];
    });
    if (best > search * search) best_index = best_any_index, best = best_any;  // no particle of the face's label near
    nearest[f] = best <= search * search ? best_index : static_cast<sph::Index>(-1);
    face_label[f] = face_labels.empty() && nearest[f] != static_cast<sph::Index>(-1)
                        ? static_cast<SurfaceLabel>(labels[nearest[f]]) : wanted;
  });
  for (std::size_t f = 0; f < mesh.n_faces(); ++f)
    if (nearest[f] == static_cast<sph::Index>(-1))
      throw std::invalid_argument("cavity surfaces: mesh face " + std::to_string(f) + " lies farther than 3 spacings from every surface particle");

  const Real support = std::visit([](const auto& k) { return k.support_radius(Real(1)); }, kernel) * smoothing_length;
  const sph::CellLinkedList<3> all_cells(positions, support);
  std::vector<CavitySurface> surfaces;
  for (const SurfaceLabel label : kept_labels) {
    CavitySurface s;
    s.label = label;
    std::map<std::uint32_t, std::uint32_t> vertex_of;  // mesh vertex -> surface vertex
    std::map<sph::Index, std::size_t> load_of;         // particle -> loaded entry
    for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
      if (face_label[f] != label) continue;
      std::array<std::uint32_t, 3> face{};
      for (int k = 0; k < 3; ++k) {
        const auto [it, added] = vertex_of.emplace(mesh.faces[f][k], static_cast<std::uint32_t>(s.reference_vertices.size()));
        if (added) s.reference_vertices.push_back(mesh.vertices[mesh.faces[f][k]].cast<Real>());
        face[k] = it->second;
      }
      s.faces.push_back(face);
      const geometry::Vec3 a = mesh.vertices[mesh.faces[f][0]], b = mesh.vertices[mesh.faces[f][1]], c = mesh.vertices[mesh.faces[f][2]];
      const sph::Vec<3> area_normal = (0.5 * (b - a).cross(c - a)).cast<Real>();
      s.area += double(area_normal.norm());
      const auto [it, added] = load_of.emplace(nearest[f], s.loaded_particles.size());
      if (added) {
        s.loaded_particles.push_back(nearest[f]);
        s.area_normals.push_back(area_normal);
      } else {
        s.area_normals[it->second] += area_normal;
      }
    }
    if (s.faces.empty()) continue;
    // Border: directed edges without their opposite.
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (const auto& f : s.faces)
      for (int k = 0; k < 3; ++k) directed[{f[k], f[(k + 1) % 3]}] += 1;
    for (const auto& [edge, count] : directed)
      if (!directed.count({edge.second, edge.first})) s.border.push_back(edge.first);
    // Vertex stencils.
    s.stencil_offsets.assign(1, 0);
    std::visit(
        [&](const auto& k) {
          for (const auto& P : s.reference_vertices) {
            const std::size_t begin = s.stencil_particle.size();
            Real total = 0;
            all_cells.for_each_candidate(P, [&](std::size_t i) {
              const Real w = k.value((P - positions[i]).norm(), smoothing_length) * volumes[i];
              if (w <= 0) return;
              s.stencil_particle.push_back(static_cast<sph::Index>(i));
              s.stencil_weight.push_back(w);
              total += w;
            });
            if (!(total > 0)) throw std::invalid_argument("cavity surfaces: an endocardial vertex has no particle within one support");
            for (std::size_t m = begin; m < s.stencil_weight.size(); ++m) s.stencil_weight[m] /= total;
            s.stencil_offsets.push_back(s.stencil_particle.size());
          }
        },
        kernel);
    s.reference_volume = closed_cavity_volume(s.reference_vertices, s.faces, s.border);
    surfaces.push_back(std::move(s));
  }
  return surfaces;
}

}  // namespace cardio
