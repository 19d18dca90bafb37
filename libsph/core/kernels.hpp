#pragma once
// Smoothing kernels W(r, h) with compact support 2h, normalised so that the integral of W over
// R^Dim is 1. Every kernel offers value, radial derivative dW/dr, dW/dr / r and the gradient
// grad_i W(x_i - x_j) = dW/dr * e_ij with e_ij = (x_i - x_j) / r_ij.
//
// Normalisation constants (q = r / h, support q < 2):
//   Wendland C2:  W = a_d (1 - q/2)^4 (1 + 2q),            a_2 = 7 / (4 pi h^2),   a_3 = 21 / (16 pi h^3)
//   Wendland C4:  W = a_d (1 - q/2)^6 (1 + 3q + 35/12 q^2), a_2 = 9 / (4 pi h^2),   a_3 = 495 / (256 pi h^3)
//   cubic B-spline M4: W = s_d [1 - 3/2 q^2 + 3/4 q^3] for q < 1, s_d/4 (2 - q)^3 for 1 <= q < 2,
//                                                         s_2 = 10 / (7 pi h^2),  s_3 = 1 / (pi h^3)
// Sources: Wendland 1995, Adv. Comput. Math. 4:389; Dehnen & Aly 2012, MNRAS 425:1068 (table 1,
// written there with the support radius H = 2h); Monaghan 1992, Annu. Rev. Astron. Astrophys. 30:543.
// Each constant is checked by numerical integration in tests/test_kernels.cpp.

#include <cmath>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>

#include "libsph/core/types.hpp"

namespace sph {

template <int Dim>
struct WendlandC2 {
  static_assert(Dim == 2 || Dim == 3, "Wendland C2 is positive definite in 2D and 3D only");
  static constexpr const char* name = "wendland_c2";

  static Real support_radius(Real h) { return Real(2) * h; }
  static Real normalisation(Real h) {
    if constexpr (Dim == 2) return Real(7) / (Real(4) * pi * h * h);
    else return Real(21) / (Real(16) * pi * h * h * h);
  }
  static Real value(Real r, Real h) {
    const Real q = r / h;
    if (q >= Real(2)) return Real(0);
    const Real s = Real(1) - Real(0.5) * q;
    return normalisation(h) * s * s * s * s * (Real(1) + Real(2) * q);
  }
  // d/dr [(1 - q/2)^4 (1 + 2q)] = -5 q (1 - q/2)^3 / h
  static Real derivative(Real r, Real h) {
    const Real q = r / h;
    if (q >= Real(2)) return Real(0);
    const Real s = Real(1) - Real(0.5) * q;
    return -Real(5) * normalisation(h) * q * s * s * s / h;
  }
  static Real derivative_over_r(Real r, Real h) {
    const Real q = r / h;
    if (q >= Real(2)) return Real(0);
    const Real s = Real(1) - Real(0.5) * q;
    return -Real(5) * normalisation(h) * s * s * s / (h * h);
  }
  /// W = normalisation(h) shape(q) and dW/dr = normalisation(h) / h shape_derivative(q), for q < 2.
  static Real shape(Real q) {
    const Real s = Real(1) - Real(0.5) * q;
    return s * s * s * s * (Real(1) + Real(2) * q);
  }
  static Real shape_derivative(Real q) {
    const Real s = Real(1) - Real(0.5) * q;
    return -Real(5) * q * s * s * s;
  }
};

template <int Dim>
struct WendlandC4 {
  static_assert(Dim == 2 || Dim == 3, "Wendland C4 is positive definite in 2D and 3D only");
  static constexpr const char* name = "wendland_c4";

  static Real support_radius(Real h) { return Real(2) * h; }
  static Real normalisation(Real h) {
    if constexpr (Dim == 2) return Real(9) / (Real(4) * pi * h * h);
    else return Real(495) / (Real(256) * pi * h * h * h);
  }
  static Real value(Real r, Real h) {
    const Real q = r / h;
    if (q >= Real(2)) return Real(0);
    const Real s = Real(1) - Real(0.5) * q;
    const Real s2 = s * s;
    return normalisation(h) * s2 * s2 * s2 * (Real(1) + Real(3) * q + Real(35) / Real(12) * q * q);
  }
  // d/dr [(1 - q/2)^6 (1 + 3q + 35/12 q^2)] = -(14/3) q (1 + 5q/2) (1 - q/2)^5 / h
  static Real derivative_over_r(Real r, Real h) {
    const Real q = r / h;
    if (q >= Real(2)) return Real(0);
    const Real s = Real(1) - Real(0.5) * q;
    const Real s2 = s * s;
    return -Real(14) / Real(3) * normalisation(h) * (Real(1) + Real(2.5) * q) * s2 * s2 * s / (h * h);
  }
  static Real derivative(Real r, Real h) { return derivative_over_r(r, h) * r; }
  static Real shape(Real q) {
    const Real s = Real(1) - Real(0.5) * q;
    const Real s2 = s * s;
    return s2 * s2 * s2 * (Real(1) + Real(3) * q + Real(35) / Real(12) * q * q);
  }
  static Real shape_derivative(Real q) {
    const Real s = Real(1) - Real(0.5) * q;
    const Real s2 = s * s;
    return -Real(14) / Real(3) * q * (Real(1) + Real(2.5) * q) * s2 * s2 * s;
  }
};

template <int Dim>
struct CubicSplineM4 {
  static_assert(Dim == 2 || Dim == 3, "only 2D and 3D normalisations are provided");
  static constexpr const char* name = "cubic_spline";

  static Real support_radius(Real h) { return Real(2) * h; }
  static Real normalisation(Real h) {
    if constexpr (Dim == 2) return Real(10) / (Real(7) * pi * h * h);
    else return Real(1) / (pi * h * h * h);
  }
  static Real value(Real r, Real h) {
    const Real q = r / h;
    if (q >= Real(2)) return Real(0);
    if (q < Real(1)) return normalisation(h) * (Real(1) - Real(1.5) * q * q + Real(0.75) * q * q * q);
    const Real s = Real(2) - q;
    return normalisation(h) * Real(0.25) * s * s * s;
  }
  static Real derivative(Real r, Real h) {
    const Real q = r / h;
    if (q >= Real(2)) return Real(0);
    if (q < Real(1)) return normalisation(h) * (-Real(3) * q + Real(2.25) * q * q) / h;
    const Real s = Real(2) - q;
    return -normalisation(h) * Real(0.75) * s * s / h;
  }
  static Real derivative_over_r(Real r, Real h) {
    const Real q = r / h;
    if (q >= Real(2)) return Real(0);
    if (q < Real(1)) return normalisation(h) * (-Real(3) + Real(2.25) * q) / (h * h);
    const Real s = Real(2) - q;
    return -normalisation(h) * Real(0.75) * s * s / (q * h * h);
  }
  static Real shape(Real q) {
    if (q < Real(1)) return Real(1) - Real(1.5) * q * q + Real(0.75) * q * q * q;
    const Real s = Real(2) - q;
    return Real(0.25) * s * s * s;
  }
  static Real shape_derivative(Real q) {
    if (q < Real(1)) return -Real(3) * q + Real(2.25) * q * q;
    const Real s = Real(2) - q;
    return -Real(0.75) * s * s;
  }
};

/// grad_i W(x_i - x_j) for displacement x_ij = x_i - x_j.
template <class Kernel, int Dim>
Vec<Dim> kernel_gradient(const Vec<Dim>& x_ij, Real h) {
  const Real r = x_ij.norm();
  return Kernel::derivative_over_r(r, h) * x_ij;
}

/// A kernel chosen at run time (by a scene parameter). Visit it once, outside particle loops.
template <int Dim>
using AnyKernel = std::variant<WendlandC2<Dim>, CubicSplineM4<Dim>, WendlandC4<Dim>>;

/// Kernel names accepted by make_kernel, in the order of AnyKernel.
inline constexpr std::string_view kernel_names[] = {"wendland_c2", "cubic_spline", "wendland_c4"};

/// Kernel by name; throws std::invalid_argument naming the value when unknown.
template <int Dim>
AnyKernel<Dim> make_kernel(std::string_view name) {
  if (name == "wendland_c2") return WendlandC2<Dim>{};
  if (name == "cubic_spline") return CubicSplineM4<Dim>{};
  if (name == "wendland_c4") return WendlandC4<Dim>{};
  throw std::invalid_argument("unknown kernel '" + std::string(name) +
                              "' (expected wendland_c2, cubic_spline or wendland_c4)");
}

}  // namespace sph
