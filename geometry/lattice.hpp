#pragma once
// Lattice particles: cell centres of a regular grid of spacing dp filling an axis-aligned box, each
// with the volume dp^Dim of its cell (so the volumes sum to the box volume exactly).

#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "libsph/core/particles.hpp"

namespace geometry {

/// Particles of spacing `spacing` filling [lower, upper]; the box extent must be a whole number of
/// spacings in every direction (up to round-off), so that volumes sum exactly.
template <int Dim>
sph::ParticleSet<Dim> lattice_box(const std::string& name, const sph::Vec<Dim>& lower, const sph::Vec<Dim>& upper,
                                  sph::Real spacing) {
  if (!(spacing > 0)) throw std::invalid_argument("lattice '" + name + "': spacing must be positive");
  std::array<long, Dim> count{};
  std::size_t total = 1;
  for (int d = 0; d < Dim; ++d) {
    const double cells = static_cast<double>((upper[d] - lower[d]) / spacing);
    count[d] = std::lround(cells);
    const double tolerance = std::max(1e-9, 100.0 * std::numeric_limits<sph::Real>::epsilon());
    if (count[d] < 1 || std::abs(cells - static_cast<double>(count[d])) > tolerance * std::max(1.0, cells))
      throw std::invalid_argument("lattice '" + name + "': box extent is not a whole number of spacings");
    total *= static_cast<std::size_t>(count[d]);
  }
  std::vector<sph::Vec<Dim>> positions;
  positions.reserve(total);
  std::array<long, Dim> k{};
  for (std::size_t n = 0; n < total; ++n) {
    std::size_t rest = n;
    for (int d = 0; d < Dim; ++d) {
      k[d] = static_cast<long>(rest % static_cast<std::size_t>(count[d]));
      rest /= static_cast<std::size_t>(count[d]);
    }
    sph::Vec<Dim> x;
    for (int d = 0; d < Dim; ++d) x[d] = lower[d] + (static_cast<sph::Real>(k[d]) + sph::Real(0.5)) * spacing;
    positions.push_back(x);
  }
  sph::Real volume = 1;
  for (int d = 0; d < Dim; ++d) volume *= spacing;
  return sph::ParticleSet<Dim>(name, std::move(positions), std::vector<sph::Real>(total, volume));
}

}  // namespace geometry

namespace geometry {

/// The cell centres of the lattice of spacing `spacing` on [lower, upper] (a whole number of
/// spacings) for which inside(x) holds, each with the volume spacing^Dim of its cell.
template <int Dim, class Inside>
sph::ParticleSet<Dim> lattice_where(const std::string& name, const sph::Vec<Dim>& lower, const sph::Vec<Dim>& upper,
                                    sph::Real spacing, Inside inside) {
  const auto all = lattice_box<Dim>(name, lower, upper, spacing);
  std::vector<sph::Vec<Dim>> positions;
  for (const auto& x : all.position)
    if (inside(x)) positions.push_back(x);
  if (positions.empty()) throw std::invalid_argument("lattice '" + name + "': no cell centre lies inside the shape");
  sph::Real volume = 1;
  for (int d = 0; d < Dim; ++d) volume *= spacing;
  const std::size_t n = positions.size();
  return sph::ParticleSet<Dim>(name, std::move(positions), std::vector<sph::Real>(n, volume));
}

}  // namespace geometry
