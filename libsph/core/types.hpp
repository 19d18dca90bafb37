#pragma once
// Scalar, vector and matrix types shared by the whole library.

#include <Eigen/Core>
#include <Eigen/LU>  // determinant() and inverse() of the small fixed-size matrices
#include <cstddef>
#include <cstdint>

namespace sph {

#ifdef CARDIOSPH_SINGLE_PRECISION
using Real = float;
#else
using Real = double;
#endif

/// Particle index inside one particle set (32 bits keep neighbour lists small).
using Index = std::uint32_t;

template <int Dim>
using Vec = Eigen::Matrix<Real, Dim, 1>;

template <int Dim>
using Mat = Eigen::Matrix<Real, Dim, Dim>;

inline constexpr Real pi = Real(3.14159265358979323846);

}  // namespace sph
