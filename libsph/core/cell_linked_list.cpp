#include "libsph/core/cell_linked_list.hpp"

#include "libsph/core/parallel.hpp"

#include <limits>
#include <stdexcept>
#include <string>

namespace sph {

template <int Dim>
void CellLinkedList<Dim>::rebuild(std::span<const Vec<Dim>> sources, Real search_radius, const Vec<Dim>* origin,
                                  std::span<const Index> order) {
  if (!(search_radius > 0)) throw std::invalid_argument("cell-linked list: search radius must be positive");
  // A cell a little larger than the search radius guarantees that two points closer than the
  // radius never fall two cells apart, whatever the rounding of (x - origin) / cell_size.
  cell_size_ = search_radius * (Real(1) + Real(64) * std::numeric_limits<Real>::epsilon());
  Vec<Dim> lower = Vec<Dim>::Constant(std::numeric_limits<Real>::max());
  Vec<Dim> upper = Vec<Dim>::Constant(std::numeric_limits<Real>::lowest());
  for (const auto& x : sources) {
    if (!x.allFinite()) throw std::invalid_argument("cell-linked list: a particle position is not finite");
    lower = lower.cwiseMin(x);
    upper = upper.cwiseMax(x);
  }
  if (sources.empty()) lower = upper = Vec<Dim>::Zero();
  if (origin) {
    if (!sources.empty() && (lower - *origin).minCoeff() < 0) throw std::invalid_argument("cell-linked list: a source lies below the grid origin");
    lower = *origin;
  }
  if (!order.empty() && order.size() != sources.size())
    throw std::invalid_argument("cell-linked list: the binning order does not cover the sources");
  origin_ = lower;
  std::size_t total = 1;
  for (int d = 0; d < Dim; ++d) {
    const auto n = static_cast<std::size_t>(std::floor((upper[d] - lower[d]) / cell_size_)) + 1;
    n_cells_[d] = n;
    total *= n;
  }
  if (total > std::size_t(1) << 34)
    throw std::invalid_argument("cell-linked list: " + std::to_string(total) +
                                " cells; the search radius is far too small for the particle extent");

  // Counting sort by cell: count, exclusive scan, fill in index order.
  cell_of_.resize(sources.size());
  cell_start_.assign(total + 1, 0);
  for (std::size_t i = 0; i < sources.size(); ++i) {
    std::size_t cell = 0, stride = 1;
    for (int d = 0; d < Dim; ++d) {
      const auto c = static_cast<std::size_t>(std::clamp<long>(cell_coordinate(sources[i][d], d), 0,
                                                               static_cast<long>(n_cells_[d]) - 1));
      cell += c * stride;
      stride *= n_cells_[d];
    }
    cell_of_[i] = cell;
    ++cell_start_[cell + 1];
  }
  for (std::size_t c = 0; c < total; ++c) cell_start_[c + 1] += cell_start_[c];
  cell_particles_.resize(sources.size());
  next_.assign(cell_start_.begin(), cell_start_.end() - 1);
  if (order.empty())
    for (std::size_t i = 0; i < sources.size(); ++i) cell_particles_[next_[cell_of_[i]]++] = static_cast<Index>(i);
  else
    for (const Index i : order) cell_particles_[next_[cell_of_[i]]++] = i;
  cell_positions_.resize(sources.size());
  for (std::size_t k = 0; k < sources.size(); ++k) cell_positions_[k] = sources[cell_particles_[k]];
}

template <int Dim>
void CellLinkedList<Dim>::order_by_position(std::span<const Vec<Dim>> sources) {
  auto before = [&](Index a, Index b) {
    for (int d = 0; d < Dim; ++d)
      if (sources[a][d] != sources[b][d]) return sources[a][d] < sources[b][d];
    return a < b;
  };
  const std::size_t n_cells = cell_start_.size() - 1;
  parallel_for(n_cells, [&](std::size_t c) {  // a cell holds a few tens of sources: insertion sort
    Index* first = cell_particles_.data() + cell_start_[c];
    Index* last = cell_particles_.data() + cell_start_[c + 1];
    for (Index* i = first + (first != last); i < last; ++i) {
      const Index value = *i;
      Index* j = i;
      for (; j > first && before(value, *(j - 1)); --j) *j = *(j - 1);
      *j = value;
    }
    for (std::size_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) cell_positions_[k] = sources[cell_particles_[k]];
  });
}

template class CellLinkedList<2>;
template class CellLinkedList<3>;

}  // namespace sph
