#pragma once
// A k-d tree for neighbour search with variable smoothing lengths, and the inner relation built
// with it.
//
// Tree (Bentley 1975, Commun. ACM 18:509; Friedman, Bentley & Finkel 1977, ACM Trans. Math. Softw.
// 3:209): every node holds a contiguous range of the points, stored in tree order, and the tight
// axis-aligned bounding box [lower, upper] of that range. A node of more than `leaf_size` points
// is split at the median of its widest box axis (std::nth_element, O(m) for m points, with ties
// broken by particle index so that the split is one definite set of points), the lower half going
// to the left child. Each level costs O(n) and there are log2(n / leaf_size) levels: O(n log n).
// The median split keeps the tree balanced whatever the point distribution (a centrally
// concentrated cloud, coincident points), which a uniform cell grid does not.
//
// Radius query at x with radius R: a node is skipped when its box lies at least R from x,
//   d_box(x)^2 = sum_d max(lower_d - x_d, 0, x_d - upper_d)^2 >= R^2,
// otherwise its children (or, at a leaf, its points) are visited. For k results the cost is
// O(log n + k) on well-spread points (Friedman, Bentley & Finkel 1977).
//
// Variable smoothing lengths. The pair (i, j), j != i, is a neighbour when
//   |x_i - x_j| < kappa h_ij,   h_ij = (h_i + h_j) / 2,
// with kappa h the kernel support (kappa = 2 for the kernels of kernels.hpp), and the kernel value
// and radial derivative are W(r_ij, h_ij) and dW/dr(r_ij, h_ij). The arithmetic mean keeps the
// relation symmetric (j is a neighbour of i exactly when i is a neighbour of j, so a pairwise
// force is antisymmetric and momentum is conserved): Hernquist & Katz 1989, ApJS 70:419 (TREESPH, the
// symmetrised smoothing length); Benz 1990, in "The Numerical Modelling of Nonlinear Stellar
// Pulsations", NATO ASI C 302:269. Each node also stores the largest h of its points, h_max(node).
// The relation is searched one leaf of targets at a time: a node is pruned when the distance
// between its box and the leaf's box is at least kappa (h_max(leaf) + h_max(node)) / 2, which can
// never exclude a neighbour since h_i <= h_max(leaf) and h_j <= h_max(node); the candidates found
// for the leaf are sorted once into the row order, and each target of the leaf keeps those that
// pass its exact pair rule. With the global h_max in place of h_max(node) this would be the search
// radius kappa (h_i + h_max) / 2 of every particle; the per-node bound is tighter, so a centrally
// concentrated cloud does not pay for its largest h everywhere.
//
// Neighbour order. rebuild_inner_relation_variable_h orders each row as the cell-linked list
// orders it (neighbour_relation.hpp): by the cell of a grid of cell size kappa h_max anchored at the
// lower corner of the points' bounding box (cells in memory order), then by source index. With a
// constant h this is exactly the cell list's grid, so the two relations agree entry by entry, bit
// for bit, and a body can switch between them. The radius query returns indices in ascending order.
// Neither order depends on the tree layout.
//
// Determinism: the two subtrees of a node of more than a few thousand points are built in
// parallel, each writing only its own nodes (their places fixed beforehand by the subtree sizes)
// and its own range of points, so the tree is the same for any number of threads; every relation
// row is searched and filled by one thread, from data of its own leaf, so the relation is bitwise
// the same for any number of threads. Storage (nodes, points, rows, scratch) is reused by rebuilds.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include "libsph/core/kernels.hpp"
#include "libsph/core/neighbour_relation.hpp"
#include "libsph/core/types.hpp"

namespace sph {

template <int Dim>
class KdTree {
 public:
  /// Largest number of points in a leaf (leaves hold between leaf_size / 2 and leaf_size points).
  static constexpr std::size_t leaf_size = 8;

  struct Node {
    Vec<Dim> lower, upper;  ///< tight bounding box of the node's points
    Real h_max = 0;         ///< largest smoothing length of the node's points (0 without lengths)
    Index begin = 0, end = 0;  ///< the node's points are entries [begin, end)
    Index right = 0;           ///< right child (the left child is the next node); 0 at a leaf
    bool leaf() const { return right == 0; }
  };
  struct Entry {
    Vec<Dim> x;   ///< position
    Real h = 0;   ///< smoothing length (0 when built without)
    Index j = 0;  ///< particle index
  };

  KdTree() = default;
  explicit KdTree(std::span<const Vec<Dim>> positions) { build(positions); }

  /// Builds the tree over `positions`, reusing the storage. Throws std::invalid_argument naming the
  /// first particle whose position is not finite.
  void build(std::span<const Vec<Dim>> positions);
  /// Builds the tree and records the largest smoothing length of every node. Throws
  /// std::invalid_argument naming the sizes when they differ, or the first particle whose position
  /// is not finite or whose smoothing length is not a positive finite number.
  void build(std::span<const Vec<Dim>> positions, std::span<const Real> smoothing_length);

  std::size_t size() const { return entries_.size(); }
  bool empty() const { return entries_.empty(); }
  std::size_t n_nodes() const { return nodes_.size(); }
  /// Bytes held by the tree and its scratch.
  std::size_t bytes() const;

  /// Indices j with |x - x_j| < radius, in ascending order, written to `out` (which is cleared).
  void radius_query(const Vec<Dim>& x, Real radius, std::vector<Index>& out) const;
  std::vector<Index> radius_query(const Vec<Dim>& x, Real radius) const {
    std::vector<Index> out;
    radius_query(x, radius, out);
    return out;
  }

  /// Calls visit(entry) for every point of every leaf whose box is nearer to x than
  /// node_radius(node) (a superset of the points within that radius), in tree order.
  /// node_radius must not be smaller than the search radius of any point of the node.
  template <class NodeRadius, class Visit>
  void for_each_candidate(const Vec<Dim>& x, NodeRadius&& node_radius, Visit&& visit) const {
    for_each_candidate_leaf(x, x, node_radius, [&](const Node& leaf) {
      for (Index k = leaf.begin; k < leaf.end; ++k) visit(entries_[k]);
    });
  }

  /// Calls visit(leaf) for every leaf whose box is nearer to the box [lower, upper] than
  /// node_radius(node), in tree order: the candidates of every point of that box.
  template <class NodeRadius, class Visit>
  void for_each_candidate_leaf(const Vec<Dim>& lower, const Vec<Dim>& upper, NodeRadius&& node_radius,
                               Visit&& visit) const {
    if (nodes_.empty()) return;
    std::array<Index, 128> stack;  // at most one pending right child per level, depth < 64
    std::size_t top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Index index = stack[--top];
      const Node& node = nodes_[index];
      const Real r = node_radius(node);
      // Pruning tolerates a few ulps (the box distance sums in another order than |x - x_j|^2), so
      // it never drops a point that the caller's exact test would keep.
      if (box_distance2(lower, upper, node) > r * r * prune_tolerance) continue;
      if (node.leaf()) {
        visit(node);
      } else {
        stack[top++] = node.right;  // visited after the left child
        stack[top++] = index + 1;
      }
    }
  }

  /// The leaves in tree order.
  std::span<const Index> leaves() const { return leaves_; }
  std::span<const Node> nodes() const { return nodes_; }
  /// The points in tree order (leaf by leaf).
  std::span<const Entry> entries() const { return entries_; }

  // Scratch of rebuild_inner_relation_variable_h, kept here so that rebuilds reuse it.
  std::vector<std::vector<Index>> block_rows;  ///< neighbours of each block of target leaves
  std::vector<Index> row_block;                 ///< block holding each particle's row
  std::vector<std::size_t> row_start;           ///< where the row starts in its block
  std::vector<Index> grid_order;                ///< particles in grid order (cell, then index)
  std::vector<Index> grid_rank;                 ///< inverse of grid_order
  std::vector<std::uint64_t> grid_key;          ///< linear grid cell of each particle
  std::vector<std::size_t> grid_count;          ///< counting-sort scratch

 private:
  static constexpr Real prune_tolerance = Real(1) + Real(64) * std::numeric_limits<Real>::epsilon();

  /// Squared distance between the box [lower, upper] and the node's box (0 if they overlap).
  static Real box_distance2(const Vec<Dim>& lower, const Vec<Dim>& upper, const Node& node) {
    Real d2 = 0;
    for (int d = 0; d < Dim; ++d) {
      const Real t = std::max({node.lower[d] - upper[d], lower[d] - node.upper[d], Real(0)});
      d2 += t * t;
    }
    return d2;
  }
  void build_entries(std::span<const Vec<Dim>> positions, std::span<const Real> smoothing_length);
  void build_node(Index node, Index begin, Index end);
  std::size_t node_count(std::size_t m) const;

  std::vector<Node> nodes_;
  std::vector<Entry> entries_;
  std::vector<Index> leaves_;
  std::vector<std::pair<std::size_t, std::size_t>> node_count_memo_;  ///< (points, nodes), sorted
};

/// Rebuilds `relation` over `positions` with one smoothing length per particle: the pair (i, j),
/// j != i, is kept when |x_i - x_j| < support(h_ij) with h_ij = (h_i + h_j) / 2, and caches the
/// same pair data as rebuild_inner_relation (neighbour, distance, unit vector, W(r_ij, h_ij),
/// dW/dr(r_ij, h_ij)) in the same row order (grid cell of size support(h_max), then index; see the
/// header comment). relation.smoothing_length is set to h_max and relation.kernel_value_at_zero to
/// W(0, h_max); with variable h a self term W(0, h_i) is the caller's to evaluate. `tree` is
/// rebuilt (it holds the scratch). With a constant h the result is bitwise that of
/// rebuild_inner_relation. Throws std::invalid_argument on a size mismatch (naming both sizes) or
/// naming the first particle with a non-finite position or a smoothing length that is not positive
/// and finite.
template <int Dim>
void rebuild_inner_relation_variable_h(InnerRelation<Dim>& relation, std::span<const Vec<Dim>> positions,
                                       std::span<const Real> smoothing_length, const AnyKernel<Dim>& kernel,
                                       KdTree<Dim>& tree);

/// Brute-force O(n^2) rows of the variable-h pair rule (|x_ij| < support((h_i + h_j) / 2), j != i),
/// each in increasing index (for tests).
template <int Dim>
std::vector<std::vector<Index>> brute_force_neighbours_variable_h(std::span<const Vec<Dim>> positions,
                                                                  std::span<const Real> smoothing_length,
                                                                  const AnyKernel<Dim>& kernel);

/// Smoothing lengths that bring every particle towards `target_neighbours` neighbours:
///   h_new = h (N_target / N_i)^(1/Dim),
/// the factor clamped to [1/2, 2] (and to 2 when N_i = 0), from the neighbour counts N_i of
/// `relation` (so N_i counts with the pair rule of the relation's h). The fixed-neighbour-number
/// adaptation of Hernquist & Katz 1989, ApJS 70:419 (the kernel volume, proportional to
/// h^Dim, scaled to hold N_target neighbours), here as one fixed-point step; iterate with rebuilds. Throws std::invalid_argument when the sizes differ or the target is not
/// positive.
template <int Dim>
void adapt_smoothing_lengths(const InnerRelation<Dim>& relation, Real target_neighbours,
                             std::span<Real> smoothing_length);

extern template class KdTree<2>;
extern template class KdTree<3>;
extern template void rebuild_inner_relation_variable_h<2>(InnerRelation<2>&, std::span<const Vec<2>>,
                                                          std::span<const Real>, const AnyKernel<2>&, KdTree<2>&);
extern template void rebuild_inner_relation_variable_h<3>(InnerRelation<3>&, std::span<const Vec<3>>,
                                                          std::span<const Real>, const AnyKernel<3>&, KdTree<3>&);
extern template std::vector<std::vector<Index>> brute_force_neighbours_variable_h<2>(std::span<const Vec<2>>,
                                                                                     std::span<const Real>,
                                                                                     const AnyKernel<2>&);
extern template std::vector<std::vector<Index>> brute_force_neighbours_variable_h<3>(std::span<const Vec<3>>,
                                                                                     std::span<const Real>,
                                                                                     const AnyKernel<3>&);
extern template void adapt_smoothing_lengths<2>(const InnerRelation<2>&, Real, std::span<Real>);
extern template void adapt_smoothing_lengths<3>(const InnerRelation<3>&, Real, std::span<Real>);

}  // namespace sph
