// Grady-Kipp damage with Weibull flaws (libsph/impact/damage.hpp): the flaw counts against the
// Weibull law, the damage ODE against its closed-form solution, the caps and the stress rule, the
// fracture area and fragment size formulas against values worked by hand, and the fragments of a
// body as connected clusters of intact particles.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "libsph/core/parallel.hpp"
#include "libsph/impact/damage.hpp"
#include "tests/precision.hpp"

namespace {

using sph::Index;
using sph::Mat;
using sph::Real;

// A relation filled by hand from adjacency lists (only offsets and neighbour are read).
template <int Dim>
sph::InnerRelation<Dim> relation_from(const std::vector<std::vector<Index>>& adjacency) {
  sph::InnerRelation<Dim> r;
  r.offsets.assign(1, 0);
  for (const auto& row : adjacency) {
    r.neighbour.insert(r.neighbour.end(), row.begin(), row.end());
    r.offsets.push_back(r.neighbour.size());
  }
  return r;
}

// Symmetric adjacency lists of an undirected edge list.
std::vector<std::vector<Index>> adjacency_of(std::size_t n, const std::vector<std::pair<Index, Index>>& edges) {
  std::vector<std::vector<Index>> a(n);
  for (const auto& [i, j] : edges) {
    a[i].push_back(j);
    a[j].push_back(i);
  }
  return a;
}

template <class F>
std::string message_of(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no std::invalid_argument)";
}

sph::WeibullParameters basalt() { return sph::weibull_material("basalt").parameters; }

TEST(GradyKipp, PublishedSetsAreValid) {
  for (const auto& material : sph::weibull_materials()) {
    EXPECT_NO_THROW(material.parameters.check()) << material.name;
    std::printf("[ measured ] %s: k = %.3g m^-3, m = %.2f (%s)\n", material.name.c_str(), material.parameters.k,
                material.parameters.m, material.source.c_str());
  }
  EXPECT_NE(message_of([] { sph::weibull_material("cheese"); }).find("basalt, ice"), std::string::npos);
}

TEST(GradyKipp, FlawCountsFollowTheWeibullLaw) {
  const std::size_t n = 20000;
  const std::vector<Real> volume(n, Real(1e-6));
  const double V = 1e-6 * n;
  const auto w = basalt();
  const auto flaws = sph::assign_weibull_flaws(volume, w, 12345);

  // Every particle holds a flaw, rows increase, the counts add up.
  ASSERT_EQ(flaws.n_particles(), n);
  ASSERT_EQ(flaws.offsets.size(), n + 1);
  EXPECT_EQ(flaws.total_flaws, flaws.threshold.size());
  EXPECT_EQ(flaws.offsets.back(), flaws.total_flaws);
  std::size_t sum = 0;
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_GE(flaws.count[i], 1u) << "particle " << i;
    ASSERT_EQ(flaws.count[i], flaws.offsets[i + 1] - flaws.offsets[i]);
    const auto row = flaws.thresholds(i);
    ASSERT_TRUE(std::is_sorted(row.begin(), row.end())) << "particle " << i;
    sum += flaws.count[i];
  }
  EXPECT_EQ(sum, flaws.total_flaws);
  // Coupon collector: the total is n H_n on average with standard deviation about pi n / sqrt(6);
  // bound 5 standard deviations.
  double harmonic = 0;
  for (std::size_t i = 1; i <= n; ++i) harmonic += 1.0 / double(i);
  const double mean_total = double(n) * harmonic, sd_total = sph::pi * double(n) / std::sqrt(6.0);
  std::printf("[ measured ] total flaws %zu (n H_n = %.0f, sd %.0f)\n", flaws.total_flaws, mean_total, sd_total);
  EXPECT_LT(std::abs(double(flaws.total_flaws) - mean_total), 5 * sd_total);

  for (const double expected : {100.0, 1000.0, 10000.0}) {
    const double eps = std::pow(expected / (w.k * V), 1 / w.m);
    std::size_t whole = 0, even = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t a = flaws.active(i, Real(eps));
      whole += a;
      if (i % 2 == 0) even += a;
    }
    // Over the whole body the count below eps is floor(k V eps^m) by construction (bound: 1, the
    // rounding of eps and of the thresholds).
    EXPECT_LE(std::abs(double(whole) - expected), 1) << "eps " << eps;
    // In half the particles it is binomial(N, 1/2): bound 3 sigma = 3 sqrt(N / 4).
    const double sigma = std::sqrt(expected / 4);
    std::printf("[ measured ] eps = %.4e: %zu flaws in the body (k V eps^m = %.0f), %zu in the even particles "
                "(expected %.0f, 3 sigma %.1f)\n",
                eps, whole, expected, even, expected / 2, 3 * sigma);
    EXPECT_LE(std::abs(double(even) - expected / 2), 3 * sigma) << "eps " << eps;
  }
}

TEST(GradyKipp, SameSeedSameFlawsOtherSeedOtherFlaws) {
  const std::vector<Real> volume(3000, Real(2e-6));
  const auto a = sph::assign_weibull_flaws(volume, basalt(), 7);
  const auto b = sph::assign_weibull_flaws(volume, basalt(), 7);
  const auto c = sph::assign_weibull_flaws(volume, basalt(), 8);
  EXPECT_EQ(a.offsets, b.offsets);
  EXPECT_EQ(a.threshold, b.threshold);
  EXPECT_EQ(a.count, b.count);
  EXPECT_NE(a.count, c.count);
  std::size_t same_rows = 0;
  for (std::size_t i = 0; i < a.n_particles(); ++i)
    same_rows += std::ranges::equal(a.thresholds(i), c.thresholds(i)) ? 1 : 0;
  std::printf("[ measured ] seeds 7 and 8: %zu and %zu flaws, %zu of %zu particles with the same flaws\n",
              a.total_flaws, c.total_flaws, same_rows, a.n_particles());
  // Bound: a particle keeps its flaws under another seed only by chance (well under 1%).
  EXPECT_LT(same_rows, a.n_particles() / 100);
}

// Constant strain above every threshold (the stress follows (1 - D) E eps, so eps stays put): D^(1/3)
// grows at n_i c_g / R_s and D reaches 1 at t* = R_s / (n_i c_g).
TEST(GradyKipp, CubeRootOfDamageGrowsLinearlyToFullDamage) {
  const std::size_t n = 10;
  const std::vector<Real> volume(n, Real(1e-6));
  const auto flaws = sph::assign_weibull_flaws(volume, basalt(), 2024);
  const Real E = Real(50e9), strain = Real(1e-2), c_s = Real(3000), R = sph::equivalent_radius<3>(Real(1e-6));
  for (std::size_t i = 0; i < n; ++i) ASSERT_LT(flaws.thresholds(i).back(), strain) << "particle " << i;
  const std::vector<Real> sound(n, c_s), radius(n, R);
  std::vector<Real> damage(n, 0), rate(n), cap(n);
  std::vector<Mat<3>> stress(n);
  std::vector<double> t_star(n);
  double t_min = 1e300;
  for (std::size_t i = 0; i < n; ++i) {
    t_star[i] = double(R) / (double(flaws.count[i]) * 0.4 * double(c_s));
    t_min = std::min(t_min, t_star[i]);
  }
  const double dt = t_min / 1000;
  std::vector<double> t_full(n, -1);
  double worst_linear = 0;
  for (std::size_t step = 0; step < 100000; ++step) {
    const double t = double(step) * dt;
    for (std::size_t i = 0; i < n; ++i) {
      stress[i] = Mat<3>::Zero();
      stress[i](0, 0) = (1 - damage[i]) * E * strain;
      // Linear growth: D^(1/3) = t / t* until full (bound: 1e-12, the cube roots; in float 5e-4, the
      // rounding of up to 5000 additions of 6e-8 relative each).
      if (damage[i] < 1) {
        const double expected = t / t_star[i], s = std::cbrt(double(damage[i]));
        worst_linear = std::max(worst_linear, std::abs(s - expected));
        EXPECT_NEAR(s, expected, test::bound(1e-12, 5e-4)) << "particle " << i << " at t " << t;
      } else if (t_full[i] < 0) {
        t_full[i] = t;
      }
    }
    if (std::ranges::all_of(damage, [](Real d) { return d >= 1; })) break;
    sph::grady_kipp_damage_rate<3>(flaws, stress, damage, E, sound, radius, rate, cap);
    if (step == 0)
      for (std::size_t i = 0; i < n; ++i) {
        EXPECT_EQ(cap[i], 1) << "all flaws active";
        EXPECT_NEAR(rate[i], 1 / t_star[i], test::bound(1e-12, 1e-6) / t_star[i]);
      }
    sph::advance_damage(damage, rate, cap, Real(dt));
  }
  double worst_time = 0;
  for (std::size_t i = 0; i < n; ++i) {
    // D = 1 is reached in the first step that ends at or after t* (bound: one step, and 1e-9 dt for
    // the rounding of t / t* near 1; in float 3 steps, the 5e-4 above at t* <= 5000 dt).
    ASSERT_GE(t_full[i], 0) << "particle " << i << " never fully damaged";
    const double slack = test::bound(1e-9, 3) * dt;
    EXPECT_GE(t_full[i], t_star[i] - slack) << "particle " << i;
    EXPECT_LT(t_full[i], t_star[i] + dt + slack) << "particle " << i;
    worst_time = std::max(worst_time, std::abs(t_full[i] - t_star[i]) / dt);
  }
  std::printf("[ measured ] max |D^(1/3) - t / t*| = %.2e; D = 1 within %.3f steps of t* (t* from %.3e to %.3e s)\n",
              worst_linear, worst_time, *std::ranges::min_element(t_star), *std::ranges::max_element(t_star));
}

TEST(GradyKipp, NoGrowthInCompressionOrBelowTheFirstThreshold) {
  const std::size_t n = 50;
  const std::vector<Real> volume(n, Real(1e-6));
  const auto flaws = sph::assign_weibull_flaws(volume, basalt(), 99);
  const Real E = Real(50e9);
  Real weakest = std::numeric_limits<Real>::max();
  for (std::size_t i = 0; i < n; ++i) weakest = std::min(weakest, flaws.thresholds(i).front());
  const std::vector<Real> sound(n, Real(3000)), radius(n, Real(0.05)), damage(n, Real(0.2));
  std::vector<Real> rate(n, -1);
  // 3D: isotropic compression of 1 GPa, and uniaxial compression.
  for (const Mat<3>& s : {Mat<3>(Real(-1e9) * Mat<3>::Identity()), Mat<3>(sph::Vec<3>(Real(-2e9), Real(-1e3), 0).asDiagonal())}) {
    const std::vector<Mat<3>> stress(n, s);
    sph::grady_kipp_damage_rate<3>(flaws, stress, damage, E, sound, radius, rate);
    for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(rate[i], 0) << "particle " << i;
  }
  // 2D: compression with shear whose largest principal stress is still negative.
  Mat<2> s2;
  s2 << -3e8, 1e8, 1e8, -2e8;
  ASSERT_LT(sph::largest_principal_stress<2>(s2), 0);
  sph::grady_kipp_damage_rate<2>(flaws, std::vector<Mat<2>>(n, s2), damage, E, sound, radius, rate);
  for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(rate[i], 0) << "particle " << i;
  // Tension just below the weakest flaw of the body: eps = 0.99 eps_min.
  const Real sigma = Real(0.99) * weakest * (1 - Real(0.2)) * E;
  sph::grady_kipp_damage_rate<3>(flaws, std::vector<Mat<3>>(n, Mat<3>(sigma * Mat<3>::Identity())), damage, E, sound,
                                 radius, rate);
  for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(rate[i], 0) << "particle " << i;
  std::printf("[ measured ] rates all 0 in compression and at 0.99 of the weakest threshold %.4e\n", weakest);
}

// With n_act of n_i flaws active, D^(1/3) stops at (n_act / n_i)^(1/3); above every threshold it goes on to 1.
TEST(GradyKipp, DamageIsCappedByTheFractionOfActiveFlaws) {
  const std::size_t n = 200;
  const auto flaws = sph::assign_weibull_flaws(std::vector<Real>(n, Real(1e-6)), basalt(), 5);
  std::size_t p = 0;
  while (p < n && flaws.count[p] < 4) ++p;
  ASSERT_LT(p, n) << "no particle with 4 flaws";
  const auto row = flaws.thresholds(p);
  const std::size_t n_i = row.size(), n_act = 2;
  const Real E = Real(50e9);
  const std::vector<Real> sound{Real(3000)}, radius{Real(0.05)};
  // One particle with the flaws of particle p.
  sph::WeibullFlaws one;
  one.offsets = {0, n_i};
  one.threshold.assign(row.begin(), row.end());
  one.count = {static_cast<Index>(n_i)};
  one.total_flaws = n_i;
  std::vector<Real> damage{0}, rate(1), cap(1);
  auto run = [&](Real strain, int steps) {
    for (int s = 0; s < steps; ++s) {
      const std::vector<Mat<3>> stress{Mat<3>((1 - damage[0]) * E * strain * Mat<3>::Identity())};
      sph::grady_kipp_damage_rate<3>(one, stress, damage, E, sound, radius, rate, cap);
      sph::advance_damage(damage, rate, cap, Real(1e-7));
    }
  };
  // Strain between the second and third thresholds; 2000 steps of 1e-7 s are 10 times the time
  // n_act c_g / R_s needs to reach the cap.
  run(std::sqrt(row[n_act - 1] * row[n_act]), 2000);
  const double expected = double(n_act) / double(n_i);
  std::printf("[ measured ] %zu of %zu flaws active: D = %.15f (n_act / n_i = %.15f), cap %.15f\n", n_act, n_i,
              double(damage[0]), expected, double(cap[0]));
  // Bound: rounding of the cube root and its cube (1e-14).
  EXPECT_NEAR(damage[0], expected, test::bound(1e-14, 1e-6));
  EXPECT_EQ(rate[0], 0) << "no growth at the cap";
  run(2 * row.back(), 2000);
  EXPECT_EQ(damage[0], 1);
}

TEST(GradyKipp, StressReductionRemovesTensileStrengthOnly) {
  EXPECT_EQ(sph::damaged_pressure(5, Real(0.25)), 5);          // compression is kept
  EXPECT_EQ(sph::damaged_pressure(-4, Real(0.25)), -3);        // tension (p < 0) is reduced
  EXPECT_EQ(sph::damaged_pressure(-4, 1), 0);                  // no tension when fully damaged
  Mat<3> s;
  s << 1, 2, 3, 2, -4, 5, 3, 5, 3;
  EXPECT_EQ(sph::damaged_deviatoric_stress<3>(s, Real(0.75)), Mat<3>(Real(0.25) * s));
  std::vector<Real> pressure{5, -4, -8}, damage{Real(0.5), Real(0.5), 1};
  std::vector<Mat<2>> dev(3, Mat<2>::Constant(Real(8)));
  sph::apply_damage_to_stress<2>(pressure, dev, damage);
  EXPECT_EQ(pressure, (std::vector<Real>{5, -2, 0}));
  EXPECT_EQ(dev[0], Mat<2>::Constant(Real(4)));
  EXPECT_EQ(dev[2], Mat<2>::Zero());
  std::printf("[ measured ] p' = %g, %g, %g for p = 5, -4, -8 and D = 0.5, 0.5, 1\n", double(pressure[0]),
              double(pressure[1]), double(pressure[2]));
}

TEST(GradyKipp, LargestPrincipalStressOfRotatedTensors) {
  // R diag(l) R^T has the largest eigenvalue max(l) (bound: 1e-12 of the largest magnitude; 1e-5 in float).
  const double angle = 0.7;
  Mat<2> R2;
  R2 << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
  const Mat<2> s2 = R2 * sph::Vec<2>(Real(-3e8), Real(2e7)).asDiagonal() * R2.transpose();
  const Mat<3> R3 = Eigen::AngleAxis<Real>(Real(angle), sph::Vec<3>(1, 2, 3).normalized()).toRotationMatrix();
  const Mat<3> s3 = R3 * sph::Vec<3>(Real(-3e8), Real(5e7), Real(2e7)).asDiagonal() * R3.transpose();
  std::printf("[ measured ] 2D %.9e (2e7), 3D %.9e (5e7)\n", sph::largest_principal_stress<2>(s2),
              sph::largest_principal_stress<3>(s3));
  EXPECT_NEAR(sph::largest_principal_stress<2>(s2), 2e7, test::bound(1e-12, 1e-5) * 3e8);
  EXPECT_NEAR(sph::largest_principal_stress<3>(s3), 5e7, test::bound(1e-12, 1e-5) * 3e8);
}

TEST(GradyKipp, DamageRateIsTheSameForAnyThreadCount) {
  const std::size_t n = 5000;
  const auto flaws = sph::assign_weibull_flaws(std::vector<Real>(n, Real(1e-6)), basalt(), 3);
  std::mt19937_64 generator(1);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Mat<3>> stress(n);
  std::vector<Real> damage(n), sound(n, Real(3000)), radius(n, Real(0.05));
  for (std::size_t i = 0; i < n; ++i) {
    Mat<3> a;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) a(r, c) = Real(u(generator));
    stress[i] = Real(5e7) * (a + a.transpose());
    damage[i] = Real(0.5 * (1 + u(generator)));
  }
  std::vector<Real> serial(n), parallel(n), cap1(n), cap2(n);
  {
    sph::ThreadLimit one(1);
    sph::grady_kipp_damage_rate<3>(flaws, stress, damage, Real(50e9), sound, radius, serial, cap1);
  }
  sph::grady_kipp_damage_rate<3>(flaws, stress, damage, Real(50e9), sound, radius, parallel, cap2);
  EXPECT_EQ(serial, parallel);
  EXPECT_EQ(cap1, cap2);
  const auto growing = std::ranges::count_if(serial, [](Real r) { return r > 0; });
  std::printf("[ measured ] %zu threads: %td of %zu particles growing, rates bitwise equal to 1 thread\n",
              sph::active_thread_count(), growing, n);
  EXPECT_GT(growing, 0);
}

TEST(GradyKipp, NoFlawsAtPhysicalStrainsMeansNoFracture) {
  // k = 1e-10 m^-3 over 1 m^3: the weakest flaw activates at eps_1 = (1e10)^(1/9) = 12.9.
  const std::size_t n = 1000;
  const std::vector<Real> volume(n, Real(1e-3));
  const sph::WeibullParameters w{1e-10, 9};
  const auto flaws = sph::assign_weibull_flaws(volume, w, 11);
  Real weakest = std::numeric_limits<Real>::max();
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_GE(flaws.count[i], 1u);
    weakest = std::min(weakest, flaws.thresholds(i).front());
  }
  EXPECT_GT(weakest, 1);
  const Real E = Real(50e9), strain = Real(1e-2);
  std::vector<Real> damage(n, 0), rate(n), cap(n);
  const std::vector<Real> sound(n, Real(3000)), radius(n, sph::equivalent_radius<3>(Real(1e-3)));
  const std::vector<Mat<3>> stress(n, Mat<3>(E * strain * Mat<3>::Identity()));
  for (int step = 0; step < 1000; ++step) {
    sph::grady_kipp_damage_rate<3>(flaws, stress, damage, E, sound, radius, rate, cap);
    sph::advance_damage(damage, rate, cap, Real(1e-6));
  }
  std::size_t active = 0;
  for (std::size_t i = 0; i < n; ++i) active += flaws.active(i, strain);
  std::printf("[ measured ] weakest threshold %.3f, %zu flaws active at strain 1e-2, max D %.1f after 1000 steps\n",
              double(weakest), active, double(*std::ranges::max_element(damage)));
  EXPECT_EQ(active, 0u);
  EXPECT_TRUE(std::ranges::all_of(damage, [](Real d) { return d == 0; }));
}

TEST(GradyKipp, ImpossibleParametersAreRefused) {
  const std::vector<Real> volume(10, Real(1e-6));
  auto assign = [&](double k, double m) { return [&, k, m] { sph::assign_weibull_flaws(volume, {k, m}, 1); }; };
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (const double k : {0.0, -1.0, nan, inf}) {
    const auto what = message_of(assign(k, 9));
    EXPECT_NE(what.find("k = "), std::string::npos) << what;
  }
  for (const double m : {0.0, -2.0, nan, inf}) {
    const auto what = message_of(assign(4e35, m));
    EXPECT_NE(what.find("m = "), std::string::npos) << what;
  }
  const auto empty = message_of([] { sph::assign_weibull_flaws({}, {4e35, 9}, 1); });
  EXPECT_NE(empty.find("particle volume list is empty"), std::string::npos) << empty;
  std::vector<Real> bad = volume;
  bad[3] = 0;
  const auto zero = message_of([&] { sph::assign_weibull_flaws(bad, {4e35, 9}, 1); });
  EXPECT_NE(zero.find("particle volume 3"), std::string::npos) << zero;
  const auto flaws = sph::assign_weibull_flaws(volume, {4e35, 9}, 1);
  std::vector<Real> rate(10);
  const auto E = message_of([&] {
    sph::grady_kipp_damage_rate<3>(flaws, std::vector<Mat<3>>(10, Mat<3>::Zero()), std::vector<Real>(10, 0), 0,
                                   std::vector<Real>(10, 1), std::vector<Real>(10, 1), rate);
  });
  EXPECT_NE(E.find("Young's modulus"), std::string::npos) << E;
  const auto length = message_of([&] {
    sph::grady_kipp_damage_rate<3>(flaws, std::vector<Mat<3>>(9, Mat<3>::Zero()), std::vector<Real>(10, 0), 1,
                                   std::vector<Real>(10, 1), std::vector<Real>(10, 1), rate);
  });
  EXPECT_NE(length.find("stress has 9 entries"), std::string::npos) << length;
  std::printf("[ measured ] e.g. \"%s\"; \"%s\"\n", message_of(assign(nan, 9)).c_str(), empty.c_str());
}

TEST(GradyKipp, FractureAreaAndFragmentSizeFormulasMatchHandValues) {
  // dA/dt with m = 3, c_g = 1, k = 15 / pi: 8 pi c_g^3 k / (4 5 6) = 1, so dA/dt = (5 6 / 2) eps^2 D^(1/3)
  // = 15 x 0.01 x 0.5 = 0.075 at eps = 0.1, D = 1/8 (bound: 1e-14 relative).
  const sph::WeibullParameters w3{15 / 3.14159265358979323846, 3};
  const double rate = sph::fracture_area_rate(w3, 1, 0.1, 0.125);
  EXPECT_NEAR(rate, 0.075, 1e-14 * 0.075);
  EXPECT_EQ(sph::fracture_area_rate(w3, 1, -0.1, 0.125), 0);
  // m = 9, A = 1 m^-1: L_m = 3 x 12 / 11 = 36/11 m, L_max = 11/3 L_m = 12 m.
  const sph::WeibullParameters w9{4e35, 9};
  const double Lm = sph::most_frequent_fragment_size(w9, 1), Lmax = sph::largest_fragment_size(w9, Lm);
  EXPECT_NEAR(Lm, 36.0 / 11, 1e-14);
  EXPECT_NEAR(Lmax, 12, 1e-13);
  // F_cum(L_max / 2) in V = L_max^3: (15 14 13 / 120) 2^-9 (1 + 4.5 + 45 / 4 + 165 / 8) = 22.75 x 37.375 / 512
  // = 1.6607055664... (bound: 1e-13 relative).
  const double V = 1728, F_half = sph::cumulative_fragment_number(w9, 6, 12, V);
  const double hand = 22.75 * 37.375 / 512;
  EXPECT_NEAR(F_half, hand, 1e-13 * hand);
  // F_cum(0) = (m+6)(m+5)(m+4)/120 V / L_max^3 = 22.75, F_cum(L_max) = 0, decreasing in between.
  EXPECT_NEAR(sph::cumulative_fragment_number(w9, 0, 12, V), 22.75, 1e-13 * 22.75);
  EXPECT_EQ(sph::cumulative_fragment_number(w9, 12, 12, V), 0);
  EXPECT_EQ(sph::cumulative_fragment_number(w9, 13, 12, V), 0);
  double previous = std::numeric_limits<double>::infinity();
  int decreasing = 0;
  for (int s = 0; s <= 1000; ++s) {
    const double F = sph::cumulative_fragment_number(w9, 12.0 * s / 1000, 12, V);
    if (s < 1000) {
      EXPECT_LT(F, previous) << "L = " << 12.0 * s / 1000;
      decreasing += F < previous;
    }
    previous = F;
  }
  std::printf("[ measured ] dA/dt %.17g (0.075); L_m %.15g (36/11 = %.15g), L_max %.15g (12); F_cum(6) %.15g (%.15g); "
              "strictly decreasing on %d of 1000 points\n",
              rate, Lm, 36.0 / 11, Lmax, F_half, hand, decreasing);
  EXPECT_NE(message_of([&] { sph::cumulative_fragment_number(w9, -1, 12, V); }).find("L = "), std::string::npos);
  EXPECT_NE(message_of([&] { sph::most_frequent_fragment_size(w9, 0); }).find("fracture area A"), std::string::npos);
}

TEST(GradyKipp, TwoSeparatedClustersAreTwoFragments) {
  // Cluster A = {0, 2, 4, 6} (a chain), cluster B = {1, 3, 5} (a triangle), no pair between them.
  const auto relation = relation_from<2>(adjacency_of(7, {{0, 2}, {2, 4}, {4, 6}, {1, 3}, {3, 5}, {5, 1}}));
  const std::vector<Real> mass{1, 10, 2, 20, 3, 30, 4};
  const std::vector<Real> damage{0, Real(0.5), Real(0.1), 0, 0, Real(0.9), 0};
  const auto f = sph::find_fragments<2>(relation, mass, damage, Real(0.95));
  ASSERT_EQ(f.n_fragments(), 2u);
  EXPECT_EQ(f.fragments[0].label, 1u);
  EXPECT_EQ(f.fragments[0].mass, 60);
  EXPECT_EQ(f.fragments[0].particles, 3u);
  EXPECT_EQ(f.fragments[1].label, 0u);
  EXPECT_EQ(f.fragments[1].mass, 10);
  EXPECT_EQ(f.label, (std::vector<Index>{0, 1, 0, 1, 0, 1, 0}));
  EXPECT_EQ(f.total_mass, 70);
  EXPECT_NEAR(f.largest_mass_fraction, 60.0 / 70, test::bound(1e-15, 1e-7));
  EXPECT_EQ(f.cumulative_number(60), 1u);
  EXPECT_EQ(f.cumulative_number(10), 2u);
  EXPECT_EQ(f.cumulative_number(61), 0u);
  std::printf("[ measured ] fragments %zu: masses %g (label %u), %g (label %u); largest fraction %.6f\n",
              f.n_fragments(), double(f.fragments[0].mass), f.fragments[0].label, double(f.fragments[1].mass),
              f.fragments[1].label, double(f.largest_mass_fraction));

  // Particle 2 fully damaged: chain A breaks into {0}, {2} (dust) and {4, 6}.
  auto broken = damage;
  broken[2] = 1;
  const auto g = sph::find_fragments<2>(relation, mass, broken, Real(0.95));
  EXPECT_EQ(g.masses(), (std::vector<Real>{60, 7, 2, 1}));
  EXPECT_EQ(g.label, (std::vector<Index>{0, 1, 2, 1, 4, 1, 4}));

  EXPECT_EQ(sph::cumulative_mass_distribution_csv(g), "mass,cumulative_number\n60,1\n7,2\n2,3\n1,4\n");
}

TEST(GradyKipp, FullyDamagedBodyGivesOneFragmentPerParticle) {
  // A 3D chain of 6 particles, every one connected to the next; all fully damaged.
  const auto relation = relation_from<3>(adjacency_of(6, {{0, 1}, {1, 2}, {2, 3}, {3, 4}, {4, 5}}));
  const std::vector<Real> mass{3, 1, 4, 1, 5, 9};
  const auto intact = sph::find_fragments<3>(relation, mass, std::vector<Real>(6, 0), 1);
  EXPECT_EQ(intact.n_fragments(), 1u);
  EXPECT_EQ(intact.largest_mass_fraction, 1);
  const auto f = sph::find_fragments<3>(relation, mass, std::vector<Real>(6, 1), 1);
  ASSERT_EQ(f.n_fragments(), 6u);
  EXPECT_EQ(f.masses(), (std::vector<Real>{9, 5, 4, 3, 1, 1}));
  // Equal masses by label: particles 1 and 3.
  EXPECT_EQ(f.fragments[4].label, 1u);
  EXPECT_EQ(f.fragments[5].label, 3u);
  for (std::size_t i = 0; i < 6; ++i) EXPECT_EQ(f.label[i], i);
  EXPECT_EQ(f.cumulative_number(1), 6u);
  EXPECT_NEAR(f.largest_mass_fraction, 9.0 / 23, test::bound(1e-15, 1e-7));
  std::printf("[ measured ] intact: %zu fragment; fully damaged: %zu fragments, largest fraction %.6f\n",
              intact.n_fragments(), f.n_fragments(), double(f.largest_mass_fraction));
  EXPECT_NE(message_of([&] { sph::find_fragments<3>(relation, mass, std::vector<Real>(5, 0), 1); }).find("damage (5)"),
            std::string::npos);
  EXPECT_NE(message_of([&] { sph::find_fragments<3>(relation, mass, std::vector<Real>(6, 0), 0); }).find("threshold"),
            std::string::npos);
}

}  // namespace
