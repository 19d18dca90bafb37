#pragma once
// Hyperelastic constitutive laws for total-Lagrangian SPH, behind one interface:
//   second_piola(F, f, s) -> S, the second Piola-Kirchhoff stress (P = F S),
//   energy(F, f, s)       -> W, the stored energy per reference volume,
//   wave_modulus()        -> M, the small-strain longitudinal (P-wave) modulus, which sets the
//                            acoustic time step c = sqrt(M / rho0).
// f and s are the local fibre and sheet directions in the reference configuration (unit,
// orthogonal); isotropic laws ignore them. Every S here is S = 2 dW/dC of its W, so the stress is
// consistent with the energy (checked by finite differences in the tests) and S(I) = 0.
// Notation: C = F^T F, E = (C - I) / 2, J = det F, I1 = tr C, I4f = f.C f, I4s = s.C s, I8 = f.C s;
// d = Dim (in 2D the laws are the plane-strain restriction: C33 = 1).
//
// Volumetric penalty of the (nearly) incompressible laws: U(J) = K/4 (J^2 - 1 - 2 ln J), which
// grows without bound as J -> 0 (it keeps particles from inverting) and has U''(1) = K;
// its stress is J U'(J) C^-1 = K/2 (J^2 - 1) C^-1. (Simo & Taylor 1982 form.)

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <variant>

#include <Eigen/Geometry>  // cross product

#include "libsph/core/types.hpp"

namespace sph {

namespace material_detail {
template <int Dim>
Mat<Dim> symmetric_dyad(const Vec<Dim>& a, const Vec<Dim>& b) {
  return a * b.transpose() + b * a.transpose();
}
inline Real volumetric_energy(Real K, Real J) { return K / 4 * (J * J - 1 - 2 * std::log(J)); }
inline Real volumetric_stress_factor(Real K, Real J) { return K / 2 * (J * J - 1); }  // J U'(J)
}  // namespace material_detail

/// Saint Venant-Kirchhoff (linear elastic in E): W = lambda/2 (tr E)^2 + mu E:E, S = lambda tr(E) I + 2 mu E.
template <int Dim>
struct SaintVenantKirchhoff {
  Real lambda = 0, mu = 0;  ///< Lame constants [stress]
  static constexpr bool anisotropic = false;
  Mat<Dim> second_piola(const Mat<Dim>& F, const Vec<Dim>&, const Vec<Dim>&) const {
    const Mat<Dim> E = Real(0.5) * (F.transpose() * F - Mat<Dim>::Identity());
    return lambda * E.trace() * Mat<Dim>::Identity() + 2 * mu * E;
  }
  Real energy(const Mat<Dim>& F, const Vec<Dim>&, const Vec<Dim>&) const {
    const Mat<Dim> E = Real(0.5) * (F.transpose() * F - Mat<Dim>::Identity());
    return lambda / 2 * E.trace() * E.trace() + mu * E.squaredNorm();
  }
  Real wave_modulus() const { return lambda + 2 * mu; }
  Real shear_modulus() const { return mu; }
};

/// Compressible Neo-Hookean: W = mu/2 (I1 - d) - mu ln J + lambda/2 (ln J)^2,
/// S = mu (I - C^-1) + lambda ln J C^-1 (Bonet & Wood, Nonlinear Continuum Mechanics, eq. 6.28).
template <int Dim>
struct NeoHookean {
  Real lambda = 0, mu = 0;
  static constexpr bool anisotropic = false;
  Mat<Dim> second_piola(const Mat<Dim>& F, const Vec<Dim>&, const Vec<Dim>&) const {
    const Mat<Dim> C_inverse = (F.transpose() * F).inverse();
    const Real log_J = std::log(F.determinant());
    return mu * (Mat<Dim>::Identity() - C_inverse) + lambda * log_J * C_inverse;
  }
  Real energy(const Mat<Dim>& F, const Vec<Dim>&, const Vec<Dim>&) const {
    const Real log_J = std::log(F.determinant());
    return mu / 2 * ((F.transpose() * F).trace() - Dim) - mu * log_J + lambda / 2 * log_J * log_J;
  }
  Real wave_modulus() const { return lambda + 2 * mu; }
  Real shear_modulus() const { return mu; }
};

/// The modified Holzapfel-Ogden myocardium law used in cardiac SPH (Holzapfel & Ogden 2009,
/// Phil. Trans. R. Soc. A 367:3445, eq. 5.38; in the compressible form of Zhang et al. 2021,
/// CMAME 381:113847):
///   W = a/(2b) [exp(b (I1 - d)) - 1] - a ln J
///     + sum_{i = f, s} a_i/(2 b_i) [exp(b_i <I4i - 1>^2) - 1] + a_fs/(2 b_fs) [exp(b_fs I8^2) - 1] + U(J)
///   S = a exp(b (I1 - d)) I - a C^-1 + 2 a_f <I4f - 1> exp(b_f <I4f - 1>^2) f (x) f
///     + 2 a_s <I4s - 1> exp(b_s <I4s - 1>^2) s (x) s + a_fs I8 exp(b_fs I8^2) (f (x) s + s (x) f) + K/2 (J^2 - 1) C^-1.
/// <x> = max(x, 0) by default: fibres and sheets bear no compression, as in Holzapfel & Ogden 2009
/// (sec. 5). With fibres_in_compression = true the terms act in compression too, as in Zhang et al.
/// 2021; that form loses ellipticity under fibre compression (the fibre stress makes the shear
/// stiffness along the fibre negative once a + 2 a_f (I4f - 1) < 0) and the solid then buckles
/// at the particle scale, so it is not the default.
/// The - a ln J term makes the reference stress free (SPHinXsys writes it as - a J C^-1, which
/// agrees to first order but derives from no energy).
template <int Dim>
struct HolzapfelOgden {
  Real a = 0, b = 1;        ///< isotropic term [stress], [-]
  Real a_f = 0, b_f = 1;    ///< fibre
  Real a_s = 0, b_s = 1;    ///< sheet
  Real a_fs = 0, b_fs = 1;  ///< fibre-sheet shear
  Real bulk_modulus = 0;    ///< K of the volumetric penalty [stress]
  bool fibres_in_compression = false;
  static constexpr bool anisotropic = true;

  /// I4 - 1, or its positive part when fibres bear no compression.
  Real fibre_strain(Real I4_minus_one) const {
    return fibres_in_compression ? I4_minus_one : std::max(I4_minus_one, Real(0));
  }

  Mat<Dim> second_piola(const Mat<Dim>& F, const Vec<Dim>& f, const Vec<Dim>& s) const {
    using namespace material_detail;
    const Mat<Dim> C = F.transpose() * F;
    const Mat<Dim> C_inverse = C.inverse();
    const Real J = F.determinant();
    const Real I4f = fibre_strain(f.dot(C * f) - 1), I4s = fibre_strain(s.dot(C * s) - 1), I8 = f.dot(C * s);
    Mat<Dim> S = a * std::exp(b * (C.trace() - Dim)) * Mat<Dim>::Identity() +
                 (volumetric_stress_factor(bulk_modulus, J) - a) * C_inverse;
    // A term with a zero coefficient is left out (not 0 x exp(...), which is NaN once exp overflows).
    if (a_f != 0) S += 2 * a_f * I4f * std::exp(b_f * I4f * I4f) * (f * f.transpose());
    if (a_s != 0) S += 2 * a_s * I4s * std::exp(b_s * I4s * I4s) * (s * s.transpose());
    if (a_fs != 0) S += a_fs * I8 * std::exp(b_fs * I8 * I8) * symmetric_dyad<Dim>(f, s);
    return S;
  }
  Real energy(const Mat<Dim>& F, const Vec<Dim>& f, const Vec<Dim>& s) const {
    const Mat<Dim> C = F.transpose() * F;
    const Real J = F.determinant();
    const Real I4f = fibre_strain(f.dot(C * f) - 1), I4s = fibre_strain(s.dot(C * s) - 1), I8 = f.dot(C * s);
    auto term = [](Real coefficient, Real exponent, Real argument) {
      return coefficient == 0 ? Real(0) : coefficient / (2 * exponent) * (std::exp(exponent * argument) - 1);
    };
    return term(a, b, C.trace() - Dim) - a * std::log(J) + term(a_f, b_f, I4f * I4f) + term(a_s, b_s, I4s * I4s) +
           term(a_fs, b_fs, I8 * I8) + material_detail::volumetric_energy(bulk_modulus, J);
  }
  /// Linearised at F = I: lambda = K + 2ab, mu = a, plus 4 a_f (or 4 a_s) along the fibre (sheet).
  Real wave_modulus() const { return bulk_modulus + 2 * a * b + 2 * a + 4 * std::max(a_f, a_s); }
  Real shear_modulus() const { return a; }
};

/// The Holzapfel & Ogden 2009 fit to the shear data of Dokos et al. 2002 (their Table 1), in kPa:
/// a = 0.059, b = 8.023, a_f = 18.472, b_f = 16.026, a_s = 2.481, b_s = 11.120, a_fs = 0.216, b_fs = 11.436.
template <int Dim>
HolzapfelOgden<Dim> holzapfel_ogden_2009_kpa(Real bulk_modulus) {
  HolzapfelOgden<Dim> law;
  law.a = Real(0.059), law.b = Real(8.023), law.a_f = Real(18.472), law.b_f = Real(16.026);
  law.a_s = Real(2.481), law.b_s = Real(11.120), law.a_fs = Real(0.216), law.b_fs = Real(11.436);
  law.bulk_modulus = bulk_modulus;
  return law;
}

/// The constants of the SPHinXsys heart case (Zhang et al. 2021, CMAME 381:113847), in kPa:
/// a = 0.496, b = 7.209, a_f = 15.196, b_f = 20.417, a_s = 3.283, b_s = 11.176, a_fs = 0.662, b_fs = 9.466.
template <int Dim>
HolzapfelOgden<Dim> holzapfel_ogden_zhang_2021_kpa(Real bulk_modulus) {
  HolzapfelOgden<Dim> law;
  law.a = Real(0.496), law.b = Real(7.209), law.a_f = Real(15.196), law.b_f = Real(20.417);
  law.a_s = Real(3.283), law.b_s = Real(11.176), law.a_fs = Real(0.662), law.b_fs = Real(9.466);
  law.bulk_modulus = bulk_modulus;
  return law;
}

/// Guccione, McCulloch & Waldman 1991 (J. Biomech. Eng. 113:42), transversely isotropic, with the
/// volumetric penalty U(J) for near incompressibility (as in Land et al. 2015, Proc. R. Soc. A 471):
///   W = C/2 (exp(Q) - 1) + U(J),
///   Q = b_f E_ff^2 + b_t (E_ss^2 + E_nn^2 + 2 E_sn^2) + 2 b_fs (E_fs^2 + E_fn^2),
/// with E_ab = a.E b in the fibre (f), sheet (s) and normal (n = f x s) directions;
///   S = C exp(Q) [b_f E_ff f f + b_t (E_ss s s + E_nn n n + E_sn (s n + n s)) + b_fs (E_fs (f s + s f) + E_fn (f n + n f))]
///     + K/2 (J^2 - 1) C^-1.
template <int Dim>
struct Guccione {
  Real C = 0;  ///< [stress]
  Real b_f = 1, b_t = 1, b_fs = 1;
  Real bulk_modulus = 0;
  static constexpr bool anisotropic = true;

  struct Strains {
    Real ff, ss, nn, fs, fn, sn;
  };
  static Strains fibre_strains(const Mat<Dim>& E, const Vec<Dim>& f, const Vec<Dim>& s, Vec<Dim>& n) {
    if constexpr (Dim == 3) n = f.cross(s);
    else n.setZero();  // plane strain: E_nn = E_fn = E_sn = 0
    return {f.dot(E * f), s.dot(E * s), n.dot(E * n), f.dot(E * s), f.dot(E * n), s.dot(E * n)};
  }
  Real exponent(const Strains& e) const {
    return b_f * e.ff * e.ff + b_t * (e.ss * e.ss + e.nn * e.nn + 2 * e.sn * e.sn) + 2 * b_fs * (e.fs * e.fs + e.fn * e.fn);
  }
  Mat<Dim> second_piola(const Mat<Dim>& F, const Vec<Dim>& f, const Vec<Dim>& s) const {
    using namespace material_detail;
    const Mat<Dim> right_cauchy = F.transpose() * F;
    const Mat<Dim> E = Real(0.5) * (right_cauchy - Mat<Dim>::Identity());
    Vec<Dim> n;
    const Strains e = fibre_strains(E, f, s, n);
    const Mat<Dim> directional = b_f * e.ff * (f * f.transpose()) +
                                 b_t * (e.ss * (s * s.transpose()) + e.nn * (n * n.transpose()) + e.sn * symmetric_dyad<Dim>(s, n)) +
                                 b_fs * (e.fs * symmetric_dyad<Dim>(f, s) + e.fn * symmetric_dyad<Dim>(f, n));
    return C * std::exp(exponent(e)) * directional +
           volumetric_stress_factor(bulk_modulus, F.determinant()) * right_cauchy.inverse();
  }
  Real energy(const Mat<Dim>& F, const Vec<Dim>& f, const Vec<Dim>& s) const {
    const Mat<Dim> E = Real(0.5) * (F.transpose() * F - Mat<Dim>::Identity());
    Vec<Dim> n;
    return C / 2 * (std::exp(exponent(fibre_strains(E, f, s, n))) - 1) +
           material_detail::volumetric_energy(bulk_modulus, F.determinant());
  }
  /// Linearised at F = I: S = C (b_f E_ff ff + ...) + K tr(E) I.
  Real wave_modulus() const { return bulk_modulus + C * std::max(b_f, b_t); }
  /// Smallest small-strain shear modulus: C b_t / 2 (sheet-normal plane) or C b_fs / 2 (fibre planes).
  Real shear_modulus() const { return C * std::min(b_t, b_fs) / 2; }
};

template <int Dim>
using MaterialLaw = std::variant<SaintVenantKirchhoff<Dim>, NeoHookean<Dim>, HolzapfelOgden<Dim>, Guccione<Dim>>;

/// First Piola-Kirchhoff stress P = F S.
template <int Dim, class Law>
Mat<Dim> first_piola(const Law& law, const Mat<Dim>& F, const Vec<Dim>& f, const Vec<Dim>& s) {
  return F * law.second_piola(F, f, s);
}

/// Cauchy stress sigma = J^-1 P F^T.
template <int Dim, class Law>
Mat<Dim> cauchy_stress(const Law& law, const Mat<Dim>& F, const Vec<Dim>& f, const Vec<Dim>& s) {
  return first_piola<Dim>(law, F, f, s) * F.transpose() / F.determinant();
}

/// Small-strain Young's modulus E = 9 K mu / (3 K + mu) of a law, with K = M - 4 mu / 3 from its
/// wave modulus M and shear modulus mu (scales the hourglass penalty force).
template <int Dim>
Real young_modulus_estimate(const MaterialLaw<Dim>& law) {
  return std::visit(
      [](const auto& m) {
        const Real mu = m.shear_modulus();
        const Real K = m.wave_modulus() - Real(4) / 3 * mu;
        return 9 * K * mu / (3 * K + mu);
      },
      law);
}

/// Lame constants from Young's modulus and Poisson's ratio (3D relations; in 2D they give plane strain).
inline void lame_constants(Real young_modulus, Real poisson_ratio, Real& lambda, Real& mu) {
  if (!(young_modulus > 0) || !(poisson_ratio > -1 && poisson_ratio < Real(0.5)))
    throw std::invalid_argument("material: need E > 0 and -1 < nu < 0.5");
  mu = young_modulus / (2 * (1 + poisson_ratio));
  lambda = young_modulus * poisson_ratio / ((1 + poisson_ratio) * (1 - 2 * poisson_ratio));
}

/// Bulk modulus K = E / (3 (1 - 2 nu)).
inline Real bulk_modulus_of(Real young_modulus, Real poisson_ratio) {
  return young_modulus / (3 * (1 - 2 * poisson_ratio));
}

/// Checks the constants of a law; throws std::invalid_argument naming the constant.
template <int Dim>
void check_material(const MaterialLaw<Dim>& law) {
  auto require = [](bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(std::string("material: ") + what);
  };
  std::visit(
      [&](const auto& m) {
        using Law = std::decay_t<decltype(m)>;
        if constexpr (std::is_same_v<Law, SaintVenantKirchhoff<Dim>> || std::is_same_v<Law, NeoHookean<Dim>>) {
          require(m.mu > 0, "shear modulus mu must be positive");
          require(m.lambda + 2 * m.mu / Dim > 0, "bulk modulus lambda + 2 mu / d must be positive");
        } else if constexpr (std::is_same_v<Law, HolzapfelOgden<Dim>>) {
          require(m.a > 0 && m.a_f >= 0 && m.a_s >= 0 && m.a_fs >= 0, "Holzapfel-Ogden a > 0 and a_f, a_s, a_fs >= 0");
          require(m.b > 0 && m.b_f > 0 && m.b_s > 0 && m.b_fs > 0, "Holzapfel-Ogden exponents b must be positive");
          require(m.bulk_modulus > 0, "bulk modulus must be positive");
        } else {
          require(m.C > 0 && m.b_f > 0 && m.b_t > 0 && m.b_fs > 0, "Guccione C and b_f, b_t, b_fs must be positive");
          require(m.bulk_modulus > 0, "bulk modulus must be positive");
        }
      },
      law);
}

}  // namespace sph
