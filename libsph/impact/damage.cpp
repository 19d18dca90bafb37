#include "libsph/impact/damage.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>

#include "libsph/core/parallel.hpp"
#include "libsph/core/union_find.hpp"

namespace sph {

namespace {

std::string number(double x) {
  std::ostringstream out;
  out << std::setprecision(6) << x;
  return out.str();
}

}  // namespace

void WeibullParameters::check() const {
  auto fail = [](const std::string& what) { throw std::invalid_argument("Weibull parameters: " + what); };
  if (!(k > 0) || !std::isfinite(k)) fail("k = " + number(k) + " (flaws per unit volume) must be finite and > 0");
  if (!(m > 0) || !std::isfinite(m)) fail("m = " + number(m) + " (the Weibull exponent) must be finite and > 0");
}

const std::vector<WeibullMaterial>& weibull_materials() {
  // Benz & Asphaug 1999, Icarus 142:5, table II, give k in cm^-3 (basalt 4e29, ice 1.4e32); x 1e6
  // for m^-3. Cross-checked against the SI collection of miluphcuda (material-config/material_data,
  // basalt.fragmentation.cfg and ice.fragmentation.cfg), not against the paper itself.
  static const std::vector<WeibullMaterial> materials{
      {"basalt", "Benz & Asphaug 1999, Icarus 142:5, table II (k 4e29 cm^-3)", {4.0e35, 9.0}},
      {"ice", "Benz & Asphaug 1999, Icarus 142:5, table II (k 1.4e32 cm^-3)", {1.4e38, 9.6}},
  };
  return materials;
}

const WeibullMaterial& weibull_material(const std::string& name) {
  std::string names;
  for (const auto& m : weibull_materials()) {
    if (m.name == name) return m;
    names += (names.empty() ? "" : ", ") + m.name;
  }
  throw std::invalid_argument("unknown Weibull material '" + name + "' (known: " + names + ")");
}

std::size_t WeibullFlaws::active(std::size_t i, Real strain) const {
  if (!(strain > 0)) return 0;
  const auto row = thresholds(i);
  // Thresholds increase along the row: the active ones are a prefix.
  return static_cast<std::size_t>(std::upper_bound(row.begin(), row.end(), strain) - row.begin());
}

namespace {

// A uniform integer in [0, n) from the raw 64-bit output, by rejection of the incomplete last
// block (exactly uniform, and the same on every standard library, unlike std::uniform_int_distribution).
std::uint64_t uniform_below(std::mt19937_64& generator, std::uint64_t n) {
  const std::uint64_t limit = std::numeric_limits<std::uint64_t>::max() - std::numeric_limits<std::uint64_t>::max() % n;
  std::uint64_t r;
  do r = generator();
  while (r >= limit);
  return r % n;
}

}  // namespace

WeibullFlaws assign_weibull_flaws(std::span<const Real> particle_volume, WeibullParameters parameters,
                                  std::uint64_t seed) {
  parameters.check();
  const std::size_t n = particle_volume.size();
  if (n == 0) throw std::invalid_argument("assign_weibull_flaws: the particle volume list is empty");
  if (n > std::numeric_limits<Index>::max())
    throw std::invalid_argument("assign_weibull_flaws: " + std::to_string(n) + " particles exceed the Index range");
  double total_volume = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double v = particle_volume[i];
    if (!(v > 0) || !std::isfinite(v))
      throw std::invalid_argument("assign_weibull_flaws: particle volume " + std::to_string(i) + " = " + number(v) +
                                  " must be finite and > 0");
    total_volume += v;
  }
  const double kV = parameters.k * total_volume;
  if (!std::isfinite(total_volume) || !std::isfinite(kV))
    throw std::invalid_argument("assign_weibull_flaws: k V = " + number(kV) + " (k = " + number(parameters.k) +
                                ", total volume V = " + number(total_volume) + ") is not finite");

  // Draw flaw j = 1, 2, ... onto a uniformly chosen particle until none is left without one.
  const double nd = static_cast<double>(n);
  const auto max_flaws = static_cast<std::size_t>(std::ceil(64 * nd * std::log(nd) + 1000));
  std::mt19937_64 generator(seed);
  std::vector<Index> owner;
  owner.reserve(static_cast<std::size_t>(nd * (std::log(nd) + 1) + 16));
  std::vector<Index> count(n, 0);
  std::size_t uncovered = n;
  while (uncovered > 0) {
    if (owner.size() >= max_flaws)
      throw std::runtime_error("assign_weibull_flaws: " + std::to_string(uncovered) + " of " + std::to_string(n) +
                               " particles still hold no flaw after " + std::to_string(max_flaws) +
                               " flaws (64 n ln n + 1000); the random generator cannot be right");
    const auto i = static_cast<Index>(uniform_below(generator, n));
    if (count[i]++ == 0) --uncovered;
    owner.push_back(i);
  }

  // Compressed rows by a counting sort on the owner; flaws stay in order of j, so every row
  // increases. eps_j = (j / (k V))^(1/m), +inf if j / (k V) overflows (a set with no flaws at any
  // physical strain).
  WeibullFlaws flaws;
  flaws.total_flaws = owner.size();
  flaws.offsets.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) flaws.offsets[i + 1] = flaws.offsets[i] + count[i];
  flaws.threshold.resize(owner.size());
  std::vector<std::size_t> next(flaws.offsets.begin(), flaws.offsets.end() - 1);
  const double inverse_m = 1 / parameters.m;
  for (std::size_t j = 0; j < owner.size(); ++j)
    flaws.threshold[next[owner[j]]++] = static_cast<Real>(std::pow(static_cast<double>(j + 1) / kV, inverse_m));
  flaws.count = std::move(count);
  return flaws;
}

template <int Dim>
Real equivalent_radius(Real volume) {
  if constexpr (Dim == 3) return std::cbrt(3 * volume / (4 * pi));
  else if constexpr (Dim == 2) return std::sqrt(volume / pi);
  else return volume / 2;
}

template <int Dim>
Real largest_principal_stress(const Mat<Dim>& stress) {
  if constexpr (Dim == 2) {
    // In 2D the closed form (a + c) / 2 + hypot((a - c) / 2, b) of the symmetric part, exact to
    // rounding and free of the iterative solver (whose 2 x 2 instantiation trips GCC's
    // -Wmaybe-uninitialized inside Eigen).
    const Real a = stress(0, 0), c = stress(1, 1), b = Real(0.5) * (stress(0, 1) + stress(1, 0));
    return Real(0.5) * (a + c) + std::hypot(Real(0.5) * (a - c), b);
  } else {
    // Eigenvalues of a self-adjoint matrix come in increasing order (the lower triangle is read).
    const Eigen::SelfAdjointEigenSolver<Mat<Dim>> solver(stress, Eigen::EigenvaluesOnly);
    return solver.eigenvalues()[Dim - 1];
  }
}

template <int Dim>
void grady_kipp_damage_rate(const WeibullFlaws& flaws, std::span<const Mat<Dim>> stress,
                            std::span<const Real> damage, Real youngs_modulus, std::span<const Real> sound_speed,
                            std::span<const Real> radius, std::span<Real> cube_root_rate,
                            std::span<Real> cube_root_cap) {
  const std::size_t n = flaws.n_particles();
  auto check_length = [n](std::size_t size, const char* name) {
    if (size != n)
      throw std::invalid_argument(std::string("grady_kipp_damage_rate: ") + name + " has " + std::to_string(size) +
                                  " entries for " + std::to_string(n) + " particles with flaws");
  };
  check_length(stress.size(), "stress");
  check_length(damage.size(), "damage");
  check_length(sound_speed.size(), "sound_speed");
  check_length(radius.size(), "radius");
  check_length(cube_root_rate.size(), "cube_root_rate");
  if (!cube_root_cap.empty()) check_length(cube_root_cap.size(), "cube_root_cap");
  if (!(youngs_modulus > 0) || !std::isfinite(youngs_modulus))
    throw std::invalid_argument("grady_kipp_damage_rate: Young's modulus E = " + number(youngs_modulus) +
                                " must be finite and > 0");
  parallel_for(n, [&](std::size_t i) {
    const Real d = damage[i];
    std::size_t n_active = 0;
    if (d < 1) {
      const Real strain = largest_principal_stress<Dim>(stress[i]) / ((1 - d) * youngs_modulus);
      n_active = flaws.active(i, strain);
    } else {
      n_active = flaws.count[i];  // fully damaged: nothing left to grow, the cap is 1
    }
    const Real cap = n_active == 0 ? Real(0)
                                   : std::cbrt(static_cast<Real>(n_active) / static_cast<Real>(flaws.count[i]));
    // At the cap up to the rounding of cap^3 and its cube root (advance_damage stores D, not D^(1/3)).
    const bool capped =
        d >= 1 || std::cbrt(std::max(d, Real(0))) >= cap * (1 - 8 * std::numeric_limits<Real>::epsilon());
    cube_root_rate[i] =
        capped ? Real(0) : static_cast<Real>(n_active) * crack_speed_fraction * sound_speed[i] / radius[i];
    if (!cube_root_cap.empty()) cube_root_cap[i] = cap;
  });
}

void advance_damage(std::span<Real> damage, std::span<const Real> cube_root_rate,
                    std::span<const Real> cube_root_cap, Real dt) {
  if (cube_root_rate.size() != damage.size() || (!cube_root_cap.empty() && cube_root_cap.size() != damage.size()))
    throw std::invalid_argument("advance_damage: cube_root_rate (" + std::to_string(cube_root_rate.size()) +
                                ") and cube_root_cap (" + std::to_string(cube_root_cap.size()) +
                                ", or empty) must have one entry per damage value (" + std::to_string(damage.size()) + ")");
  parallel_for(damage.size(), [&](std::size_t i) {
    const Real s = std::cbrt(std::max(damage[i], Real(0)));
    Real next = s + cube_root_rate[i] * dt;
    if (!cube_root_cap.empty()) next = std::min(next, cube_root_cap[i]);
    next = std::min(next, Real(1));
    if (next > s) damage[i] = next >= 1 ? Real(1) : next * next * next;  // damage never heals
  });
}

template <int Dim>
void apply_damage_to_stress(std::span<Real> pressure, std::span<Mat<Dim>> deviatoric, std::span<const Real> damage) {
  if (pressure.size() != damage.size() || deviatoric.size() != damage.size())
    throw std::invalid_argument("apply_damage_to_stress: pressure (" + std::to_string(pressure.size()) +
                                ") and deviatoric (" + std::to_string(deviatoric.size()) +
                                ") must have one entry per damage value (" + std::to_string(damage.size()) + ")");
  parallel_for(damage.size(), [&](std::size_t i) {
    pressure[i] = damaged_pressure(pressure[i], damage[i]);
    deviatoric[i] = damaged_deviatoric_stress<Dim>(deviatoric[i], damage[i]);
  });
}

// Grady & Kipp 1980; Melosh, Ryan & Asphaug 1992 (J. Geophys. Res. 97:14735):
//   dA/dt = (m+2)(m+3) / (2 c_g) (8 pi c_g^3 k / ((m+1)(m+2)(m+3)))^(2/3) eps^(2m/3) D^(1/3)
double fracture_area_rate(const WeibullParameters& weibull, double crack_speed, double strain, double damage) {
  weibull.check();
  if (!(crack_speed > 0))
    throw std::invalid_argument("fracture_area_rate: the crack speed c_g = " + number(crack_speed) + " must be > 0");
  if (!(strain > 0) || !(damage > 0)) return 0;
  const double m = weibull.m, k = weibull.k;
  const double pi_double = 3.14159265358979323846;  // the formulas of this group are in double whatever Real is
  const double g = 8 * pi_double * crack_speed * crack_speed * crack_speed * k / ((m + 1) * (m + 2) * (m + 3));
  return (m + 2) * (m + 3) / (2 * crack_speed) * std::pow(g, 2.0 / 3) * std::pow(strain, 2 * m / 3) *
         std::cbrt(std::min(damage, 1.0));
}

// L_m = 3 (m+3) / ((m+2) A) (Melosh et al. 1992).
double most_frequent_fragment_size(const WeibullParameters& weibull, double fracture_area) {
  weibull.check();
  if (!(fracture_area > 0))
    throw std::invalid_argument("most_frequent_fragment_size: the fracture area A = " + number(fracture_area) +
                                " must be > 0");
  return 3 * (weibull.m + 3) / ((weibull.m + 2) * fracture_area);
}

// L_max = (m+2) / 3 L_m (Melosh et al. 1992).
double largest_fragment_size(const WeibullParameters& weibull, double most_frequent_size) {
  weibull.check();
  return (weibull.m + 2) / 3 * most_frequent_size;
}

// F_cum(L) = (m+6)(m+5)(m+4)/120 V / L_max^3 (1 - x)^m [1 + m x + m(m+1)/2 x^2 + m(m+1)(m+2)/6 x^3],
// x = L / L_max (Melosh et al. 1992, after Grady & Kipp 1980). The bracket times (1 - x)^m is the
// regularised incomplete beta function I_{1-x}(m, 4), which falls from 1 at x = 0 to 0 at x = 1.
double cumulative_fragment_number(const WeibullParameters& weibull, double size, double largest_size,
                                  double volume) {
  weibull.check();
  if (!(size >= 0)) throw std::invalid_argument("cumulative_fragment_number: the size L = " + number(size) + " must be >= 0");
  if (!(largest_size > 0))
    throw std::invalid_argument("cumulative_fragment_number: L_max = " + number(largest_size) + " must be > 0");
  if (!(volume > 0)) throw std::invalid_argument("cumulative_fragment_number: the volume V = " + number(volume) + " must be > 0");
  if (size >= largest_size) return 0;
  const double m = weibull.m, x = size / largest_size;
  const double bracket = 1 + x * (m + x * (m * (m + 1) / 2 + x * m * (m + 1) * (m + 2) / 6));
  return (m + 6) * (m + 5) * (m + 4) / 120 * volume / (largest_size * largest_size * largest_size) *
         std::pow(1 - x, m) * bracket;
}

std::vector<Real> FragmentStatistics::masses() const {
  std::vector<Real> out(fragments.size());
  for (std::size_t f = 0; f < fragments.size(); ++f) out[f] = fragments[f].mass;
  return out;
}

std::size_t FragmentStatistics::cumulative_number(Real m) const {
  // Descending masses: the fragments with mass >= m are a prefix.
  const auto end = std::partition_point(fragments.begin(), fragments.end(), [m](const Fragment& f) { return f.mass >= m; });
  return static_cast<std::size_t>(end - fragments.begin());
}

template <int Dim>
FragmentStatistics find_fragments(const InnerRelation<Dim>& relation, std::span<const Real> mass,
                                  std::span<const Real> damage, Real threshold) {
  const std::size_t n = relation.n_targets();
  if (mass.size() != n || damage.size() != n)
    throw std::invalid_argument("find_fragments: mass (" + std::to_string(mass.size()) + ") and damage (" +
                                std::to_string(damage.size()) + ") must have one entry per particle of the relation (" +
                                std::to_string(n) + ")");
  if (!(threshold > 0) || !(threshold <= 1))
    throw std::invalid_argument("find_fragments: the damage threshold " + number(threshold) + " must be in (0, 1]");
  UnionFind sets(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (!(damage[i] < threshold)) continue;
    for (const auto [p, j] : relation.row(i)) {
      if (j >= n)
        throw std::invalid_argument("find_fragments: neighbour " + std::to_string(j) + " of particle " +
                                    std::to_string(i) + " is not a particle of the relation (" + std::to_string(n) + ")");
      if (damage[j] < threshold) sets.unite(i, j);
    }
  }
  FragmentStatistics out;
  out.label.resize(n);
  const std::vector<std::size_t> smallest = sets.smallest_member_labels();
  std::vector<std::size_t> fragment_of(n, n);  // by label
  for (std::size_t i = 0; i < n; ++i) {
    const Index label = static_cast<Index>(smallest[i]);
    out.label[i] = label;
    if (fragment_of[label] == n) {  // a label is its fragment's smallest index, met first in index order
      fragment_of[label] = out.fragments.size();
      out.fragments.push_back({label, 0, 0});
    }
    auto& f = out.fragments[fragment_of[label]];
    f.mass += mass[i];
    ++f.particles;
    out.total_mass += mass[i];
  }
  // The fragments are in label order here; a stable sort keeps it among equal masses.
  std::stable_sort(out.fragments.begin(), out.fragments.end(),
                   [](const FragmentStatistics::Fragment& a, const FragmentStatistics::Fragment& b) { return a.mass > b.mass; });
  out.largest_mass_fraction = out.fragments.empty() || !(out.total_mass > 0) ? Real(0) : out.fragments[0].mass / out.total_mass;
  return out;
}

std::string cumulative_mass_distribution_csv(const FragmentStatistics& statistics) {
  std::ostringstream out;
  out << "mass,cumulative_number\n" << std::setprecision(17);
  const auto& f = statistics.fragments;
  for (std::size_t a = 0; a < f.size(); ++a)
    if (a + 1 == f.size() || f[a + 1].mass != f[a].mass) out << f[a].mass << ',' << a + 1 << '\n';
  return out.str();
}

template Real equivalent_radius<2>(Real);
template Real equivalent_radius<3>(Real);
template Real largest_principal_stress<2>(const Mat<2>&);
template Real largest_principal_stress<3>(const Mat<3>&);
template void grady_kipp_damage_rate<2>(const WeibullFlaws&, std::span<const Mat<2>>, std::span<const Real>, Real,
                                        std::span<const Real>, std::span<const Real>, std::span<Real>, std::span<Real>);
template void grady_kipp_damage_rate<3>(const WeibullFlaws&, std::span<const Mat<3>>, std::span<const Real>, Real,
                                        std::span<const Real>, std::span<const Real>, std::span<Real>, std::span<Real>);
template void apply_damage_to_stress<2>(std::span<Real>, std::span<Mat<2>>, std::span<const Real>);
template void apply_damage_to_stress<3>(std::span<Real>, std::span<Mat<3>>, std::span<const Real>);
template FragmentStatistics find_fragments<2>(const InnerRelation<2>&, std::span<const Real>, std::span<const Real>, Real);
template FragmentStatistics find_fragments<3>(const InnerRelation<3>&, std::span<const Real>, std::span<const Real>, Real);

}  // namespace sph
