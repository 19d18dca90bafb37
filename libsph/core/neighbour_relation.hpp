#pragma once
// Neighbour relations in compressed-row form: for each target particle i, the source particles j
// with |x_i - x_j| < support radius, in a fixed order (cell stencil order, then source index), with
// the kernel value W_ij, the radial derivative dW/dr(r_ij), the distance r_ij and the unit vector
// e_ij = (x_i - x_j) / r_ij cached per pair (e_ij = 0 for coincident points).
//
// InnerRelation: a particle set with itself (i is not its own neighbour).
// ContactRelation: targets of one set, sources of another, with the contact's smoothing length
// (by default the larger of the two sets' smoothing lengths, as for multi-resolution coupling).
//
// Both are built in two passes (count per target, keeping what it finds; exclusive scan; fill from
// what was kept, searching again only for a row longer than the kept stride), each target writing only
// its own row: no atomics, and the same lists for any number of threads. A relation is rebuilt in
// place (rebuild_*_relation) when its particles move: the cell list, the row offsets and the pair
// arrays keep their storage, so a rebuild allocates nothing once the pair count stops growing.
//
// Periodic boundaries: with a PeriodicBox, sources near a periodic face are also seen through the
// opposite face (as images shifted by the period); a pair with an image stores the index of the
// original source and the distance and unit vector to the image, so operators that read only the
// cached pair geometry (fluids) need not know about periodicity. Every period must be at least two
// kernel supports, so that no particle sees itself or one source twice.
//
// Distribution: targets and sources are plain position spans, so a partition's relation is built
// over its owned particles as targets and owned plus ghost particles as sources (the ParticleSet
// overload of build_inner_relation does this, on the grid and in the order of partition.hpp); no
// code here assumes that a source is owned (docs/architecture.md).

#include <array>
#include <cmath>
#include <span>
#include <vector>

#include "libsph/core/cell_linked_list.hpp"
#include "libsph/core/kernels.hpp"
#include "libsph/core/particles.hpp"
#include "libsph/core/types.hpp"

namespace sph {

/// An axis-aligned box with periodic axes (the others are left open).
template <int Dim>
struct PeriodicBox {
  Vec<Dim> lower = Vec<Dim>::Zero();
  Vec<Dim> upper = Vec<Dim>::Zero();
  std::array<bool, Dim> periodic{};
  bool any() const {
    for (bool p : periodic)
      if (p) return true;
    return false;
  }
  Vec<Dim> period() const { return upper - lower; }
  /// x brought back into the box along the periodic axes.
  Vec<Dim> wrap(Vec<Dim> x) const {
    for (int d = 0; d < Dim; ++d) {
      if (!periodic[d]) continue;
      const Real L = upper[d] - lower[d];
      x[d] -= L * std::floor((x[d] - lower[d]) / L);
      if (x[d] >= upper[d]) x[d] -= L;  // round-off of the floor
    }
    return x;
  }
};

/// One pair of a row: its place k in the pair arrays and its source j = neighbour[k].
struct NeighbourPair {
  std::size_t k;
  Index j;
};

/// The pairs of one target in the relation's order, as (k, j):
///   for (const auto [k, j] : relation.row(i)) sum += volume[j] * relation.kernel_value[k];
/// is the loop for (k = offsets[i]; k < offsets[i + 1]; ++k) { j = neighbour[k]; ... }.
class NeighbourRow {
 public:
  class iterator {
   public:
    iterator(const Index* neighbour, std::size_t k) : neighbour_(neighbour), k_(k) {}
    NeighbourPair operator*() const { return {k_, neighbour_[k_]}; }
    iterator& operator++() {
      ++k_;
      return *this;
    }
    bool operator!=(const iterator& other) const { return k_ != other.k_; }
    bool operator==(const iterator& other) const { return k_ == other.k_; }

   private:
    const Index* neighbour_;
    std::size_t k_;
  };
  NeighbourRow(const Index* neighbour, std::size_t begin, std::size_t end) : neighbour_(neighbour), begin_(begin), end_(end) {}
  iterator begin() const { return {neighbour_, begin_}; }
  iterator end() const { return {neighbour_, end_}; }
  std::size_t size() const { return end_ - begin_; }
  bool empty() const { return begin_ == end_; }

 private:
  const Index* neighbour_;
  std::size_t begin_, end_;
};

template <int Dim>
struct NeighbourList {
  Real smoothing_length = 0;
  Real kernel_value_at_zero = 0;       ///< W(0, h)
  std::vector<std::size_t> offsets;    ///< row i is [offsets[i], offsets[i+1])
  std::vector<Index> neighbour;        ///< source index j of each pair
  std::vector<Real> kernel_value;      ///< W(r_ij, h)
  std::vector<Real> kernel_derivative; ///< dW/dr at r_ij (<= 0)
  std::vector<Real> distance;          ///< r_ij
  std::vector<Vec<Dim>> unit_vector;   ///< e_ij = (x_i - x_j) / r_ij

  std::size_t n_targets() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  std::size_t n_pairs() const { return neighbour.size(); }
  std::size_t n_neighbours(std::size_t i) const { return offsets[i + 1] - offsets[i]; }
  /// The pairs (k, j) of target i (NeighbourRow).
  NeighbourRow row(std::size_t i) const { return {neighbour.data(), offsets[i], offsets[i + 1]}; }
  /// Sets the row offsets from each row's neighbour count (an exclusive scan) and sizes the pair
  /// arrays to match.
  void size_rows(std::span<const std::size_t> count) {
    const std::size_t n = count.size();
    offsets.assign(n + 1, 0);
    for (std::size_t i = 0; i < n; ++i) offsets[i + 1] = offsets[i] + count[i];
    const std::size_t n_pairs = offsets[n];
    neighbour.resize(n_pairs);
    kernel_value.resize(n_pairs);
    kernel_derivative.resize(n_pairs);
    distance.resize(n_pairs);
    unit_vector.resize(n_pairs);
  }
  /// Bytes held per stored pair (index and cached kernel data).
  static constexpr std::size_t bytes_per_pair = sizeof(Index) + 3 * sizeof(Real) + sizeof(Vec<Dim>);
  /// Bytes held: the pairs, the row offsets, and the cell list and counts kept for rebuilds.
  std::size_t bytes() const {
    return n_pairs() * bytes_per_pair + (offsets.size() + row_count.capacity()) * sizeof(std::size_t) + cells.bytes() + candidates.capacity() * sizeof(Index) +
           extended_sources.capacity() * sizeof(Vec<Dim>) + image_origin.capacity() * sizeof(Index);
  }

  // Reused by rebuilds.
  CellLinkedList<Dim> cells;
  std::vector<std::size_t> row_count;
  std::vector<Index> candidates;           ///< neighbours found by the counting pass, a fixed stride per
                                           ///< row (48 in 2D, 128 in 3D), kept by the rebuild_* functions only
  std::vector<Vec<Dim>> extended_sources;  ///< sources, then their periodic images
  std::vector<Index> image_origin;         ///< the source of each image
};

template <int Dim>
struct InnerRelation : NeighbourList<Dim> {};

template <int Dim>
struct ContactRelation : NeighbourList<Dim> {};

/// The order in which the sources of a cell enter a row, which decides the bits of every pair sum:
///   by_index     by source index: for particles that keep their place in memory (solids, walls);
///   by_position  lexicographically by position (x, then y, then z; ties by index): a row is then the
///                same wherever its particles sit in memory, so a fluid that is re-sorted along the
///                cells, or whose particles migrate between ranks, sums its pairs in the same order
///                (re-sorting changes the speed only; any rank count gives the bits of one rank).
enum class SourceOrder { by_index, by_position };

/// Neighbours of every particle of `positions` among the same particles.
template <int Dim>
InnerRelation<Dim> build_inner_relation(std::span<const Vec<Dim>> positions, const AnyKernel<Dim>& kernel,
                                        Real smoothing_length);

/// Neighbours of the particles a rank computes (its owned ones; all of them in a serial run) among
/// all its local particles; for a distributed set, rows in the order of a serial run (partition.hpp).
template <int Dim>
InnerRelation<Dim> build_inner_relation(const ParticleSet<Dim>& particles, const AnyKernel<Dim>& kernel,
                                        Real smoothing_length);

/// Neighbours of every target among the sources (two different particle sets).
template <int Dim>
ContactRelation<Dim> build_contact_relation(std::span<const Vec<Dim>> targets, std::span<const Vec<Dim>> sources,
                                            const AnyKernel<Dim>& kernel, Real smoothing_length);

/// Rebuilds the inner relation at new positions, reusing its storage.
template <int Dim>
void rebuild_inner_relation(InnerRelation<Dim>& relation, std::span<const Vec<Dim>> positions,
                            const AnyKernel<Dim>& kernel, Real smoothing_length);

/// Rebuilds the contact relation at new positions, reusing its storage.
template <int Dim>
void rebuild_contact_relation(ContactRelation<Dim>& relation, std::span<const Vec<Dim>> targets,
                              std::span<const Vec<Dim>> sources, const AnyKernel<Dim>& kernel, Real smoothing_length,
                              SourceOrder order = SourceOrder::by_index);

/// Rebuilds the inner relation with periodic images across the periodic axes of `box`.
template <int Dim>
void rebuild_inner_relation(InnerRelation<Dim>& relation, std::span<const Vec<Dim>> positions,
                            const AnyKernel<Dim>& kernel, Real smoothing_length, const PeriodicBox<Dim>& box);

/// Rebuilds the inner relation of a particle set that moves (fluids): the particles a rank computes
/// (its owned ones; all in a serial run) among all its local ones, with periodic images across the
/// periodic axes of `box` (a serial set only), sources in `order`.
template <int Dim>
void rebuild_inner_relation(InnerRelation<Dim>& relation, const ParticleSet<Dim>& particles, const AnyKernel<Dim>& kernel,
                            Real smoothing_length, const PeriodicBox<Dim>& box, SourceOrder order);

/// Rebuilds the contact relation with periodic images of the sources across the periodic axes of `box`.
template <int Dim>
void rebuild_contact_relation(ContactRelation<Dim>& relation, std::span<const Vec<Dim>> targets,
                              std::span<const Vec<Dim>> sources, const AnyKernel<Dim>& kernel, Real smoothing_length,
                              const PeriodicBox<Dim>& box);

/// Brute-force O(N_t N_s) neighbour indices, row by row in increasing source index (for tests).
template <int Dim>
std::vector<std::vector<Index>> brute_force_neighbours(std::span<const Vec<Dim>> targets,
                                                       std::span<const Vec<Dim>> sources, Real support_radius,
                                                       bool exclude_self);

extern template InnerRelation<2> build_inner_relation<2>(std::span<const Vec<2>>, const AnyKernel<2>&, Real);
extern template InnerRelation<3> build_inner_relation<3>(std::span<const Vec<3>>, const AnyKernel<3>&, Real);
extern template ContactRelation<2> build_contact_relation<2>(std::span<const Vec<2>>, std::span<const Vec<2>>,
                                                             const AnyKernel<2>&, Real);
extern template void rebuild_inner_relation<2>(InnerRelation<2>&, std::span<const Vec<2>>, const AnyKernel<2>&, Real);
extern template void rebuild_inner_relation<3>(InnerRelation<3>&, std::span<const Vec<3>>, const AnyKernel<3>&, Real);
extern template void rebuild_contact_relation<2>(ContactRelation<2>&, std::span<const Vec<2>>, std::span<const Vec<2>>,
                                                 const AnyKernel<2>&, Real, SourceOrder);
extern template void rebuild_contact_relation<3>(ContactRelation<3>&, std::span<const Vec<3>>, std::span<const Vec<3>>,
                                                 const AnyKernel<3>&, Real, SourceOrder);
extern template ContactRelation<3> build_contact_relation<3>(std::span<const Vec<3>>, std::span<const Vec<3>>,
                                                             const AnyKernel<3>&, Real);

}  // namespace sph
