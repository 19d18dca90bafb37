#pragma once
// Particles for fluids: wall layers behind the boundary of a container shape and the check that
// a fluid lies inside it.
//
// Wall particles sit on the same lattice as the fluid (cell centres lower + (k + 1/2) dp), in the
// layer 0 < d <= thickness outside the container, d its signed distance; each carries the unit
// normal pointing into the fluid (minus the container's outward normal at the nearest surface
// point), which the one-sided Riemann problem of the wall needs (libsph/fluid/fluid_wall.hpp).
// In 2D the container is a 3D shape cut at z = 0.

#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "geometry/shape.hpp"
#include "libsph/core/particles.hpp"

namespace geometry {

template <int Dim>
struct WallParticles {
  sph::ParticleSet<Dim> particles;
  std::vector<sph::Vec<Dim>> normals;  ///< into the fluid
};

template <int Dim>
Vec3 embed(const sph::Vec<Dim>& x) {
  Vec3 p = Vec3::Zero();
  for (int d = 0; d < Dim; ++d) p[d] = static_cast<double>(x[d]);
  return p;
}

/// Wall particles of spacing dp in the layer of `thickness` outside `container`, on the lattice of
/// cell centres of [grid_lower, grid_upper] (a whole number of spacings along every axis).
template <int Dim>
WallParticles<Dim> wall_particles(const std::string& name, const Shape& container, const sph::Vec<Dim>& grid_lower,
                                  const sph::Vec<Dim>& grid_upper, sph::Real dp, double thickness) {
  if (!(dp > 0)) throw std::invalid_argument("wall '" + name + "': spacing must be positive");
  std::array<long, Dim> count{};
  std::size_t total = 1;
  for (int d = 0; d < Dim; ++d) {
    const double cells = static_cast<double>((grid_upper[d] - grid_lower[d]) / dp);
    count[d] = std::lround(cells);
    if (count[d] < 1 || std::abs(cells - static_cast<double>(count[d])) > 1e-6 * std::max(1.0, cells))
      throw std::invalid_argument("wall '" + name + "': grid extent is not a whole number of spacings");
    total *= static_cast<std::size_t>(count[d]);
  }
  std::vector<sph::Vec<Dim>> positions, normals;
  for (std::size_t n = 0; n < total; ++n) {
    std::size_t rest = n;
    sph::Vec<Dim> x;
    for (int d = 0; d < Dim; ++d) {
      const auto k = static_cast<long>(rest % static_cast<std::size_t>(count[d]));
      rest /= static_cast<std::size_t>(count[d]);
      x[d] = grid_lower[d] + (static_cast<sph::Real>(k) + sph::Real(0.5)) * dp;
    }
    const Vec3 p = embed<Dim>(x);
    const double distance = container.signed_distance(p);
    if (!(distance > 0 && distance <= thickness)) continue;
    const Vec3 outward = container.normal(p);
    sph::Vec<Dim> normal;
    for (int d = 0; d < Dim; ++d) normal[d] = static_cast<sph::Real>(-outward[d]);
    if (!(normal.norm() > 0.5)) throw std::invalid_argument("wall '" + name + "': no normal at a wall particle");
    positions.push_back(x);
    normals.push_back(normal.normalized());
  }
  if (positions.empty()) throw std::invalid_argument("wall '" + name + "': the layer around the container holds no particle");
  sph::Real volume = 1;
  for (int d = 0; d < Dim; ++d) volume *= dp;
  const std::size_t n_wall = positions.size();
  return {sph::ParticleSet<Dim>(name, std::move(positions), std::vector<sph::Real>(n_wall, volume)), std::move(normals)};
}

/// Throws std::invalid_argument naming the first fluid particle that is not inside `container` by
/// at least half a spacing (the fluid is not enclosed, or it overlaps the wall).
template <int Dim>
void check_inside(const sph::ParticleSet<Dim>& fluid, const Shape& container, sph::Real dp) {
  for (std::size_t i = 0; i < fluid.n_particles(); ++i) {
    const double distance = container.signed_distance(embed<Dim>(fluid.position[i]));
    if (distance <= -0.5 * dp * (1 - 1e-6)) continue;
    std::ostringstream s;
    s << "fluid '" << fluid.name() << "': particle " << i << " at (";
    for (int d = 0; d < Dim; ++d) s << (d ? ", " : "") << fluid.position[i][d];
    s << ") is " << (distance < 0 ? "closer than half a spacing to the wall of " : "outside ") << container.describe()
      << (distance < 0 ? " (fluid and wall overlap)" : " (the wall does not enclose the fluid)");
    throw std::invalid_argument(s.str());
  }
}

}  // namespace geometry
