#pragma once
// Bounds that depend on the floating-point type of sph::Real: a test states its bound for double
// (the default build) and for float (CARDIOSPH_SINGLE_PRECISION), where round-off in the sums is
// about 1e-7 relative instead of 1e-16.
#include <type_traits>

#include "libsph/core/types.hpp"

namespace test {

constexpr double bound(double for_double, double for_float) {
  return std::is_same_v<sph::Real, float> ? for_float : for_double;
}

}  // namespace test
