#pragma once
// This rank's part of a distributed particle set (libsph/core/distribution.hpp builds it).
//
// Local particles are the owned ones first, then the ghosts (copies of particles other ranks own,
// within the ghost radius of an owned one), each group in increasing global id: the global id of a
// particle is its index in the whole set as every rank built it, so one rank (or a serial run)
// numbers the particles as the global ids. Relations take the owned particles as targets and all
// local ones as sources; their cells are laid on the grid of the whole set (`grid_origin`) and
// filled in global-id order (`id_order`), so a row lists its neighbours in the order of a serial
// run and every per-particle sum is bitwise that of one rank.

#include <cstddef>
#include <vector>

#include "libsph/core/types.hpp"

namespace sph {

template <int Dim>
struct Partition {
  std::size_t n_global = 0;              ///< particles of the whole set
  std::size_t n_owned = 0;               ///< the first n_owned local particles are this rank's
  std::vector<Index> global_id;          ///< global id of every local particle
  std::vector<Index> id_order;           ///< local indices in increasing global id (owned and ghosts merged)
  Vec<Dim> grid_origin = Vec<Dim>::Zero();  ///< lower corner of the whole set: the origin of every cell grid
  std::vector<std::vector<Index>> send;     ///< per rank q: owned local indices that q holds as ghosts, by global id
  std::vector<std::vector<Index>> receive;  ///< per rank q: ghost local indices owned by q, by global id
  /// The particles migrate between ranks (MovingPartition): the layout is not that of a fresh
  /// distribution, so a checkpoint cannot restore it.
  bool moves = false;
  /// Ghost values this rank receives in one halo update of one scalar (for the scaling report).
  std::size_t n_ghosts() const { return global_id.size() - n_owned; }
};

}  // namespace sph
