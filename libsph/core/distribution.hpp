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

#include <cstring>
#include <span>
#include <vector>

#include "libsph/core/communicator.hpp"
#include "libsph/core/parallel.hpp"
#include "libsph/core/particles.hpp"

namespace sph {

/// Makes `particles` (the whole set, the same on every rank) this rank's part with its ghosts.
/// Throws std::invalid_argument if there are fewer particles than ranks or the ranks disagree on
/// the set. Fields registered before are distributed with the particles.
template <int Dim>
void distribute(ParticleSet<Dim>& particles, Real ghost_radius, const Communicator& comm = Communicator::world());

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
  if (!particles.partition()) return parallel_sum(particles.n_particles(), 0.0, [&](std::size_t i) { return double(term(i)); });
  std::vector<double> local(particles.n_owned()), whole;
  for (std::size_t i = 0; i < local.size(); ++i) local[i] = double(term(i));
  const auto all = gather_all<Dim, double>(particles, local, whole);
  return parallel_sum(all.size(), 0.0, [&](std::size_t i) { return all[i]; });
}

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

/// The whole set in global-id order (positions, volumes, every field) at rank 0, written into
/// `whole` (resized and given the fields of `particles` on first use); other ranks leave it empty.
/// Only for a distributed set.
template <int Dim>
void gather_particles(const ParticleSet<Dim>& particles, ParticleSet<Dim>& whole);

}  // namespace sph
