#pragma once
// Cavity surfaces of a ventricular body: the LV and RV endocardia of the mesh, carried along with
// the particles, for cavity volumes over time and cavity pressure loads.
//
// Faces carry the labels of the mesh (regions or the geometric rule, cardio/surface_labels.hpp);
// when the particles were labelled from separate surface meshes instead, each face takes the label
// of its nearest labelled particle. For each endocardial label:
// - the faces and their vertices; a vertex P moves with the tissue by the first-order reconstruction
//     x(P) = sum_i w_i (x_i + F_i (P - X_i)) / sum_i w_i,   w_i = V_i W(|P - X_i|, h),
//   over the particles within one support of P in the reference configuration (exact for any
//   locally affine motion);
// - the cavity volume: the surface closed at its border (the base opening) by a fan from the
//   centroid c of the border vertices, V = |sum_faces (a - c) . ((b - c) x (d - c))| / 6 (the fan
//   triangles contribute nothing with apex c), evaluated at the moved vertices;
// - the load of a cavity pressure p: on each face of the moved surface the follower force
//   - p a n_a (a n_a = (b - a) x (c - a) / 2 its current area vector, outward of the myocardium,
//   i.e. into the cavity), a third to each vertex, passed to the particles with the weights that
//   move the vertex (the transpose of the interpolation, so the load does the work p dV on the
//   interpolated surface). Spreading the load over the stencils keeps it smooth where a load on
//   single surface particles, through their own F, lets the surface layer buckle.
// - for reference, each face's reference area vector is also summed on its nearest particle
//   (loaded_particles, area_normals).

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "cardio/surface_labels.hpp"
#include "geometry/mesh.hpp"
#include "libsph/core/kernels.hpp"
#include "libsph/core/types.hpp"

namespace cardio {

using sph::Real;

struct CavitySurface {
  SurfaceLabel label = label_none;
  std::vector<sph::Vec<3>> reference_vertices;
  std::vector<std::array<std::uint32_t, 3>> faces;  ///< oriented outward of the myocardium
  std::vector<std::uint32_t> border;                ///< vertices on the opening (empty: closed)
  std::vector<std::size_t> stencil_offsets;         ///< per vertex into stencil_particle / weight
  std::vector<sph::Index> stencil_particle;
  std::vector<Real> stencil_weight;                 ///< normalised per vertex
  std::vector<sph::Index> loaded_particles;         ///< particles carrying the faces' area
  std::vector<sph::Vec<3>> area_normals;            ///< sum of A n of their faces (reference)
  double reference_volume = 0;                      ///< [mm^3]
  double area = 0;                                  ///< reference area of the faces

  /// Vertices at the current configuration (x, F and X of the particles).
  std::vector<sph::Vec<3>> moved_vertices(std::span<const sph::Vec<3>> x, std::span<const sph::Mat<3>> F,
                                          std::span<const sph::Vec<3>> X) const;
  /// The same into `moved` (resized; its storage is reused from call to call).
  void move_vertices(std::span<const sph::Vec<3>> x, std::span<const sph::Mat<3>> F, std::span<const sph::Vec<3>> X,
                     std::vector<sph::Vec<3>>& moved) const;
  /// Adds the forces of cavity pressure p on the particles to `force` (see above).
  void add_pressure_forces(Real pressure, std::span<const sph::Vec<3>> x, std::span<const sph::Mat<3>> F,
                           std::span<const sph::Vec<3>> X, std::span<sph::Vec<3>> force) const;
  /// The same for a pressure that depends on the cavity volume V (a 0D model coupled through a stiff
  /// volume penalty): V is taken from the same moved surface, p(V) applied; returns V [mm^3].
  double add_pressure_forces(const std::function<Real(double volume)>& pressure_of_volume, std::span<const sph::Vec<3>> x,
                             std::span<const sph::Mat<3>> F, std::span<const sph::Vec<3>> X, std::span<sph::Vec<3>> force) const;
  /// Cavity volume at the current configuration.
  double volume(std::span<const sph::Vec<3>> x, std::span<const sph::Mat<3>> F, std::span<const sph::Vec<3>> X) const;

 private:
  void spread_pressure(Real pressure, std::span<sph::Vec<3>> force) const;  // on moved_scratch_
  // Scratch of add_pressure_forces, kept so that the load allocates nothing once warm (the calls
  // on one surface are sequential: one mechanics sub-step after another).
  mutable std::vector<sph::Vec<3>> moved_scratch_, vertex_force_scratch_;
};

inline constexpr SurfaceLabel cavity_labels[] = {label_lv_endo, label_rv_endo};

/// Volume of the cavity bounded by `faces` of `vertices`, closed by a fan at its border (see above).
double closed_cavity_volume(std::span<const sph::Vec<3>> vertices, std::span<const std::array<std::uint32_t, 3>> faces,
                            std::span<const std::uint32_t> border);

/// The surfaces of the mesh with the given labels (default: the LV and RV cavities, LV first). `face_labels` holds one label per face, or
/// is empty to label each face by its nearest labelled particle. `positions` and `volumes` are the
/// particles in the reference configuration, `labels` their surface labels, `spacing` the particle
/// spacing; the vertex stencils use `kernel` with smoothing length h. Each face's area goes to the
/// nearest particle of its label. Throws std::invalid_argument if a face is farther than 3
/// spacings from every labelled particle.
std::vector<CavitySurface> cavity_surfaces(const geometry::TriangleMesh& mesh, std::span<const SurfaceLabel> face_labels,
                                           std::span<const sph::Vec<3>> positions,
                                           std::span<const Real> volumes, std::span<const std::int8_t> labels,
                                           Real spacing, const sph::AnyKernel<3>& kernel, Real smoothing_length,
                                           std::span<const SurfaceLabel> kept_labels = cavity_labels);

}  // namespace cardio
