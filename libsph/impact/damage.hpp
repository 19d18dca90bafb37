#pragma once
// Brittle fracture of the impact family: the Grady-Kipp scalar damage D in [0, 1] (0 intact, 1
// fully fractured) grown from explicit Weibull flaws, the fracture area and fragment sizes it
// implies, and the fragments of a body found as connected clusters of intact particles.
//
// Sources: Grady & Kipp 1980 (Int. J. Rock Mech. Min. Sci. 17:147), the damage growth and the
// Weibull flaw law; Benz & Asphaug 1994 (Icarus 107:98) and 1995 (Comput. Phys. Commun. 87:253),
// its SPH form with flaws assigned to particles; Melosh, Ryan & Asphaug 1992 (J. Geophys. Res.
// 97:14735), the fracture area and fragment size distribution; the equations as collected in the
// impact SPH theory notes (impact_sph_theory.rst, "Damage and Fragmentation").
//
// Weibull law: n(eps) = k eps^m flaws per unit volume activate at tensile strains below eps (in 2D
// a "volume" is an area and k is per unit area; the published 3D sets do not carry over).
//
// Flaws (Benz & Asphaug 1995): flaws j = 1, 2, 3, ... are drawn in turn, each placed on
// a particle chosen uniformly at random, with activation strain
//   eps_j = (j / (k V))^(1/m),   V the volume of the whole body,
// so that the body holds exactly floor(k V eps^m) flaws below eps, until every particle holds at
// least one flaw. A particle's thresholds come out in increasing order. The choice is uniform over
// particles, as in Benz & Asphaug, which assumes particles of (nearly) equal volume: the particle
// volumes only enter through V.
//
// Damage growth, for particle i with the largest principal stress sigma_1 (tension positive):
//   eps_i = sigma_1 / ((1 - D_i) E),                        E Young's modulus
//   n_act = number of flaws of i with eps_j <= eps_i         (none if eps_i <= 0)
//   d D_i^(1/3) / dt = n_act c_g / R_s,  c_g = 0.4 c_s      (crack speed, c_s the sound speed)
// with D^(1/3) capped at (n_act / n_i)^(1/3), n_i the flaws of i (Benz & Asphaug 1995:
// a particle is fully damaged only when all its flaws are active), and at 1. R_s is the radius of
// the particle's crack-growth volume, a choice left to the caller: equivalent_radius below gives the
// radius of the sphere (disc in 2D) of the particle's volume, (3V / 4pi)^(1/3); the smoothing
// length h is the other common choice (in 3D at h = 1.2 dx it is 1.9 times the equivalent radius
// of dx^3, so damage grows 1.9 times slower).
//
// Damaged stress (Benz & Asphaug 1994), pressure positive in compression:
//   p' = p if p > 0, (1 - D) p otherwise;   s' = (1 - D) s   (s the deviatoric stress)
//
// Fracture area per unit volume A and fragment sizes (Grady & Kipp 1980; Melosh et al. 1992):
//   dA/dt = (m+2)(m+3) / (2 c_g) (8 pi c_g^3 k / ((m+1)(m+2)(m+3)))^(2/3) eps^(2m/3) D^(1/3)
//   L_m   = 3 (m+3) / ((m+2) A)          (most frequent fragment size)
//   L_max = (m+2) / 3 L_m = (m+3) / A    (largest fragment size)
//   F_cum(L) = (m+6)(m+5)(m+4)/120 V / L_max^3 (1 - x)^m [1 + m x + m(m+1)/2 x^2 + m(m+1)(m+2)/6 x^3],
//              x = L / L_max, the number of fragments of size >= L in a particle of volume V
//              (0 for L >= L_max).
//
// Fragments: particles with D < threshold are intact; two neighbours (an InnerRelation pair) that
// are both intact belong to the same fragment (union-find). A particle with D >= threshold is a
// fragment of its own (dust at the resolution of the particles), counted with its mass among the
// fragments (a one-particle fragment is dust or an isolated intact particle; the damage tells them
// apart). Fragments are labelled by their smallest particle
// index, independent of the thread count and of the order of the pairs.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "libsph/core/neighbour_relation.hpp"
#include "libsph/core/types.hpp"

namespace sph {

/// n(eps) = k eps^m flaws per unit volume with activation strain below eps.
struct WeibullParameters {
  double k = 0;  ///< [1 / volume]
  double m = 0;  ///< dimensionless
  /// Throws std::invalid_argument naming k or m unless both are finite and > 0.
  void check() const;
};

/// A published set with its source.
struct WeibullMaterial {
  std::string name, source;
  WeibullParameters parameters;
};

/// Basalt and ice of Benz & Asphaug 1999 (Icarus 142:5, table II), converted to SI (k in m^-3).
const std::vector<WeibullMaterial>& weibull_materials();
/// The named set; std::invalid_argument listing the names if there is none.
const WeibullMaterial& weibull_material(const std::string& name);

/// The flaws of every particle in compressed-row form.
struct WeibullFlaws {
  std::vector<std::size_t> offsets;  ///< row i is [offsets[i], offsets[i+1])
  std::vector<Real> threshold;       ///< activation strains, increasing within each row
  std::vector<Index> count;          ///< flaws of each particle (offsets[i+1] - offsets[i], >= 1)
  std::size_t total_flaws = 0;       ///< over the body (= threshold.size())

  std::size_t n_particles() const { return count.size(); }
  std::span<const Real> thresholds(std::size_t i) const {
    return {threshold.data() + offsets[i], threshold.data() + offsets[i + 1]};
  }
  /// Flaws of particle i with threshold <= strain (0 for strain <= 0).
  std::size_t active(std::size_t i, Real strain) const;
};

/// Assigns Weibull flaws to the particles (Benz & Asphaug 1995), serially with std::mt19937_64
/// seeded by `seed`, so the flaws depend on the seed only (not on the thread count or platform:
/// the particle is drawn from the raw 64-bit output by rejection, not by a library distribution).
/// Stops once every particle holds a flaw; throws std::runtime_error if that takes more than
/// 64 n ln n + 1000 draws (n particles; the coupon collector needs about n ln n, so this never
/// happens short of a broken generator). Throws std::invalid_argument for bad parameters, an empty
/// volume list or a volume that is not finite and > 0.
///
/// With k so small that eps_1 = (1 / (k V))^(1/m) exceeds any physical strain, the flaws are still
/// assigned (every particle gets its thresholds, possibly +inf) and the material never fractures.
WeibullFlaws assign_weibull_flaws(std::span<const Real> particle_volume, WeibullParameters parameters,
                                  std::uint64_t seed);

/// Crack growth speed over sound speed, c_g = 0.4 c_s (Benz & Asphaug 1994, after Grady & Kipp).
inline constexpr Real crack_speed_fraction = Real(0.4);

/// The radius of the sphere (3D) or disc (2D) of the given volume: (3V / 4pi)^(1/3), (V / pi)^(1/2).
template <int Dim>
Real equivalent_radius(Real volume);

/// Largest eigenvalue of a symmetric stress tensor (Eigen::SelfAdjointEigenSolver in 3D, the
/// closed form (a + c) / 2 + hypot((a - c) / 2, b) in 2D).
template <int Dim>
Real largest_principal_stress(const Mat<Dim>& stress);

/// The damage rate d D^(1/3) / dt of every particle (see the header comment), written into
/// `cube_root_rate`; if `cube_root_cap` is not empty, the cap (n_act / n_i)^(1/3) of D^(1/3) is
/// written into it. The rate is 0 in compression, below the first threshold, for D >= 1 and once
/// D^(1/3) has reached its cap. `stress` is the full Cauchy stress -p I + s (tension positive),
/// `sound_speed` c_s and `radius` R_s per particle. Runs with parallel_for (each particle writes
/// only its own entries, so the result is the same for any thread count). Throws
/// std::invalid_argument for spans of the wrong length or E not > 0.
template <int Dim>
void grady_kipp_damage_rate(const WeibullFlaws& flaws, std::span<const Mat<Dim>> stress,
                            std::span<const Real> damage, Real youngs_modulus, std::span<const Real> sound_speed,
                            std::span<const Real> radius, std::span<Real> cube_root_rate,
                            std::span<Real> cube_root_cap = {});

/// One explicit step of the damage: D^(1/3) <- min(D^(1/3) + rate dt, cap, 1), D never decreasing.
/// `cube_root_cap` may be empty (then only the cap 1 applies).
void advance_damage(std::span<Real> damage, std::span<const Real> cube_root_rate,
                    std::span<const Real> cube_root_cap, Real dt);

/// p' = p if p > 0, (1 - D) p otherwise (Benz & Asphaug 1994): damage removes tensile strength only.
inline Real damaged_pressure(Real pressure, Real damage) { return pressure > 0 ? pressure : (1 - damage) * pressure; }
/// s' = (1 - D) s (Benz & Asphaug 1994).
template <int Dim>
Mat<Dim> damaged_deviatoric_stress(const Mat<Dim>& deviatoric, Real damage) {
  return (1 - damage) * deviatoric;
}
/// Both rules applied in place to every particle (parallel_for).
template <int Dim>
void apply_damage_to_stress(std::span<Real> pressure, std::span<Mat<Dim>> deviatoric, std::span<const Real> damage);

/// dA/dt, the growth of the fracture area per unit volume (Grady & Kipp 1980; Melosh et al. 1992):
/// (m+2)(m+3) / (2 c_g) (8 pi c_g^3 k / ((m+1)(m+2)(m+3)))^(2/3) eps^(2m/3) D^(1/3); 0 for eps <= 0.
double fracture_area_rate(const WeibullParameters& weibull, double crack_speed, double strain, double damage);
/// L_m = 3 (m+3) / ((m+2) A), the most frequent fragment size for fracture area per volume A > 0.
double most_frequent_fragment_size(const WeibullParameters& weibull, double fracture_area);
/// L_max = (m+2) / 3 L_m, the largest fragment size.
double largest_fragment_size(const WeibullParameters& weibull, double most_frequent_size);
/// F_cum(L), the number of fragments of size >= L in a particle of volume V (Melosh et al. 1992, as
/// in the header comment); 0 for L >= L_max. Throws std::invalid_argument for L < 0 or L_max, V <= 0.
double cumulative_fragment_number(const WeibullParameters& weibull, double size, double largest_size,
                                  double volume);

/// The fragments of a body, largest first.
struct FragmentStatistics {
  struct Fragment {
    Index label = 0;              ///< its smallest particle index
    Real mass = 0;
    std::size_t particles = 0;
  };
  std::vector<Index> label;          ///< per particle: the label of its fragment
  std::vector<Fragment> fragments;   ///< by mass descending, equal masses by label ascending
  Real total_mass = 0;
  Real largest_mass_fraction = 0;    ///< fragments[0].mass / total_mass (0 for an empty body)

  std::size_t n_fragments() const { return fragments.size(); }
  /// Fragment masses, descending.
  std::vector<Real> masses() const;
  /// Number of fragments with mass >= m.
  std::size_t cumulative_number(Real m) const;
};

/// Fragments as connected clusters of intact (D < threshold) neighbours, union-find over the pairs
/// of `relation` (offsets and neighbour only). Throws std::invalid_argument for spans whose length
/// is not the relation's target count or a threshold outside (0, 1].
template <int Dim>
FragmentStatistics find_fragments(const InnerRelation<Dim>& relation, std::span<const Real> mass,
                                  std::span<const Real> damage, Real threshold);

/// "mass,cumulative_number" rows, one per distinct fragment mass, descending: the number of
/// fragments with mass >= that mass (a CSV text for the caller to write).
std::string cumulative_mass_distribution_csv(const FragmentStatistics& statistics);

extern template Real equivalent_radius<2>(Real);
extern template Real equivalent_radius<3>(Real);
extern template Real largest_principal_stress<2>(const Mat<2>&);
extern template Real largest_principal_stress<3>(const Mat<3>&);
extern template void grady_kipp_damage_rate<2>(const WeibullFlaws&, std::span<const Mat<2>>, std::span<const Real>, Real,
                                               std::span<const Real>, std::span<const Real>, std::span<Real>,
                                               std::span<Real>);
extern template void grady_kipp_damage_rate<3>(const WeibullFlaws&, std::span<const Mat<3>>, std::span<const Real>, Real,
                                               std::span<const Real>, std::span<const Real>, std::span<Real>,
                                               std::span<Real>);
extern template void apply_damage_to_stress<2>(std::span<Real>, std::span<Mat<2>>, std::span<const Real>);
extern template void apply_damage_to_stress<3>(std::span<Real>, std::span<Mat<3>>, std::span<const Real>);
extern template FragmentStatistics find_fragments<2>(const InnerRelation<2>&, std::span<const Real>,
                                                     std::span<const Real>, Real);
extern template FragmentStatistics find_fragments<3>(const InnerRelation<3>&, std::span<const Real>,
                                                     std::span<const Real>, Real);

}  // namespace sph
