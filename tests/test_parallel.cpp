// Results are bitwise identical with 1 and 2 threads: neighbour lists, reductions, a run of the
// diffusion system (every particle loop is a gather; sums use fixed blocks) and the cell models
// advanced in SIMD lanes (blocks fixed by the particle index).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "geometry/lattice.hpp"
#include "libsph/core/exact_sum.hpp"
#include "libsph/core/neighbour_relation.hpp"
#include "libsph/core/parallel.hpp"
#include "libsph/diffusion/diffusion_system.hpp"
#include "libsph/reaction/reaction_system.hpp"
#include "libsph/reaction/ten_tusscher_panfilov_2006.hpp"

namespace {

using sph::Real;

struct Outcome {
  std::vector<std::size_t> offsets;
  std::vector<sph::Index> neighbours;
  std::vector<Real> kernel_values;
  Real sum = 0;
  std::vector<Real> field;
};

Outcome compute(std::size_t threads) {
  sph::ThreadLimit limit(threads);
  EXPECT_EQ(sph::active_thread_count(), threads);
  auto body = geometry::lattice_box<3>("cube", sph::Vec<3>::Zero(), sph::Vec<3>::Constant(1), 1.0 / 24);
  std::mt19937_64 engine(342343901);
  for (auto& x : body.position)
    for (int d = 0; d < 3; ++d) x[d] += (static_cast<Real>(engine() >> 11) * 0x1.0p-53 - 0.5) * 0.01;
  const auto relation = sph::build_inner_relation<3>(body.position, sph::WendlandC2<3>{}, 1.3 / 24);
  sph::ScalarDiffusionSystem<3>::Settings settings;
  settings.diffusion_tensor = {sph::Mat<3>(sph::Vec<3>(1e-3, 2e-4, 5e-4).asDiagonal())};
  sph::ScalarDiffusionSystem<3> diffusion(body, relation, settings);
  auto C = body.field(diffusion.value_field());
  for (std::size_t i = 0; i < C.size(); ++i) C[i] = std::sin(7 * body.position[i][0]) * body.position[i][1];
  for (int step = 0; step < 20; ++step) diffusion.advance(step * 0.1, diffusion.stable_time_step());
  Outcome out{relation.offsets, relation.neighbour, relation.kernel_value, 0, {C.begin(), C.end()}};
  out.sum = sph::parallel_sum(C.size(), Real(0), [&](std::size_t i) { return C[i] * body.volume[i]; });
  return out;
}

template <class T>
bool bitwise_equal(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

TEST(Determinism, OneAndTwoThreadsGiveBitwiseIdenticalResults) {
  const Outcome one = compute(1), two = compute(2);
  EXPECT_TRUE(bitwise_equal(one.offsets, two.offsets));
  EXPECT_TRUE(bitwise_equal(one.neighbours, two.neighbours));
  EXPECT_TRUE(bitwise_equal(one.kernel_values, two.kernel_values));
  EXPECT_TRUE(bitwise_equal(one.field, two.field));
  EXPECT_EQ(std::memcmp(&one.sum, &two.sum, sizeof(Real)), 0);
  EXPECT_GT(one.field.size(), 10000u);
}

// ten Tusscher-Panfilov cells in lanes of eight, 1,003 of them (the last block is partial), paced
// with strengths and times that differ from cell to cell, through the upstroke and plateau.
std::vector<Real> paced_cells(std::size_t threads) {
  sph::ThreadLimit limit(threads);
  constexpr std::size_t n = 1003;
  sph::ParticleSet<3> cells("cells", std::vector<sph::Vec<3>>(n, sph::Vec<3>::Zero()), std::vector<Real>(n, 1.0));
  sph::ReactionSystem<3, sph::TenTusscherPanfilov2006> reaction(cells, sph::TenTusscherPanfilov2006{}, {});
  std::vector<Real> stimulus(n);
  constexpr double dt = 0.05;
  for (int step = 0; step < 400; ++step) {
    for (std::size_t i = 0; i < n; ++i) stimulus[i] = step * dt < 1 + 0.01 * double(i % 37) ? 40.0 + double(i % 11) : 0.0;
    reaction.advance(step * dt, dt, stimulus);
  }
  std::vector<Real> states;
  for (std::size_t k = 0; k < sph::TenTusscherPanfilov2006::n_states; ++k) {
    const auto column = cells.field(reaction.state_field(k));
    states.insert(states.end(), column.begin(), column.end());
  }
  return states;
}

TEST(Determinism, CellModelLanesGiveBitwiseIdenticalResultsForAnyThreadCount) {
  static_assert(sph::HasLanesRbrQssStep<sph::TenTusscherPanfilov2006>);
  const std::vector<Real> one = paced_cells(1), two = paced_cells(2);
  EXPECT_TRUE(bitwise_equal(one, two));
  EXPECT_GT(*std::max_element(one.begin(), one.begin() + 1003), 0.0);  // the cells fired: V > 0 mV at 20 ms
}

TEST(ParallelHelpers, FirstIndexWhereFindsTheLowestIndex) {
  sph::ThreadLimit limit(2);
  std::vector<int> flags(100000, 0);
  flags[70001] = flags[5003] = flags[99999] = 1;
  EXPECT_EQ(sph::first_index_where(flags.size(), [&](std::size_t i) { return flags[i] == 1; }), 5003u);
  EXPECT_EQ(sph::first_index_where(flags.size(), [&](std::size_t) { return false; }), flags.size());
}

// The exact sum does not depend on the order or grouping of its terms, and it is exact where the
// naive sum loses everything: 1e100 + 1 - 1e100 = 1.
TEST(ExactSum, IsTheSameForAnyOrderAndGroupingOfTheTerms) {
  std::mt19937_64 engine(20261207);
  std::vector<double> terms(50000);
  for (auto& t : terms) {
    const double mantissa = static_cast<double>(engine() >> 11) * 0x1.0p-53 - 0.6;  // a negative sum
    t = std::ldexp(mantissa, static_cast<int>(engine() % 120) - 60);  // magnitudes 2^-61 to 2^59
  }
  const double reference = sph::exact_sum(terms.size(), [&](std::size_t i) { return terms[i]; });
  long double naive = 0;
  for (const double t : terms) naive += t;
  ASSERT_TRUE(std::isfinite(reference));
  EXPECT_LE(std::abs(double(naive) - reference), 1e-15 * std::abs(reference));  // bound: long double's 64-bit mantissa
  // 1e100 and -1e100 among the terms cancel exactly: the sum keeps every bit of the others.
  terms.push_back(1e100);
  terms.push_back(-1e100);
  for (int trial = 0; trial < 5; ++trial) {
    std::shuffle(terms.begin(), terms.end(), engine);
    sph::ExactSum a, b;  // two parts merged, as two ranks would
    for (std::size_t i = 0; i < terms.size(); ++i) (i % 3 == 0 ? a : b).add(terms[i]);
    a.add(sph::ExactSum::from_bytes(b.bytes()));
    const double threads = [&] {
      sph::ThreadLimit limit(static_cast<std::size_t>(trial % 2 + 1));
      return sph::exact_sum(terms.size(), [&](std::size_t i) { return terms[i]; });
    }();
    EXPECT_EQ(std::memcmp(&reference, &threads, sizeof(double)), 0) << threads << " against " << reference;
    const double merged = a.value();
    EXPECT_EQ(std::memcmp(&reference, &merged, sizeof(double)), 0) << merged << " against " << reference;
  }
  long double naive_with_big = 0;
  for (const double t : terms) naive_with_big += t;
  sph::ExactSum cancel;
  for (const double t : {1e100, 1.0, -1e100, -3.0}) cancel.add(t);
  EXPECT_EQ(cancel.value(), -2.0);
  sph::ExactSum special;
  special.add(1.0);
  special.add(std::numeric_limits<double>::infinity());
  EXPECT_EQ(special.value(), std::numeric_limits<double>::infinity());
  special.add(-std::numeric_limits<double>::infinity());
  EXPECT_TRUE(std::isnan(special.value()));
  std::printf("[ measured ] exact sum of 50,000 terms %.17g (long double %.17Lg); with 1e100 and -1e100 shuffled in, "
              "the same bits in 5 orders and groupings (long double sum then %.17Lg)\n",
              reference, naive, naive_with_big);
}

}  // namespace

