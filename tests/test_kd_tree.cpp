// K-d tree neighbour search (libsph/core/kd_tree.hpp): at constant h the k-d tree relation is the
// cell-linked-list relation entry by entry and bit for bit; with variable h it holds exactly the
// brute-force pairs of the symmetric rule |x_ij| < 2 (h_i + h_j) / 2; radius queries equal brute force,
// also on degenerate point sets; the relation is bitwise the same for 1 and 2 threads; bad input is
// named. Timings against the cell list are printed, not asserted.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "tests/random_points.hpp"
#include "libsph/core/kd_tree.hpp"
#include "libsph/core/neighbour_relation.hpp"
#include "libsph/core/parallel.hpp"

namespace {

using sph::Index;
using sph::Real;

using test::random_points;
using test::uniform;

// A cubic lattice of spacing dx with every coordinate moved by up to +-jitter * dx.
template <int Dim>
std::vector<sph::Vec<Dim>> jittered_lattice(int per_side, Real dx, Real jitter, std::uint64_t seed) {
  std::mt19937_64 engine(seed);
  std::vector<sph::Vec<Dim>> points;
  const int nz = Dim == 2 ? 1 : per_side;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < per_side; ++j)
      for (int i = 0; i < per_side; ++i) {
        sph::Vec<Dim> x;
        x[0] = i * dx;
        x[1] = j * dx;
        if constexpr (Dim == 3) x[2] = k * dx;
        for (int d = 0; d < Dim; ++d) x[d] += jitter * dx * (2 * uniform(engine) - 1);
        points.push_back(x);
      }
  return points;
}

// A unit sphere of n particles of equal mass with density rho(r) = 1 / (2 pi r) (mass inside r is r^2,
// so r = sqrt(u)), and h_i = eta (m / rho(r_i))^(1/3) = eta (2 pi r_i / n)^(1/3).
void concentrated_sphere(std::size_t n, Real eta, std::uint64_t seed, std::vector<sph::Vec<3>>& x,
                         std::vector<Real>& h) {
  std::mt19937_64 engine(seed);
  x.resize(n);
  h.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Real r = std::sqrt(uniform(engine));
    const Real cos_theta = 2 * uniform(engine) - 1, phi = 2 * sph::pi * uniform(engine);
    const Real s = std::sqrt(std::max(Real(0), 1 - cos_theta * cos_theta));
    x[i] = r * sph::Vec<3>(s * std::cos(phi), s * std::sin(phi), cos_theta);
    h[i] = eta * std::cbrt(2 * sph::pi * std::max(r, Real(1e-6)) / static_cast<Real>(n));
  }
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// Number of entries in which two relations differ (any array, bitwise); 0 when identical.
template <int Dim>
std::size_t relation_differences(const sph::NeighbourList<Dim>& a, const sph::NeighbourList<Dim>& b) {
  if (a.offsets != b.offsets || a.n_pairs() != b.n_pairs()) return std::max<std::size_t>(1, a.n_pairs() + b.n_pairs());
  std::size_t differ = 0;
  for (std::size_t k = 0; k < a.n_pairs(); ++k) {
    const bool same = a.neighbour[k] == b.neighbour[k] &&
                      std::memcmp(&a.distance[k], &b.distance[k], sizeof(Real)) == 0 &&
                      std::memcmp(&a.kernel_value[k], &b.kernel_value[k], sizeof(Real)) == 0 &&
                      std::memcmp(&a.kernel_derivative[k], &b.kernel_derivative[k], sizeof(Real)) == 0 &&
                      std::memcmp(a.unit_vector[k].data(), b.unit_vector[k].data(), sizeof(sph::Vec<Dim>)) == 0;
    if (!same) ++differ;
  }
  return differ;
}

template <int Dim>
std::vector<std::vector<Index>> sorted_rows(const sph::NeighbourList<Dim>& relation) {
  std::vector<std::vector<Index>> rows(relation.n_targets());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    rows[i].assign(relation.neighbour.begin() + relation.offsets[i], relation.neighbour.begin() + relation.offsets[i + 1]);
    std::sort(rows[i].begin(), rows[i].end());
  }
  return rows;
}

template <int Dim>
void expect_equals_cell_list(const std::vector<sph::Vec<Dim>>& x, Real h, const char* label) {
  const sph::AnyKernel<Dim> kernels[] = {sph::CubicSplineM4<Dim>{}, sph::WendlandC2<Dim>{}, sph::WendlandC4<Dim>{}};
  for (const auto& kernel : kernels) {
    sph::InnerRelation<Dim> cells, tree_relation;
    sph::rebuild_inner_relation<Dim>(cells, x, kernel, h);
    sph::KdTree<Dim> tree;
    const std::vector<Real> hs(x.size(), h);
    sph::rebuild_inner_relation_variable_h<Dim>(tree_relation, x, hs, kernel, tree);
    const std::size_t differ = relation_differences(cells, tree_relation);
    std::printf("[ measured ] %s, kernel %zu: %zu particles, %zu pairs (cell list %zu), %zu entries differ\n", label,
                kernel.index(), x.size(), tree_relation.n_pairs(), cells.n_pairs(), differ);
    // Bound: identical (same neighbours in the same order, every cached value bitwise).
    EXPECT_EQ(differ, 0u);
    EXPECT_GT(cells.n_pairs(), 10 * x.size());
    EXPECT_EQ(std::memcmp(&cells.kernel_value_at_zero, &tree_relation.kernel_value_at_zero, sizeof(Real)), 0);
    EXPECT_EQ(cells.smoothing_length, tree_relation.smoothing_length);
  }
}

TEST(KdTree, ConstantHEqualsCellListRandom2D) {
  expect_equals_cell_list<2>(random_points<2>(4000, 1.0, 8101), Real(0.02), "random 2D");
}
TEST(KdTree, ConstantHEqualsCellListRandom3D) {
  expect_equals_cell_list<3>(random_points<3>(5000, 1.0, 8102), Real(0.06), "random 3D");
}
// Spacing 0.25 and support 0.5: many points on cell faces and many pairs exactly one support apart.
TEST(KdTree, ConstantHEqualsCellListOnCellFaces3D) {
  expect_equals_cell_list<3>(jittered_lattice<3>(14, 0.25, 0, 1), Real(0.25), "lattice on cell faces 3D");
}

template <int Dim>
void expect_variable_h_equals_brute_force(std::size_t n, Real h0, std::uint64_t seed) {
  const auto x = random_points<Dim>(n, 1.0, seed);
  std::mt19937_64 engine(seed + 1);
  std::vector<Real> h(n);
  for (auto& value : h) value = h0 * (1 + 2 * uniform(engine));  // in [h0, 3 h0]
  const sph::AnyKernel<Dim> kernel = sph::CubicSplineM4<Dim>{};
  sph::InnerRelation<Dim> relation;
  sph::KdTree<Dim> tree;
  sph::rebuild_inner_relation_variable_h<Dim>(relation, x, h, kernel, tree);
  const auto expected = sph::brute_force_neighbours_variable_h<Dim>(x, h, kernel);
  const auto rows = sorted_rows(relation);
  std::size_t rows_differ = 0, asymmetric = 0, min_count = n, max_count = 0;
  double worst_value = 0, worst_derivative = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (rows[i] != expected[i]) ++rows_differ;
    min_count = std::min(min_count, rows[i].size());
    max_count = std::max(max_count, rows[i].size());
    for (std::size_t k = relation.offsets[i]; k < relation.offsets[i + 1]; ++k) {
      const Index j = relation.neighbour[k];
      if (!std::binary_search(rows[j].begin(), rows[j].end(), static_cast<Index>(i))) ++asymmetric;
      const Real h_ij = (h[i] + h[j]) / 2, r = (x[i] - x[j]).norm();
      const Real w = sph::CubicSplineM4<Dim>::value(r, h_ij), dw = sph::CubicSplineM4<Dim>::derivative(r, h_ij);
      worst_value = std::max(worst_value, double(std::abs(relation.kernel_value[k] - w) / sph::CubicSplineM4<Dim>::normalisation(h_ij)));
      worst_derivative = std::max(worst_derivative, double(std::abs(relation.kernel_derivative[k] - dw) /
                                                           (sph::CubicSplineM4<Dim>::normalisation(h_ij) / h_ij)));
    }
  }
  std::printf("[ measured ] variable h %dD: %zu particles, %zu pairs, %zu..%zu neighbours, %zu rows differ from brute "
              "force, %zu asymmetric pairs, |W - W(r, h_ij)| / W(0-scale) <= %.2e, same for dW/dr <= %.2e\n",
              Dim, n, relation.n_pairs(), min_count, max_count, rows_differ, asymmetric, worst_value, worst_derivative);
  // Bound: every row the brute-force set; the pair rule is symmetric.
  EXPECT_EQ(rows_differ, 0u);
  EXPECT_EQ(asymmetric, 0u);
  // Bound: W and dW/dr are those at h_ij up to round-off (1e-14 of the kernel scale in double).
  const double round_off = std::is_same_v<Real, float> ? 1e-5 : 1e-13;
  EXPECT_LT(worst_value, round_off);
  EXPECT_LT(worst_derivative, round_off);
  EXPECT_GT(relation.n_pairs(), 5 * n);
  EXPECT_EQ(relation.smoothing_length, *std::max_element(h.begin(), h.end()));
}

TEST(KdTree, VariableHEqualsBruteForce2D) { expect_variable_h_equals_brute_force<2>(3000, Real(0.01), 8201); }
TEST(KdTree, VariableHEqualsBruteForce3D) { expect_variable_h_equals_brute_force<3>(3000, Real(0.03), 8202); }

template <int Dim>
std::size_t radius_query_mismatches(const std::vector<sph::Vec<Dim>>& x, const std::vector<sph::Vec<Dim>>& queries,
                                    const std::vector<Real>& radii, std::size_t& results) {
  sph::KdTree<Dim> tree(x);
  std::size_t mismatches = 0;
  std::vector<Index> found;
  for (const auto& q : queries)
    for (Real r : radii) {
      tree.radius_query(q, r, found);
      std::vector<Index> expected;
      for (std::size_t j = 0; j < x.size(); ++j)
        if ((q - x[j]).squaredNorm() < r * r) expected.push_back(static_cast<Index>(j));
      if (found != expected) ++mismatches;
      results += found.size();
    }
  return mismatches;
}

TEST(KdTree, RadiusQueriesEqualBruteForce) {
  const std::vector<Real> radii = {0, 0.01, 0.05, 0.2, 0.7, 10};
  std::size_t results = 0;
  const auto x3 = random_points<3>(3000, 1.0, 8301);
  auto q3 = random_points<3>(100, 1.4, 8302);
  for (auto& q : q3) q.array() -= Real(0.2);  // some queries outside the cloud
  for (std::size_t k = 0; k < 20; ++k) q3.push_back(x3[k * 17]);  // queries on particles
  const std::size_t m3 = radius_query_mismatches<3>(x3, q3, radii, results);
  const auto x2 = random_points<2>(3000, 1.0, 8303);
  const auto q2 = random_points<2>(100, 1.0, 8304);
  const std::size_t m2 = radius_query_mismatches<2>(x2, q2, radii, results);
  // Points exactly on a lattice: distances equal to the radius are excluded (strict <).
  const auto lattice = jittered_lattice<3>(10, 0.25, 0, 1);
  const std::size_t m_lattice = radius_query_mismatches<3>(lattice, {lattice[0], lattice[555]}, {0.25, 0.5}, results);
  std::printf("[ measured ] radius queries: %zu results, mismatches 3D %zu, 2D %zu, lattice %zu\n", results, m3, m2,
              m_lattice);
  // Bound: every query equals brute force, indices ascending.
  EXPECT_EQ(m3 + m2 + m_lattice, 0u);
}

TEST(KdTree, DegenerateInputs) {
  const sph::AnyKernel<3> kernel = sph::CubicSplineM4<3>{};
  std::size_t results = 0;
  // n = 0: an empty tree, empty queries, an empty relation.
  {
    const std::vector<sph::Vec<3>> none;
    sph::KdTree<3> tree(none);
    EXPECT_TRUE(tree.empty());
    EXPECT_TRUE(tree.radius_query(sph::Vec<3>::Zero(), 1).empty());
    sph::InnerRelation<3> relation;
    sph::rebuild_inner_relation_variable_h<3>(relation, none, std::vector<Real>{}, kernel, tree);
    EXPECT_EQ(relation.n_targets(), 0u);
    EXPECT_EQ(relation.n_pairs(), 0u);
    EXPECT_EQ(relation.offsets, std::vector<std::size_t>{0});
  }
  // n = 1: no neighbour, the point found by a query around it.
  {
    const std::vector<sph::Vec<3>> one = {sph::Vec<3>(0.3, -2, 5)};
    sph::KdTree<3> tree(one);
    EXPECT_EQ(tree.radius_query(one[0], Real(1e-9)), std::vector<Index>{0});
    EXPECT_TRUE(tree.radius_query(one[0], 0).empty());
    sph::InnerRelation<3> relation;
    sph::rebuild_inner_relation_variable_h<3>(relation, one, std::vector<Real>{0.1}, kernel, tree);
    EXPECT_EQ(relation.n_targets(), 1u);
    EXPECT_EQ(relation.n_pairs(), 0u);
  }
  // All points identical: each sees all the others at distance 0 with a zero unit vector.
  {
    const std::size_t n = 50;
    const std::vector<sph::Vec<3>> same(n, sph::Vec<3>(1, 2, 3));
    std::vector<Real> h(n);
    for (std::size_t i = 0; i < n; ++i) h[i] = Real(0.1) * (1 + Real(i % 3));
    sph::KdTree<3> tree(same);
    EXPECT_EQ(tree.radius_query(same[0], Real(0.5)).size(), n);
    sph::InnerRelation<3> relation;
    sph::rebuild_inner_relation_variable_h<3>(relation, same, h, kernel, tree);
    EXPECT_EQ(relation.n_pairs(), n * (n - 1));
    EXPECT_EQ(sorted_rows(relation), sph::brute_force_neighbours_variable_h<3>(same, h, kernel));
    bool zero_geometry = true;
    for (std::size_t k = 0; k < relation.n_pairs(); ++k)
      zero_geometry = zero_geometry && relation.distance[k] == 0 && relation.unit_vector[k].isZero(0);
    EXPECT_TRUE(zero_geometry);
    results += relation.n_pairs();
  }
  // Collinear points (a line in 3D, with coincident pairs): queries and relation equal brute force.
  {
    std::mt19937_64 engine(8401);
    std::vector<sph::Vec<3>> line(400);
    std::vector<Real> h(line.size());
    for (std::size_t i = 0; i < line.size(); ++i) {
      const Real t = std::floor(200 * uniform(engine)) / 200;  // on a grid: many coincident points
      line[i] = sph::Vec<3>(1, 2, -1) * t + sph::Vec<3>(0.5, 0, 0);
      h[i] = Real(0.005) * (1 + 2 * uniform(engine));
    }
    const std::size_t mismatches =
        radius_query_mismatches<3>(line, {line[0], line[7], sph::Vec<3>(0, 0, 0)}, {0.01, 0.1, 1}, results);
    EXPECT_EQ(mismatches, 0u);
    sph::KdTree<3> tree;
    sph::InnerRelation<3> relation;
    sph::rebuild_inner_relation_variable_h<3>(relation, line, h, kernel, tree);
    EXPECT_EQ(sorted_rows(relation), sph::brute_force_neighbours_variable_h<3>(line, h, kernel));
    results += relation.n_pairs();
  }
  std::printf("[ measured ] degenerate inputs: %zu pairs and query results checked\n", results);
}

TEST(KdTree, BitwiseForOneAndTwoThreads) {
  std::vector<sph::Vec<3>> x;
  std::vector<Real> h;
  concentrated_sphere(30000, Real(1.2), 8501, x, h);
  const sph::AnyKernel<3> kernel = sph::WendlandC2<3>{};
  sph::InnerRelation<3> one, two;
  sph::KdTree<3> tree_one, tree_two;
  {
    sph::ThreadLimit limit(1);
    sph::rebuild_inner_relation_variable_h<3>(one, x, h, kernel, tree_one);
  }
  {
    sph::ThreadLimit limit(2);
    sph::rebuild_inner_relation_variable_h<3>(two, x, h, kernel, tree_two);
    // A second rebuild in place (reused storage) gives the same again.
    sph::rebuild_inner_relation_variable_h<3>(two, x, h, kernel, tree_two);
  }
  const std::size_t differ = relation_differences(one, two);
  const bool same_tree = tree_one.n_nodes() == tree_two.n_nodes() &&
                         std::memcmp(tree_one.entries().data(), tree_two.entries().data(),
                                     tree_one.size() * sizeof(sph::KdTree<3>::Entry)) == 0;
  std::printf("[ measured ] 1 vs 2 threads: %zu particles, %zu pairs, %zu entries differ, tree layouts %s\n", x.size(),
              one.n_pairs(), differ, same_tree ? "identical" : "differ");
  // Bound: bitwise identical relations (and the same tree).
  EXPECT_EQ(differ, 0u);
  EXPECT_TRUE(same_tree);
}

void expect_throws_naming(const std::function<void()>& call, const std::string& name) {
  try {
    call();
    ADD_FAILURE() << "no exception; expected one naming '" << name << "'";
  } catch (const std::invalid_argument& e) {
    std::printf("[ measured ] message: %s\n", e.what());
    EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
  }
}

TEST(KdTree, BadInputIsNamed) {
  const auto x = random_points<2>(20, 1.0, 8601);
  const sph::AnyKernel<2> kernel = sph::CubicSplineM4<2>{};
  sph::InnerRelation<2> relation;
  sph::KdTree<2> tree;
  auto with_h = [&](std::size_t i, Real value) {
    std::vector<Real> h(x.size(), Real(0.1));
    h[i] = value;
    return h;
  };
  expect_throws_naming([&] { sph::rebuild_inner_relation_variable_h<2>(relation, x, with_h(7, 0), kernel, tree); },
                       "particle 7");
  expect_throws_naming([&] { sph::rebuild_inner_relation_variable_h<2>(relation, x, with_h(3, -1), kernel, tree); },
                       "particle 3");
  expect_throws_naming(
      [&] { sph::rebuild_inner_relation_variable_h<2>(relation, x, with_h(11, std::nan("")), kernel, tree); },
      "particle 11");
  expect_throws_naming(
      [&] {
        sph::rebuild_inner_relation_variable_h<2>(relation, x, with_h(19, std::numeric_limits<Real>::infinity()), kernel,
                                                  tree);
      },
      "particle 19");
  expect_throws_naming(
      [&] {
        sph::rebuild_inner_relation_variable_h<2>(relation, x, std::vector<Real>(19, Real(0.1)), kernel, tree);
      },
      "19 smoothing lengths for 20 positions");
  auto bad_x = x;
  bad_x[5][1] = std::nan("");
  expect_throws_naming(
      [&] {
        sph::rebuild_inner_relation_variable_h<2>(relation, bad_x, std::vector<Real>(20, Real(0.1)), kernel, tree);
      },
      "particle 5");
  expect_throws_naming([&] { tree.build(bad_x); }, "particle 5");
  expect_throws_naming([&] { tree.build(x, with_h(2, 0)); }, "particle 2");
  expect_throws_naming([&] { tree.radius_query(x[0], -1); }, "radius");
}

TEST(KdTree, AdaptingHApproachesTheTargetNeighbourCount) {
  // A jittered lattice with h far too small: a few adaptation steps bring the neighbour counts near
  // the target (about 4/3 pi 2.4^3 = 58 at h = 1.2 dx).
  const auto x = jittered_lattice<3>(20, 1.0, Real(0.1), 8701);
  std::vector<Real> h(x.size(), Real(0.5));
  const sph::AnyKernel<3> kernel = sph::CubicSplineM4<3>{};
  sph::InnerRelation<3> relation;
  sph::KdTree<3> tree;
  const Real target = 58;
  for (int step = 0; step < 6; ++step) {
    sph::rebuild_inner_relation_variable_h<3>(relation, x, h, kernel, tree);
    sph::adapt_smoothing_lengths<3>(relation, target, h);
  }
  sph::rebuild_inner_relation_variable_h<3>(relation, x, h, kernel, tree);
  // Interior particles only (the lattice faces lack neighbours on one side).
  double mean = 0;
  std::size_t interior = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    if ((x[i].array() > 5).all() && (x[i].array() < 14).all()) {
      mean += relation.n_neighbours(i);
      ++interior;
    }
  mean /= interior;
  std::printf("[ measured ] adapted h: interior mean neighbours %.2f (target %.0f), h in [%.3f, %.3f]\n", mean, target,
              *std::min_element(h.begin(), h.end()), *std::max_element(h.begin(), h.end()));
  // Bound: within 10 % of the target in the interior.
  EXPECT_NEAR(mean, target, 0.1 * target);
  EXPECT_THROW(sph::adapt_smoothing_lengths<3>(relation, 0, h), std::invalid_argument);
}

}  // namespace
