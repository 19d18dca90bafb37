#pragma once
// The ranks of a distributed run. Built with MPI (CARDIOSPH_WITH_MPI), a Communicator is
// MPI_COMM_WORLD; without it there is one rank and every operation is the identity, so the serial
// build needs no MPI at all. MPI stays inside communicator.cpp and distribution.cpp (and VTK's
// own MPI controller inside libsph/io/vtk/vtu_writer.cpp, for the .pvtu pieces): nothing else
// includes mpi.h.
//
// Every operation here is collective (all ranks call it, in the same order) except rank() and
// size(). Messages are bytes; the typed helpers of distribution.hpp pack and unpack them.

#include <cstddef>
#include <string>
#include <vector>

namespace sph {

class Communicator {
 public:
  /// All ranks of the run (MPI_COMM_WORLD once MpiSession has started MPI; one rank otherwise).
  static const Communicator& world();
  /// True if this build can run on several ranks.
  static bool built_with_mpi();

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool is_root() const { return rank_ == 0; }

  double min(double value) const;
  double max(double value) const;
  /// The smallest value over the ranks (e.g. the first global id with a problem).
  unsigned long long min(unsigned long long value) const;
  /// The sum over the ranks of a count (exact: integers).
  unsigned long long sum(unsigned long long value) const;
  /// True on every rank if `flag` is true on any rank.
  bool any(bool flag) const;

  /// Sends send[q] to rank q and receives from every rank q into receive[q], which the caller has
  /// sized to what q sends (both sides know the halo lists). Empty buffers send nothing.
  void exchange(const std::vector<std::vector<std::byte>>& send, std::vector<std::vector<std::byte>>& receive) const;
  /// Sends send[q] to rank q (q = this rank included) when the receivers do not know the sizes
  /// (particles migrating): the sizes go first, in an all-to-all; returns what each rank sent here.
  std::vector<std::vector<std::byte>> exchange(const std::vector<std::vector<std::byte>>& send) const;
  /// Every rank's bytes, in rank order, at rank 0 (empty on the others).
  std::vector<std::vector<std::byte>> gather(const std::vector<std::byte>& local) const;
  /// Every rank's bytes, in rank order, on every rank.
  std::vector<std::vector<std::byte>> all_gather(const std::vector<std::byte>& local) const;
  void barrier() const;
  /// Ends every rank of the run at once with exit code `code` (MPI_Abort); exits this process alone
  /// without MPI.
  [[noreturn]] void abort(int code) const;
  /// The MPI communicator (an MPI_Comm) for libraries that take one (Zoltan); only with MPI.
  const void* native_handle() const;

  /// What this rank has sent since the start: halo exchanges (calls of exchange), the point-to-point
  /// messages and bytes they sent, and collective operations (reductions, gathers, barriers).
  struct Traffic {
    unsigned long long exchanges = 0, messages = 0, bytes = 0, collectives = 0;
  };
  const Traffic& traffic() const { return traffic_; }

 private:
  Communicator() = default;
  static Communicator& mutable_world();
  int rank_ = 0;
  int size_ = 1;
  mutable Traffic traffic_;  // (MPI is called from one thread only)
  friend class MpiSession;
};

/// Starts MPI for the life of the object (the executable's main), or does nothing in a serial
/// build. Only the thread that created it calls MPI (MPI_THREAD_FUNNELED).
class MpiSession {
 public:
  MpiSession(int& argc, char**& argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

 private:
  bool started_ = false;
};

}  // namespace sph
