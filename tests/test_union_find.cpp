// The one union-find (libsph/core/union_find.hpp) against a brute-force labelling of the same
// random graph: the sets, their count and sizes, and labels that do not depend on the union order.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <utility>
#include <vector>

#include "libsph/core/union_find.hpp"

namespace {

// Per vertex, the smallest vertex reachable from it (repeated relaxation over the edges).
std::vector<std::size_t> brute_force_labels(std::size_t n, const std::vector<std::pair<std::size_t, std::size_t>>& edges) {
  std::vector<std::size_t> label(n);
  for (std::size_t i = 0; i < n; ++i) label[i] = i;
  for (bool changed = true; changed;) {
    changed = false;
    for (const auto& [a, b] : edges) {
      const std::size_t m = std::min(label[a], label[b]);
      if (label[a] != m || label[b] != m) {
        label[a] = label[b] = m;
        changed = true;
      }
    }
  }
  return label;
}

TEST(UnionFind, StartsWithSingletons) {
  sph::UnionFind sets(5);
  EXPECT_EQ(sets.n_elements(), 5u);
  EXPECT_EQ(sets.n_sets(), 5u);
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(sets.find(i), i);
    EXPECT_EQ(sets.set_size(i), 1u);
  }
  EXPECT_EQ(sets.smallest_member_labels(), (std::vector<std::size_t>{0, 1, 2, 3, 4}));
  sph::UnionFind none(0);
  EXPECT_EQ(none.n_sets(), 0u);
  EXPECT_TRUE(none.smallest_member_labels().empty());
}

TEST(UnionFind, UniteReportsWhetherSetsWereMerged) {
  sph::UnionFind sets(6);
  EXPECT_TRUE(sets.unite(4, 1));
  EXPECT_TRUE(sets.unite(1, 5));
  EXPECT_FALSE(sets.unite(5, 4));
  EXPECT_FALSE(sets.unite(2, 2));
  EXPECT_EQ(sets.n_sets(), 4u);
  EXPECT_TRUE(sets.same_set(4, 5));
  EXPECT_FALSE(sets.same_set(0, 5));
  EXPECT_EQ(sets.set_size(5), 3u);
  EXPECT_EQ(sets.smallest_member_labels(), (std::vector<std::size_t>{0, 1, 2, 3, 1, 1}));
}

TEST(UnionFind, MatchesBruteForceOnRandomGraphsWhateverTheUnionOrder) {
  std::mt19937 random(20240611);
  for (const std::size_t n : {1u, 2u, 17u, 300u, 2000u}) {
    for (const double edges_per_vertex : {0.2, 0.5, 1.0, 3.0}) {
      std::uniform_int_distribution<std::size_t> vertex(0, n - 1);
      std::vector<std::pair<std::size_t, std::size_t>> edges(static_cast<std::size_t>(edges_per_vertex * static_cast<double>(n)));
      for (auto& e : edges) e = {vertex(random), vertex(random)};
      const auto expected = brute_force_labels(n, edges);
      std::vector<std::size_t> size_of_label(n, 0);
      for (const std::size_t l : expected) ++size_of_label[l];
      const auto unused_labels = static_cast<std::size_t>(std::count(size_of_label.begin(), size_of_label.end(), std::size_t{0}));

      for (int order = 0; order < 2; ++order) {
        if (order == 1) std::shuffle(edges.begin(), edges.end(), random);
        sph::UnionFind sets(n);
        for (const auto& [a, b] : edges) sets.unite(a, b);
        EXPECT_EQ(sets.smallest_member_labels(), expected) << "n = " << n;
        EXPECT_EQ(sets.n_sets(), n - unused_labels) << "n = " << n;
        for (std::size_t i = 0; i < n; ++i) {
          EXPECT_EQ(sets.set_size(i), size_of_label[expected[i]]);
          EXPECT_EQ(sets.same_set(i, expected[i]), true);
        }
      }
    }
  }
}

}  // namespace
