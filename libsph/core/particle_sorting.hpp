#pragma once
// Sorting particles so that neighbours are near in memory: the particles are put in the order of
// the cells of a cell-linked list (cells in memory order, particles by index within a cell), every
// field permuted together (ParticleSet::permute). Neighbour loops then read nearby entries, which
// matters once a particle set outgrows the caches. A sort invalidates relations and any particle
// indices held outside the set: sort before the systems are built (solids), or as an event
// followed by the relation rebuild (fluids).

#include <span>
#include <vector>

#include "libsph/core/cell_linked_list.hpp"
#include "libsph/core/particles.hpp"

namespace sph {

/// The permutation that sorts `positions` along a cell list of cell size `cell_size`: entry k is
/// the index of the particle that goes to place k.
template <int Dim>
std::vector<Index> cell_order(std::span<const Vec<Dim>> positions, Real cell_size) {
  const CellLinkedList<Dim> cells(positions, cell_size);
  const auto order = cells.cell_order();
  return {order.begin(), order.end()};
}

/// Sorts the particles of `particles` along a cell list (cell size: the kernel support) and returns
/// the permutation applied (new index k holds the old particle order[k]).
template <int Dim>
std::vector<Index> sort_particles(ParticleSet<Dim>& particles, Real cell_size) {
  auto order = cell_order<Dim>(particles.position, cell_size);
  particles.permute(order);
  return order;
}

}  // namespace sph
