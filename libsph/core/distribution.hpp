#pragma once
// Distributed particle sets: a partition per rank with ghosts, halo updates, and the whole set
// gathered in global-id order for output, observers and reproducible sums.
//
// Every rank builds the whole particle set the same way (a lattice, a mesh's particles), then
// distribute() keeps this rank's part: Zoltan's recursive coordinate bisection (RCB) assigns the
// particles to ranks, and each rank keeps its owned particles followed by the ghosts within the
// ghost radius (one kernel support for a one-ring pair loop), both in global-id order
// (partition.hpp). Systems then compute the owned particles only and call update_ghosts() on the
// fields their pair loops read, between the phase that writes them and the next that reads them
// across particles (docs/architecture.md, "Distribution over MPI ranks").
//
// Results do not depend on the number of ranks: a row of a relation lists its neighbours as in a
// serial run, so per-particle sums are bitwise those of one rank; minima and maxima are exact; sums
// over particles (global_sum) gather the terms in global-id order and add them as a serial run's
// parallel_sum does. On one rank (or a serial build) every function here is the identity.

#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#include "libsph/core/communicator.hpp"
#include "libsph/core/exact_sum.hpp"
#include "libsph/core/parallel.hpp"
#include "libsph/core/particles.hpp"

namespace sph {

/// Makes `particles` (the whole set, the same on every rank) this rank's part with its ghosts.
/// `keep_together` (empty, or one global id per particle): particle i goes to the rank of particle
/// keep_together[i], so that units of particles that a system treats together (the lane blocks of
/// the cell models, sph::reaction_blocks) stay whole. Throws std::invalid_argument if there are
/// fewer particles than ranks or the ranks disagree on the set. Fields registered before are
/// distributed with the particles.
template <int Dim>
void distribute(ParticleSet<Dim>& particles, Real ghost_radius, const Communicator& comm = Communicator::world(),
                std::span<const Index> keep_together = {});

/// The partition of a particle set that moves (a fluid): each rank owns the particles inside its
/// region of Zoltan's recursive coordinate bisection of space (the cuts kept, KEEP_CUTS) and holds as
/// ghosts the other ranks' particles within the ghost radius of its region (Zoltan's box
/// assignment). update() moves the particles that crossed into another rank's region to that rank,
/// every field with them (one message per pair of ranks, sizes sent first), then gathers the ghosts
/// anew; every `rebalance_interval` updates it cuts the regions again at the particles' current
/// positions, equal counts per rank. Owned particles and ghosts are each kept in global-id order
/// (partition.hpp). A fluid's relations order their sources by position (SourceOrder::by_position),
/// so where a particle is owned changes no result. One rank (or a serial build): nothing happens.
template <int Dim>
class MovingPartition {
 public:
  explicit MovingPartition(Real ghost_radius, std::size_t rebalance_interval = 20,
                           const Communicator& comm = Communicator::world());
  ~MovingPartition();
  MovingPartition(const MovingPartition&) = delete;
  MovingPartition& operator=(const MovingPartition&) = delete;

  /// The first call distributes the whole set that every rank holds (the same on every rank; throws
  /// std::invalid_argument otherwise, or with fewer particles than ranks); later calls move the
  /// particles of the set it distributed. Relations and particle indices held elsewhere must be
  /// rebuilt afterwards.
  void update(ParticleSet<Dim>& particles);
  /// Updates so far, and how many of them cut the regions anew.
  std::size_t updates() const { return updates_; }
  std::size_t rebalances() const { return rebalances_; }

 private:
  struct Cuts;
  std::unique_ptr<Cuts> cuts_;
  Real ghost_radius_;
  std::size_t interval_, updates_ = 0, rebalances_ = 0;
  const Communicator& comm_;
};

/// The communicator of a set: the world for a distributed set; nullptr for a serial one.
template <int Dim>
const Communicator* communicator_of(const ParticleSet<Dim>& particles) {
  return particles.partition() ? &Communicator::world() : nullptr;
}

/// Copies the values of the owned particles into the ghosts that other ranks hold of them; with
/// several fields, all of them in one message per neighbouring rank.
template <int Dim, class... T>
void update_ghosts(const ParticleSet<Dim>& particles, std::span<T>... values) {
  const Partition<Dim>* p = particles.partition();
  if (!p) return;
  constexpr std::size_t bytes = (sizeof(T) + ...);
  const std::size_t ranks = p->send.size();
  std::vector<std::vector<std::byte>> send(ranks), receive(ranks);
  for (std::size_t q = 0; q < ranks; ++q) {
    send[q].resize(p->send[q].size() * bytes);
    std::byte* at = send[q].data();
    for (const Index i : p->send[q])
      ((std::memcpy(at, &values[i], sizeof(T)), at += sizeof(T)), ...);
    receive[q].resize(p->receive[q].size() * bytes);
  }
  Communicator::world().exchange(send, receive);
  for (std::size_t q = 0; q < ranks; ++q) {
    const std::byte* at = receive[q].data();
    for (const Index i : p->receive[q])
      ((std::memcpy(static_cast<void*>(&values[i]), at, sizeof(T)), at += sizeof(T)), ...);
  }
}

/// The smallest `value` over the ranks of a distributed set (the value itself otherwise).
template <int Dim>
Real global_min(const ParticleSet<Dim>& particles, Real value) {
  const Communicator* comm = communicator_of(particles);
  return comm ? static_cast<Real>(comm->min(double(value))) : value;
}

/// The largest `value` over the ranks of a distributed set (the value itself otherwise).
template <int Dim>
Real global_max(const ParticleSet<Dim>& particles, Real value) {
  const Communicator* comm = communicator_of(particles);
  return comm ? static_cast<Real>(comm->max(double(value))) : value;
}

/// The values of the owned particles of every rank in global-id order, on every rank (the whole
/// set's values, as a serial run holds them). Serial: `local` itself, nothing copied.
template <int Dim, class T>
std::span<const T> gather_all(const ParticleSet<Dim>& particles, std::span<const T> local, std::vector<T>& whole) {
  const Partition<Dim>* p = particles.partition();
  if (!p) return local;
  std::vector<std::byte> mine(p->n_owned * (sizeof(Index) + sizeof(T)));
  for (std::size_t i = 0; i < p->n_owned; ++i) {
    std::memcpy(mine.data() + i * (sizeof(Index) + sizeof(T)), &p->global_id[i], sizeof(Index));
    std::memcpy(mine.data() + i * (sizeof(Index) + sizeof(T)) + sizeof(Index), &local[i], sizeof(T));
  }
  whole.resize(p->n_global);
  for (const auto& part : Communicator::world().all_gather(mine)) {
    for (std::size_t at = 0; at < part.size(); at += sizeof(Index) + sizeof(T)) {
      Index id;
      std::memcpy(&id, part.data() + at, sizeof(Index));
      std::memcpy(static_cast<void*>(&whole[id]), part.data() + at + sizeof(Index), sizeof(T));
    }
  }
  return whole;
}

/// Sum of term(i) over the owned particles of every rank, added in global-id order exactly as
/// parallel_sum adds it over the whole set in a serial run (bitwise the same for any rank count).
template <int Dim, class Term>
double global_sum(const ParticleSet<Dim>& particles, Term&& term) {
  // The terms are stored before they are added, on one rank as on several: a term computed inside
  // the adding loop could be fused with the addition (a multiply-add) and differ in the last bit.
  std::vector<double> local(particles.n_owned()), whole;
  parallel_for(local.size(), [&](std::size_t i) { local[i] = double(term(i)); });
  const auto all = gather_all<Dim, double>(particles, local, whole);
  return parallel_sum(all.size(), 0.0, [&](std::size_t i) { return all[i]; });
}

/// Sum of term(i) over the owned particles of every rank, exactly accumulated (exact_sum.hpp): the
/// same bits for any order of the particles, thread count and rank count, with one small message
/// per rank. For sets whose particles move between ranks and in memory (fluids).
template <int Dim, class Term>
double global_exact_sum(const ParticleSet<Dim>& particles, Term&& term) {
  if (!particles.partition()) return exact_sum(particles.n_particles(), term);
  ExactSum local;
  for (std::size_t i = 0; i < particles.n_owned(); ++i) local.add(double(term(i)));
  ExactSum total;
  for (const auto& part : Communicator::world().all_gather(local.bytes())) total.add(ExactSum::from_bytes(part));
  return total.value();
}

/// The global id of local particle i (its index in a serial run).
template <int Dim>
Index global_index(const ParticleSet<Dim>& particles, std::size_t i) {
  const Partition<Dim>* p = particles.partition();
  return p ? p->global_id[i] : static_cast<Index>(i);
}

/// The local indices of the particles with the given global ids that this rank holds (all local
/// particles, or only its owned ones), in the order of `ids`; the others are left out. Serial:
/// `ids` itself.
template <int Dim>
std::vector<Index> local_indices(const ParticleSet<Dim>& particles, std::span<const Index> ids, bool owned_only) {
  const Partition<Dim>* p = particles.partition();
  if (!p) return {ids.begin(), ids.end()};
  constexpr Index absent = std::numeric_limits<Index>::max();
  std::vector<Index> local_of(p->n_global, absent);
  const std::size_t held = owned_only ? p->n_owned : p->global_id.size();
  for (std::size_t i = 0; i < held; ++i) local_of[p->global_id[i]] = static_cast<Index>(i);
  std::vector<Index> local;
  for (const Index id : ids)
    if (local_of[id] != absent) local.push_back(local_of[id]);
  return local;
}

/// A fixed selection of particles (by global id) whose values every rank needs whole: the
/// particles that carry a surface spread over the ranks (a cavity's endocardium), read at every
/// step by all ranks. gather() gives the values of the selected particles in selection order on
/// every rank, each from its owner; owned(k) names the local index of the k-th selected particle
/// where this rank owns it, so that what is computed from the gathered values is written back by
/// one rank. Serial: a copy by index, every particle owned.
template <int Dim>
class SharedSelection {
 public:
  static constexpr Index not_owned = std::numeric_limits<Index>::max();

  SharedSelection(const ParticleSet<Dim>& particles, std::vector<Index> ids) : particles_(particles), ids_(std::move(ids)) {
    const Partition<Dim>* p = particles.partition();
    if (!p) {
      owned_ = ids_;
      return;
    }
    std::vector<Index> local_of(p->n_global, not_owned);
    for (std::size_t i = 0; i < p->n_owned; ++i) local_of[p->global_id[i]] = static_cast<Index>(i);
    owned_.resize(ids_.size());
    for (std::size_t k = 0; k < ids_.size(); ++k) {
      owned_[k] = local_of[ids_[k]];
      if (owned_[k] != not_owned) mine_.push_back(static_cast<Index>(k));
    }
  }

  std::size_t size() const { return ids_.size(); }
  /// The global ids of the selected particles.
  const std::vector<Index>& ids() const { return ids_; }
  /// The local index of the k-th selected particle if this rank owns it, else not_owned.
  Index owned(std::size_t k) const { return owned_[k]; }

  /// The values of the selected particles, in selection order, on every rank (one all-gather).
  template <class T>
  void gather(std::span<const T> local, std::vector<T>& selected) const {
    selected.resize(ids_.size());
    if (!particles_.partition()) {
      for (std::size_t k = 0; k < ids_.size(); ++k) selected[k] = local[ids_[k]];
      return;
    }
    std::vector<std::byte> part(mine_.size() * (sizeof(Index) + sizeof(T)));
    std::byte* at = part.data();
    for (const Index k : mine_) {
      std::memcpy(at, &k, sizeof(Index));
      std::memcpy(at + sizeof(Index), &local[owned_[k]], sizeof(T));
      at += sizeof(Index) + sizeof(T);
    }
    for (const auto& from : Communicator::world().all_gather(part))
      for (std::size_t b = 0; b < from.size(); b += sizeof(Index) + sizeof(T)) {
        Index k;
        std::memcpy(&k, from.data() + b, sizeof(Index));
        std::memcpy(static_cast<void*>(&selected[k]), from.data() + b + sizeof(Index), sizeof(T));
      }
  }

 private:
  const ParticleSet<Dim>& particles_;
  std::vector<Index> ids_, owned_, mine_;
};

/// The particle named in a failure found on some rank: the lowest global id over the ranks of
/// the owned particles for which a rank reports a problem (`local` = its first such owned index,
/// or n_owned() if none), with its position. found is false on every rank if no rank has one.
template <int Dim>
struct GlobalParticle {
  bool found = false;
  std::size_t id = 0;  ///< global id (the index in a serial run)
  Vec<Dim> position = Vec<Dim>::Zero();
};
template <int Dim>
GlobalParticle<Dim> first_over_ranks(const ParticleSet<Dim>& particles, std::size_t local);

/// On every rank, the `value` that the owner of `particle` (found by first_over_ranks from
/// `local`) passes; other ranks' values are ignored. A non-finite value arrives as NaN. Serial:
/// `value` itself.
template <int Dim>
double value_of_owner(const ParticleSet<Dim>& particles, const GlobalParticle<Dim>& particle, std::size_t local, double value) {
  const Partition<Dim>* p = particles.partition();
  if (!p) return value;
  const bool mine = local < p->n_owned && p->global_id[local] == particle.id;
  // (a non-finite value travels as the largest double, which no finite quantity here reaches)
  const double big = std::numeric_limits<double>::max();
  const double sent = mine ? (std::isfinite(value) ? value : big) : -std::numeric_limits<double>::infinity();
  const double got = Communicator::world().max(sent);
  return got == big ? std::numeric_limits<double>::quiet_NaN() : got;
}

/// The whole set in global-id order (positions, volumes, every field) at rank 0, written into
/// `whole` (resized and given the fields of `particles` on first use); other ranks leave it empty.
/// Only for a distributed set.
template <int Dim>
void gather_particles(const ParticleSet<Dim>& particles, ParticleSet<Dim>& whole);

}  // namespace sph
