#include "libsph/core/kd_tree.hpp"

#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_sort.h>

#include "libsph/core/parallel.hpp"

namespace sph {
namespace {

/// Below this many points a subtree is built on the calling thread.
constexpr std::size_t parallel_build_threshold = 4096;
/// Target leaves per block of the relation's search pass (one thread per block, rows kept per block).
constexpr std::size_t leaves_per_block = 64;

/// The symmetric smoothing length h_ij = (h_i + h_j) / 2 (exact halving, the same in every pass).
inline Real pair_smoothing_length(Real h_i, Real h_j) { return Real(0.5) * (h_i + h_j); }

std::string number(Real x) { return std::to_string(x); }

}  // namespace

template <int Dim>
std::size_t KdTree<Dim>::node_count(std::size_t m) const {
  if (m <= leaf_size) return 1;
  const auto it = std::lower_bound(node_count_memo_.begin(), node_count_memo_.end(), std::make_pair(m, std::size_t(0)));
  return it->second;  // every size met in the build is in the memo
}

template <int Dim>
void KdTree<Dim>::build(std::span<const Vec<Dim>> positions) {
  build_entries(positions, {});
}

template <int Dim>
void KdTree<Dim>::build(std::span<const Vec<Dim>> positions, std::span<const Real> smoothing_length) {
  if (smoothing_length.size() != positions.size())
    throw std::invalid_argument("k-d tree: " + std::to_string(smoothing_length.size()) + " smoothing lengths for " +
                                std::to_string(positions.size()) + " positions");
  if (positions.empty()) {
    build_entries(positions, {});
    return;
  }
  build_entries(positions, smoothing_length);
}

template <int Dim>
void KdTree<Dim>::build_entries(std::span<const Vec<Dim>> positions, std::span<const Real> smoothing_length) {
  const std::size_t n = positions.size();
  if (n >= std::numeric_limits<Index>::max())
    throw std::invalid_argument("k-d tree: " + std::to_string(n) + " points exceed the 32-bit particle index");
  const std::size_t bad_x = first_index_where(n, [&](std::size_t i) { return !positions[i].allFinite(); });
  if (bad_x < n) throw std::invalid_argument("k-d tree: the position of particle " + std::to_string(bad_x) + " is not finite");
  const bool with_h = !smoothing_length.empty();
  if (with_h) {
    const std::size_t bad_h = first_index_where(n, [&](std::size_t i) {
      const Real h = smoothing_length[i];
      return !(h > 0) || !std::isfinite(h);
    });
    if (bad_h < n)
      throw std::invalid_argument("k-d tree: smoothing length of particle " + std::to_string(bad_h) + " is " +
                                  number(smoothing_length[bad_h]) + " (must be positive and finite)");
  }
  entries_.resize(n);
  parallel_for(n, [&](std::size_t i) {
    entries_[i].x = positions[i];
    entries_[i].h = with_h ? smoothing_length[i] : Real(0);
    entries_[i].j = static_cast<Index>(i);
  });
  if (n == 0) {
    nodes_.clear();
    leaves_.clear();
    return;
  }
  // Node counts of the subtree sizes met in the build (at most two sizes per level: floor and ceil
  // of n / 2^level), so that each subtree knows where its right child goes before it is built.
  node_count_memo_.clear();
  auto count = [&](auto&& self, std::size_t m) -> std::size_t {
    if (m <= leaf_size) return 1;
    const auto it = std::lower_bound(node_count_memo_.begin(), node_count_memo_.end(), std::make_pair(m, std::size_t(0)));
    if (it != node_count_memo_.end() && it->first == m) return it->second;
    const std::size_t c = 1 + self(self, m / 2) + self(self, m - m / 2);
    node_count_memo_.insert(std::lower_bound(node_count_memo_.begin(), node_count_memo_.end(), std::make_pair(m, std::size_t(0))),
                            {m, c});
    return c;
  };
  nodes_.resize(count(count, n));
  build_node(0, 0, static_cast<Index>(n));
  // Preorder layout: the leaves in node order are the leaves from left to right.
  leaves_.clear();
  for (std::size_t k = 0; k < nodes_.size(); ++k)
    if (nodes_[k].leaf()) leaves_.push_back(static_cast<Index>(k));
}

template <int Dim>
void KdTree<Dim>::build_node(Index node_index, Index begin, Index end) {
  Node& node = nodes_[node_index];
  node.begin = begin;
  node.end = end;
  Vec<Dim> lower = entries_[begin].x, upper = entries_[begin].x;
  Real h_max = entries_[begin].h;
  for (Index k = begin + 1; k < end; ++k) {
    lower = lower.cwiseMin(entries_[k].x);
    upper = upper.cwiseMax(entries_[k].x);
    h_max = std::max(h_max, entries_[k].h);
  }
  node.lower = lower;
  node.upper = upper;
  node.h_max = h_max;
  const std::size_t m = end - begin;
  if (m <= leaf_size) {
    node.right = 0;
    return;
  }
  int axis = 0;
  for (int d = 1; d < Dim; ++d)
    if (upper[d] - lower[d] > upper[axis] - lower[axis]) axis = d;
  const Index mid = begin + static_cast<Index>(m / 2);
  // Ties broken by particle index: the lower half is one definite set of points.
  std::nth_element(entries_.begin() + begin, entries_.begin() + mid, entries_.begin() + end,
                   [axis](const Entry& a, const Entry& b) {
                     return a.x[axis] < b.x[axis] || (a.x[axis] == b.x[axis] && a.j < b.j);
                   });
  const Index left = node_index + 1;
  const Index right = static_cast<Index>(node_index + 1 + node_count(mid - begin));
  node.right = right;
  if (m >= parallel_build_threshold) {
    tbb::parallel_invoke([&] { build_node(left, begin, mid); }, [&] { build_node(right, mid, end); });
  } else {
    build_node(left, begin, mid);
    build_node(right, mid, end);
  }
}

template <int Dim>
std::size_t KdTree<Dim>::bytes() const {
  std::size_t b = nodes_.capacity() * sizeof(Node) + entries_.capacity() * sizeof(Entry) +
                  node_count_memo_.capacity() * sizeof(std::pair<std::size_t, std::size_t>) +
                  (grid_order.capacity() + grid_rank.capacity() + leaves_.capacity() + row_block.capacity()) * sizeof(Index) +
                  row_start.capacity() * sizeof(std::size_t) +
                  grid_key.capacity() * sizeof(std::uint64_t) + grid_count.capacity() * sizeof(std::size_t) +
                  block_rows.capacity() * sizeof(std::vector<Index>);
  for (const auto& rows : block_rows) b += rows.capacity() * sizeof(Index);
  return b;
}

template <int Dim>
void KdTree<Dim>::radius_query(const Vec<Dim>& x, Real radius, std::vector<Index>& out) const {
  if (!(radius >= 0) || !std::isfinite(radius))
    throw std::invalid_argument("k-d tree: query radius " + number(radius) + " must be non-negative and finite");
  if (!x.allFinite()) throw std::invalid_argument("k-d tree: query point is not finite");
  out.clear();
  const Real r2 = radius * radius;
  for_each_candidate(
      x, [radius](const Node&) { return radius; },
      [&](const Entry& e) {
        if ((x - e.x).squaredNorm() < r2) out.push_back(e.j);
      });
  std::sort(out.begin(), out.end());
}

namespace {

/// tree.grid_order and tree.grid_rank: the particles ordered as a cell-linked list of search radius
/// `cell_radius` orders them (CellLinkedList::rebuild, the same arithmetic): by linear cell index
/// of a grid anchored at the lower corner of the bounding box, then by particle index. A grid with
/// more than 2^62 cells (a search radius absurdly small for the extent, which the cell list itself
/// refuses) falls back to plain index order.
template <int Dim>
void grid_order(KdTree<Dim>& tree, std::span<const Vec<Dim>> positions, Real cell_radius) {
  const std::size_t n = positions.size();
  const Real cell_size = cell_radius * (Real(1) + Real(64) * std::numeric_limits<Real>::epsilon());
  Vec<Dim> lower = Vec<Dim>::Constant(std::numeric_limits<Real>::max());
  Vec<Dim> upper = Vec<Dim>::Constant(std::numeric_limits<Real>::lowest());
  for (const auto& x : positions) {
    lower = lower.cwiseMin(x);
    upper = upper.cwiseMax(x);
  }
  std::array<std::size_t, Dim> n_cells{};
  Real total_real = 1;
  for (int d = 0; d < Dim; ++d) total_real *= std::floor((upper[d] - lower[d]) / cell_size) + 1;
  auto& order = tree.grid_order;
  auto& rank = tree.grid_rank;
  order.resize(n);
  rank.resize(n);
  if (!(total_real <= Real(std::uint64_t(1) << 62))) {
    parallel_for(n, [&](std::size_t i) { order[i] = rank[i] = static_cast<Index>(i); });
    return;
  }
  std::size_t total = 1;
  for (int d = 0; d < Dim; ++d) {
    n_cells[d] = static_cast<std::size_t>(std::floor((upper[d] - lower[d]) / cell_size)) + 1;
    total *= n_cells[d];
  }
  auto& key = tree.grid_key;
  key.resize(n);
  parallel_for(n, [&](std::size_t i) {
    std::uint64_t cell = 0, stride = 1;
    for (int d = 0; d < Dim; ++d) {
      const Real c = std::floor((positions[i][d] - lower[d]) / cell_size);
      const Real limit = static_cast<Real>(n_cells[d]) + Real(2);
      const long cd = std::clamp<long>(static_cast<long>(std::clamp(c, -Real(2), limit)), 0,
                                       static_cast<long>(n_cells[d]) - 1);
      cell += static_cast<std::uint64_t>(cd) * stride;
      stride *= n_cells[d];
    }
    key[i] = cell;
  });
  if (total <= 4 * n + 1024) {
    // Counting sort by cell (stable: index order within a cell), as the cell list does.
    auto& start = tree.grid_count;
    start.assign(total + 1, 0);
    for (std::size_t i = 0; i < n; ++i) ++start[key[i] + 1];
    for (std::size_t c = 0; c < total; ++c) start[c + 1] += start[c];
    for (std::size_t i = 0; i < n; ++i) order[start[key[i]]++] = static_cast<Index>(i);
  } else {
    // A sparse grid: comparison sort on (cell, index), a strict total order, so one result.
    parallel_for(n, [&](std::size_t i) { order[i] = static_cast<Index>(i); });
    tbb::parallel_sort(order.begin(), order.end(),
                       [&](Index a, Index b) { return key[a] < key[b] || (key[a] == key[b] && a < b); });
  }
  parallel_for(n, [&](std::size_t k) { rank[order[k]] = static_cast<Index>(k); });
}

template <int Dim, class Kernel>
void fill_variable_h(InnerRelation<Dim>& relation, std::span<const Vec<Dim>> positions,
                     std::span<const Real> smoothing_length, KdTree<Dim>& tree) {
  const std::size_t n = positions.size();
  if (smoothing_length.size() != n)
    throw std::invalid_argument("rebuild_inner_relation_variable_h: " + std::to_string(smoothing_length.size()) +
                                " smoothing lengths for " + std::to_string(n) + " positions");
  const std::size_t bad_h = first_index_where(n, [&](std::size_t i) {
    const Real h = smoothing_length[i];
    return !(h > 0) || !std::isfinite(h);
  });
  if (bad_h < n)
    throw std::invalid_argument("rebuild_inner_relation_variable_h: smoothing length of particle " +
                                std::to_string(bad_h) + " is " + number(smoothing_length[bad_h]) +
                                " (must be positive and finite)");
  const std::size_t bad_x = first_index_where(n, [&](std::size_t i) { return !positions[i].allFinite(); });
  if (bad_x < n)
    throw std::invalid_argument("rebuild_inner_relation_variable_h: the position of particle " + std::to_string(bad_x) +
                                " is not finite");

  relation.image_origin.clear();
  if (n == 0) {
    relation.smoothing_length = 0;
    relation.kernel_value_at_zero = 0;
    relation.offsets.assign(1, 0);
    relation.row_count.clear();
    relation.neighbour.clear();
    relation.kernel_value.clear();
    relation.kernel_derivative.clear();
    relation.distance.clear();
    relation.unit_vector.clear();
    return;
  }
  const Real h_max = parallel_max(n, Real(0), [&](std::size_t i) { return smoothing_length[i]; });
  relation.smoothing_length = h_max;
  relation.kernel_value_at_zero = Kernel::normalisation(h_max) * Kernel::shape(Real(0));

  tree.build(positions, smoothing_length);
  grid_order(tree, positions, Kernel::support_radius(h_max));
  const auto& rank = tree.grid_rank;

  // Pass 1, one thread per block of target leaves. The candidates of a whole leaf are gathered
  // once (every point of a node within kappa (h_max(leaf) + h_max(node)) / 2 of the leaf's box) and
  // sorted by grid rank; each target of the leaf then keeps, in that order, the candidates that
  // pass the pair rule, so its row comes out sorted.
  using Entry = typename KdTree<Dim>::Entry;
  using Node = typename KdTree<Dim>::Node;
  const auto leaves = tree.leaves();
  const auto entries = tree.entries();
  const auto nodes = tree.nodes();
  const std::size_t n_blocks = (leaves.size() + leaves_per_block - 1) / leaves_per_block;
  tree.block_rows.resize(n_blocks);
  tree.row_block.resize(n);
  tree.row_start.resize(n);
  auto& count = relation.row_count;
  count.resize(n);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n_blocks, 1), [&](const tbb::blocked_range<std::size_t>& range) {
    thread_local std::vector<std::uint64_t> keys;  // (rank << 32) | position among the candidates
    thread_local std::vector<Entry> candidates, sorted;
    for (std::size_t b = range.begin(); b != range.end(); ++b) {
      auto& rows = tree.block_rows[b];
      rows.clear();
      const std::size_t last = std::min(leaves.size(), (b + 1) * leaves_per_block);
      for (std::size_t l = b * leaves_per_block; l < last; ++l) {
        const Node& leaf = nodes[leaves[l]];
        candidates.clear();
        tree.for_each_candidate_leaf(
            leaf.lower, leaf.upper,
            [&leaf](const Node& node) { return Kernel::support_radius(pair_smoothing_length(leaf.h_max, node.h_max)); },
            [&](const Node& node) { candidates.insert(candidates.end(), entries.begin() + node.begin, entries.begin() + node.end); });
        keys.resize(candidates.size());
        for (std::size_t c = 0; c < candidates.size(); ++c) keys[c] = (std::uint64_t(rank[candidates[c].j]) << 32) | c;
        std::sort(keys.begin(), keys.end());
        sorted.resize(candidates.size());
        for (std::size_t c = 0; c < candidates.size(); ++c) sorted[c] = candidates[keys[c] & 0xffffffffu];
        for (Index t = leaf.begin; t < leaf.end; ++t) {
          const Entry& target = entries[t];
          const Index i = target.j;
          const Vec<Dim>& x_i = positions[i];
          const Real h_i = smoothing_length[i];
          const std::size_t start = rows.size();
          for (const Entry& e : sorted) {
            if (e.j == i) continue;
            const Real r2 = (x_i - e.x).squaredNorm();
            const Real support = Kernel::support_radius(pair_smoothing_length(h_i, e.h));
            if (r2 < support * support) rows.push_back(e.j);
          }
          tree.row_block[i] = static_cast<Index>(b);
          tree.row_start[i] = start;
          count[i] = rows.size() - start;
        }
      }
    }
  });

  relation.size_rows(count);

  // Pass 2: the pair data, with the same expressions as the cell-list relation evaluated at h_ij
  // (so that a constant h gives the same bits).
  parallel_for(n, [&](std::size_t i) {
    const Index* row = tree.block_rows[tree.row_block[i]].data() + tree.row_start[i];
    const Real h_i = smoothing_length[i];
    // Kernel scales of the last h_ij, recomputed only when h_ij changes (never at constant h).
    Real h = -1, normalisation = 0, inverse_h = 0, derivative_scale = 0;
    for (std::size_t k = relation.offsets[i], c = 0; k < relation.offsets[i + 1]; ++k, ++c) {
      const Index j = row[c];
      const Vec<Dim> x_ij = positions[i] - positions[j];
      const Real r2 = x_ij.squaredNorm();
      const Real r = std::sqrt(r2);
      const Real h_ij = pair_smoothing_length(h_i, smoothing_length[j]);
      if (h_ij != h) {
        h = h_ij;
        normalisation = Kernel::normalisation(h);
        inverse_h = Real(1) / h;
        derivative_scale = normalisation * inverse_h;
      }
      relation.neighbour[k] = j;
      relation.distance[k] = r;
      const Real q = r * inverse_h;
      relation.kernel_value[k] = normalisation * Kernel::shape(q);
      relation.kernel_derivative[k] = derivative_scale * Kernel::shape_derivative(q);
      relation.unit_vector[k] = r > 0 ? Vec<Dim>(x_ij / r) : Vec<Dim>::Zero();
    }
  });
}

}  // namespace

template <int Dim>
void rebuild_inner_relation_variable_h(InnerRelation<Dim>& relation, std::span<const Vec<Dim>> positions,
                                       std::span<const Real> smoothing_length, const AnyKernel<Dim>& kernel,
                                       KdTree<Dim>& tree) {
  std::visit([&]<class K>(const K&) { fill_variable_h<Dim, K>(relation, positions, smoothing_length, tree); }, kernel);
}

template <int Dim>
std::vector<std::vector<Index>> brute_force_neighbours_variable_h(std::span<const Vec<Dim>> positions,
                                                                  std::span<const Real> smoothing_length,
                                                                  const AnyKernel<Dim>& kernel) {
  if (smoothing_length.size() != positions.size())
    throw std::invalid_argument("brute_force_neighbours_variable_h: " + std::to_string(smoothing_length.size()) +
                                " smoothing lengths for " + std::to_string(positions.size()) + " positions");
  std::vector<std::vector<Index>> rows(positions.size());
  std::visit(
      [&]<class K>(const K&) {
        for (std::size_t i = 0; i < positions.size(); ++i)
          for (std::size_t j = 0; j < positions.size(); ++j) {
            if (i == j) continue;
            const Real support = K::support_radius(pair_smoothing_length(smoothing_length[i], smoothing_length[j]));
            if ((positions[i] - positions[j]).squaredNorm() < support * support)
              rows[i].push_back(static_cast<Index>(j));
          }
      },
      kernel);
  return rows;
}

template <int Dim>
void adapt_smoothing_lengths(const InnerRelation<Dim>& relation, Real target_neighbours,
                             std::span<Real> smoothing_length) {
  if (!(target_neighbours > 0) || !std::isfinite(target_neighbours))
    throw std::invalid_argument("adapt_smoothing_lengths: target_neighbours " + number(target_neighbours) +
                                " must be positive and finite");
  if (smoothing_length.size() != relation.n_targets())
    throw std::invalid_argument("adapt_smoothing_lengths: " + std::to_string(smoothing_length.size()) +
                                " smoothing lengths for a relation of " + std::to_string(relation.n_targets()) +
                                " particles");
  parallel_for(smoothing_length.size(), [&](std::size_t i) {
    const std::size_t n_i = relation.n_neighbours(i);
    const Real factor = n_i == 0 ? Real(2)
                                 : std::clamp(std::pow(target_neighbours / static_cast<Real>(n_i), Real(1) / Real(Dim)),
                                              Real(0.5), Real(2));
    smoothing_length[i] *= factor;
  });
}

template class KdTree<2>;
template class KdTree<3>;
template void rebuild_inner_relation_variable_h<2>(InnerRelation<2>&, std::span<const Vec<2>>, std::span<const Real>,
                                                   const AnyKernel<2>&, KdTree<2>&);
template void rebuild_inner_relation_variable_h<3>(InnerRelation<3>&, std::span<const Vec<3>>, std::span<const Real>,
                                                   const AnyKernel<3>&, KdTree<3>&);
template std::vector<std::vector<Index>> brute_force_neighbours_variable_h<2>(std::span<const Vec<2>>,
                                                                              std::span<const Real>,
                                                                              const AnyKernel<2>&);
template std::vector<std::vector<Index>> brute_force_neighbours_variable_h<3>(std::span<const Vec<3>>,
                                                                              std::span<const Real>,
                                                                              const AnyKernel<3>&);
template void adapt_smoothing_lengths<2>(const InnerRelation<2>&, Real, std::span<Real>);
template void adapt_smoothing_lengths<3>(const InnerRelation<3>&, Real, std::span<Real>);

}  // namespace sph
