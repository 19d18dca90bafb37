#pragma once
// Cell-linked list: source particles binned into cubic cells no smaller than the search radius,
// so that every neighbour of a point lies in its own cell or one of the 3^Dim - 1 adjacent cells.
// Particles of a cell are stored contiguously (counting sort), in increasing index order; that order
// (cells in memory order, then particle index) is also the order particles are sorted in
// (particle_sorting.hpp). rebuild() reuses the storage: no allocation while the number of cells
// and particles does not grow.

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <vector>

#include "libsph/core/types.hpp"

namespace sph {

template <int Dim>
class CellLinkedList {
 public:
  CellLinkedList() = default;
  CellLinkedList(std::span<const Vec<Dim>> sources, Real search_radius, const Vec<Dim>* origin = nullptr,
                 std::span<const Index> order = {}) {
    rebuild(sources, search_radius, origin, order);
  }
  /// Bins `sources` anew, reusing the storage. A distributed set (partition.hpp) passes the origin of
  /// the whole set's grid (its lower corner) and its local indices in global-id order, so that cells
  /// and their contents are those of a serial run; by default the grid starts at the sources' lower
  /// corner and a cell holds its sources by index.
  void rebuild(std::span<const Vec<Dim>> sources, Real search_radius, const Vec<Dim>* origin = nullptr,
               std::span<const Index> order = {});

  /// Re-orders the sources within each cell lexicographically by position (x, then y, then z; ties
  /// by index), so that the order no longer depends on where the sources sit in memory or on which
  /// rank they are (neighbour_relation.hpp, SourceOrder::by_position).
  void order_by_position(std::span<const Vec<Dim>> sources);

  /// Calls visit(j) for every source j in the cells around `x` (a superset of the neighbours
  /// within the search radius), in a fixed order: cells in stencil order, sources by index.
  template <class Visit>
  void for_each_candidate(const Vec<Dim>& x, Visit&& visit) const {
    std::array<long, Dim> lo, hi;
    for (int d = 0; d < Dim; ++d) {
      const long c = cell_coordinate(x[d], d);
      lo[d] = std::max(c - 1, 0L);
      hi[d] = std::min(c + 1, static_cast<long>(n_cells_[d]) - 1);
      if (lo[d] > hi[d]) return;  // x is more than one cell away from every source
    }
    if constexpr (Dim == 2) {
      for (long cy = lo[1]; cy <= hi[1]; ++cy)
        for (long cx = lo[0]; cx <= hi[0]; ++cx) visit_cell(cx + cy * n_cells_[0], visit);
    } else {
      for (long cz = lo[2]; cz <= hi[2]; ++cz)
        for (long cy = lo[1]; cy <= hi[1]; ++cy)
          for (long cx = lo[0]; cx <= hi[0]; ++cx)
            visit_cell(cx + n_cells_[0] * (cy + n_cells_[1] * cz), visit);
    }
  }

  /// Calls visit(j) for every source j within `radius2` (squared distance, strictly less) of `x`, in
  /// the order of for_each_candidate. The cells of a row of the stencil are adjacent in memory, and
  /// the sources' positions are kept in that order (cell_positions_): the test runs over a few
  /// contiguous ranges instead of gathering positions through indices.
  template <class Visit>
  void for_each_within(const Vec<Dim>& x, Real radius2, Visit&& visit) const {
    std::array<long, Dim> lo, hi;
    for (int d = 0; d < Dim; ++d) {
      const long c = cell_coordinate(x[d], d);
      lo[d] = std::max(c - 1, 0L);
      hi[d] = std::min(c + 1, static_cast<long>(n_cells_[d]) - 1);
      if (lo[d] > hi[d]) return;
    }
    auto visit_row = [&](long first_cell, long last_cell) {
      for (std::size_t k = cell_start_[first_cell]; k < cell_start_[last_cell + 1]; ++k)
        if ((x - cell_positions_[k]).squaredNorm() < radius2) visit(cell_particles_[k]);
    };
    if constexpr (Dim == 2) {
      for (long cy = lo[1]; cy <= hi[1]; ++cy) visit_row(lo[0] + cy * n_cells_[0], hi[0] + cy * n_cells_[0]);
    } else {
      for (long cz = lo[2]; cz <= hi[2]; ++cz)
        for (long cy = lo[1]; cy <= hi[1]; ++cy) {
          const long row = n_cells_[0] * (cy + n_cells_[1] * cz);
          visit_row(lo[0] + row, hi[0] + row);
        }
    }
  }

  Real cell_size() const { return cell_size_; }
  std::size_t n_cells() const { return cell_start_.size() - 1; }
  /// Bytes held (cell offsets, binned indices and the sort's scratch).
  std::size_t bytes() const {
    return (cell_start_.capacity() + cell_of_.capacity() + next_.capacity()) * sizeof(std::size_t) +
           cell_particles_.capacity() * sizeof(Index) + cell_positions_.capacity() * sizeof(Vec<Dim>);
  }
  /// The sources cell by cell (cells in memory order, sources by index within a cell).
  std::span<const Index> cell_order() const { return cell_particles_; }

 private:
  long cell_coordinate(Real x, int d) const {
    // Clamp in floating point first so that far-away points cannot overflow the integer.
    const Real c = std::floor((x - origin_[d]) / cell_size_);
    const Real limit = static_cast<Real>(n_cells_[d]) + Real(2);
    return static_cast<long>(std::clamp(c, -Real(2), limit));
  }
  template <class Visit>
  void visit_cell(long cell, Visit& visit) const {
    for (std::size_t k = cell_start_[cell]; k < cell_start_[cell + 1]; ++k) visit(cell_particles_[k]);
  }

  Vec<Dim> origin_ = Vec<Dim>::Zero();
  Real cell_size_ = 1;
  std::array<std::size_t, Dim> n_cells_{};
  std::vector<std::size_t> cell_start_;  ///< CSR offsets into cell_particles_, size n_cells + 1
  std::vector<Index> cell_particles_;
  std::vector<Vec<Dim>> cell_positions_;  ///< the sources' positions in the order of cell_particles_
  std::vector<std::size_t> cell_of_, next_;  // scratch of the counting sort
};

extern template class CellLinkedList<2>;
extern template class CellLinkedList<3>;

}  // namespace sph
