#pragma once
// Reproducible random points for the neighbour-search tests.

#include <cstdint>
#include <random>
#include <vector>

#include "libsph/core/types.hpp"

namespace test {

/// A uniform number in [0, 1) from the top 53 bits of the engine.
inline sph::Real uniform(std::mt19937_64& engine) { return static_cast<sph::Real>(engine() >> 11) * static_cast<sph::Real>(0x1.0p-53); }

/// n points uniform in [0, extent]^Dim.
template <int Dim>
std::vector<sph::Vec<Dim>> random_points(std::size_t n, sph::Real extent, std::uint64_t seed) {
  std::mt19937_64 engine(seed);
  std::vector<sph::Vec<Dim>> points(n);
  for (auto& x : points)
    for (int d = 0; d < Dim; ++d) x[d] = extent * uniform(engine);
  return points;
}

}  // namespace test
