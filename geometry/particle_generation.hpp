#pragma once
// Body-fitted particles inside a shape.
//
// 1. Level set: the shape's signed distance sampled on a grid of spacing dp (nodes on the particle
//    lattice, padded by three cells), exact in a band around the surface and interpolated from a
//    coarser grid far from it; trilinear interpolation gives distance and normal anywhere.
// 2. Lattice: one particle at every node inside the shape.
// 3. Relaxation: particles move against the zero-order consistency residual
//        r_i = sum_j V0 grad_i W_ij + A(d_i) n_i,      V0 = dp^3,
//    which vanishes for a uniform distribution. The second term is the part of the kernel support
//    outside the shape, integrated over the level-set nodes there (each weighted by the outside
//    fraction of its cell), as in the level-set correction of the body-fitted particle generator of
//    Zhu, Zhang, Yu & Hu 2021 (J. Hydrodyn. 33:195): the outside acts as if filled with particles,
//    so the surface neither attracts nor expels them and holds the outer layer near depth dp/2.
//    Each step moves x_i by -gamma h^2 r_i (at most 0.1 dp) and puts a particle that left the shape
//    back at depth 0.1 dp. A hard projection of the outer layer to depth dp/2 (a common choice) was
//    measured to compress it: on a sphere of radius 10 dp the volumes then summed 1.8 % short.
//    The sums run over Verlet lists (the particles and the outside nodes within support + skin),
//    rebuilt only once a particle has moved half the skin; their rows are in increasing index and
//    every term is tested against the exact distance, so the particles do not depend on the skin.
// 4. Volumes: V_i = dp^3 S_lattice / (sum_j W_ij + W(0) + outside part), with S_lattice the same sum
//    on a perfect lattice (the kernel's discrete normalisation, about 1.009 / dp^3 for Wendland C2 at
//    h = 1.3 dp), so that a lattice particle has exactly dp^3 and a surface particle is not
//    credited with the missing support.
//
// Reported: the particle count, sum V_i against the shape's volume, the spread of V_i, and the
// nearest-neighbour distances.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "geometry/shape.hpp"

namespace geometry {

struct ParticleGenerationSettings {
  double spacing = 0;                   ///< dp [length]
  double smoothing_ratio = 1.3;         ///< h / dp
  std::string kernel = "wendland_c2";   ///< kernel used by the relaxation and the volumes
  long relaxation_steps = 100;          ///< 0: keep the lattice
  double relaxation_gain = 0.2;         ///< gamma in dx = -gamma h^2 r
  /// Stop early once the largest displacement of a step falls below this fraction of dp.
  double converged_displacement = 1e-4;
  /// Verlet skin of the neighbour lists, as a fraction of dp: the lists hold the particles and
  /// outside level-set nodes within support + skin and are rebuilt once a particle has moved skin / 2.
  /// Any value gives the same particles; it only trades list length against rebuilds.
  double neighbour_skin = 0.3;
  /// Thin features: a particle is in one when it has fewer than min_neighbour_fraction of the
  /// median neighbour count, a neighbourhood conditioning below min_conditioning, or a neighbour
  /// closer than min_distance_ratio dp (relaxation packed particles into a feature thinner than
  /// the spacing, where the mechanics' corrected kernels are singular).
  double min_neighbour_fraction = 0.25, min_conditioning = 0.02, min_distance_ratio = 0.5;
  /// Called every step with (step, rms residual * h).
  std::function<void(long, double)> on_step;
};

struct BodyParticles {
  std::vector<Vec3> positions;
  std::vector<double> volumes;
  std::vector<double> depth;          ///< -signed distance (> 0 inside)
  std::vector<Vec3> normals;          ///< outward normal of the nearest surface point
  std::vector<std::uint8_t> surface;  ///< 1 for the outer layer (depth < dp)

  // Statistics.
  double shape_volume = 0;            ///< the shape's volume (exact or integrated)
  double volume_relative_error = 0;   ///< (sum V_i - shape_volume) / shape_volume
  double density_spread = 0;          ///< standard deviation of V_i / mean V_i
  double volume_min_ratio = 0, volume_max_ratio = 0;  ///< min and max of V_i / dp^3
  /// Distance from each particle to its nearest neighbour, over dp: min, mean, max, and the standard
  /// deviation over the mean.
  double spacing_min_ratio = 0, spacing_mean_ratio = 0, spacing_max_ratio = 0, spacing_spread = 0;
  double residual_initial = 0, residual_final = 0;    ///< rms |r_i| h over all particles
  /// Neighbourhoods within the kernel support: the median and smallest neighbour counts, and the
  /// smallest conditioning (lambda_min / lambda_max of sum_j W_ij r_ij r_ij^T: 1 for a full
  /// sphere, 0 for a single layer of particles).
  std::size_t neighbours_median = 0, neighbours_min = 0;
  double conditioning_min = 1;
  /// Particles in features thinner than the spacing (see check_thin_features), index order.
  std::vector<std::size_t> thin;
  std::string thin_description;       ///< the worst of them, for messages ("" when none)
  long relaxation_steps_done = 0;
  long neighbour_builds = 0;          ///< builds of the relaxation's neighbour lists
  double level_set_seconds = 0, lattice_seconds = 0, relaxation_seconds = 0, volume_seconds = 0;

  std::size_t size() const { return positions.size(); }
};

/// Particles of spacing settings.spacing filling `shape` (see the file comment). Throws
/// std::invalid_argument when the spacing is not positive or leaves no particle inside. Thin
/// features are measured (BodyParticles::thin), not acted on: see require_no_thin_features.
BodyParticles generate_particles(const Shape& shape, const ParticleGenerationSettings& settings);

/// Throws std::invalid_argument when `body` holds particles in thin features: the message counts
/// them, names the worst (position, neighbours against the median, nearest distance,
/// conditioning) and the spacing that would resolve the feature there (a third of its local
/// thickness, estimated as twice the largest depth of the thin particles around it). `what`
/// names the input (e.g. the mesh file).
void require_no_thin_features(const BodyParticles& body, double spacing, const std::string& what);

}  // namespace geometry
