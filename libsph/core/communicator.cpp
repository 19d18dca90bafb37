#include "libsph/core/communicator.hpp"

#include <cstdlib>
#include <stdexcept>

#ifdef CARDIOSPH_WITH_MPI
#include <mpi.h>
#endif

namespace sph {

Communicator& Communicator::mutable_world() {
  static Communicator world;
  return world;
}

const Communicator& Communicator::world() { return mutable_world(); }

#ifdef CARDIOSPH_WITH_MPI

bool Communicator::built_with_mpi() { return true; }

namespace {
MPI_Comm comm_of(const Communicator& c) { return *static_cast<const MPI_Comm*>(c.native_handle()); }
MPI_Comm world_comm = MPI_COMM_WORLD;
}  // namespace

const void* Communicator::native_handle() const { return &world_comm; }

namespace {
/// One all-reduce of one value of MPI type `type` with operation `op` (counted as a collective).
template <class T>
T all_reduce(const Communicator& comm, Communicator::Traffic& traffic, T value, MPI_Datatype type, MPI_Op op) {
  if (comm.size() == 1) return value;
  ++traffic.collectives;
  T out;
  MPI_Allreduce(&value, &out, 1, type, op, comm_of(comm));
  return out;
}
}  // namespace

double Communicator::min(double value) const { return all_reduce(*this, traffic_, value, MPI_DOUBLE, MPI_MIN); }
double Communicator::max(double value) const { return all_reduce(*this, traffic_, value, MPI_DOUBLE, MPI_MAX); }
unsigned long long Communicator::min(unsigned long long value) const {
  return all_reduce(*this, traffic_, value, MPI_UNSIGNED_LONG_LONG, MPI_MIN);
}
unsigned long long Communicator::sum(unsigned long long value) const {
  return all_reduce(*this, traffic_, value, MPI_UNSIGNED_LONG_LONG, MPI_SUM);
}

bool Communicator::any(bool flag) const {
  if (size_ == 1) return flag;
  ++traffic_.collectives;
  int in = flag ? 1 : 0, out = 0;
  MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_MAX, comm_of(*this));
  return out != 0;
}

void Communicator::exchange(const std::vector<std::vector<std::byte>>& send,
                            std::vector<std::vector<std::byte>>& receive) const {
  if (size_ == 1) {
    if (!send.empty() && !receive.empty()) receive[0] = send[0];
    return;
  }
  ++traffic_.exchanges;
  std::vector<MPI_Request> requests;
  requests.reserve(2 * static_cast<std::size_t>(size_));
  // What a rank sends itself (a fluid's particles that stay) is copied, not counted as traffic.
  if (!send[static_cast<std::size_t>(rank_)].empty())
    receive[static_cast<std::size_t>(rank_)] = send[static_cast<std::size_t>(rank_)];
  for (int q = 0; q < size_; ++q) {
    auto& buffer = receive[static_cast<std::size_t>(q)];
    if (buffer.empty() || q == rank_) continue;
    requests.emplace_back();
    MPI_Irecv(buffer.data(), static_cast<int>(buffer.size()), MPI_BYTE, q, 7, comm_of(*this), &requests.back());
  }
  for (int q = 0; q < size_; ++q) {
    const auto& buffer = send[static_cast<std::size_t>(q)];
    if (buffer.empty() || q == rank_) continue;
    ++traffic_.messages;
    traffic_.bytes += buffer.size();
    requests.emplace_back();
    MPI_Isend(buffer.data(), static_cast<int>(buffer.size()), MPI_BYTE, q, 7, comm_of(*this), &requests.back());
  }
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
}

std::vector<std::vector<std::byte>> Communicator::exchange(const std::vector<std::vector<std::byte>>& send) const {
  if (size_ == 1) return {send.at(0)};
  ++traffic_.collectives;
  std::vector<unsigned long long> sizes(static_cast<std::size_t>(size_)), incoming(sizes.size());
  for (std::size_t q = 0; q < sizes.size(); ++q) sizes[q] = send.at(q).size();
  MPI_Alltoall(sizes.data(), 1, MPI_UNSIGNED_LONG_LONG, incoming.data(), 1, MPI_UNSIGNED_LONG_LONG, comm_of(*this));
  std::vector<std::vector<std::byte>> receive(sizes.size());
  for (std::size_t q = 0; q < sizes.size(); ++q) receive[q].resize(incoming[q]);
  exchange(send, receive);
  return receive;
}

std::vector<std::vector<std::byte>> Communicator::all_gather(const std::vector<std::byte>& local) const {
  if (size_ == 1) return {local};
  ++traffic_.collectives;
  const int n = static_cast<int>(local.size());
  std::vector<int> counts(static_cast<std::size_t>(size_)), offsets(static_cast<std::size_t>(size_), 0);
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, comm_of(*this));
  for (int q = 1; q < size_; ++q) offsets[q] = offsets[q - 1] + counts[q - 1];
  std::vector<std::byte> all(static_cast<std::size_t>(offsets.back() + counts.back()));
  MPI_Allgatherv(local.data(), n, MPI_BYTE, all.data(), counts.data(), offsets.data(), MPI_BYTE, comm_of(*this));
  std::vector<std::vector<std::byte>> out(static_cast<std::size_t>(size_));
  for (int q = 0; q < size_; ++q)
    out[q].assign(all.begin() + offsets[q], all.begin() + offsets[q] + counts[q]);
  return out;
}

std::vector<std::vector<std::byte>> Communicator::gather(const std::vector<std::byte>& local) const {
  if (size_ == 1) return {local};
  ++traffic_.collectives;
  const int n = static_cast<int>(local.size());
  std::vector<int> counts(static_cast<std::size_t>(size_)), offsets(static_cast<std::size_t>(size_), 0);
  MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm_of(*this));
  for (int q = 1; q < size_; ++q) offsets[q] = offsets[q - 1] + counts[q - 1];
  std::vector<std::byte> all(rank_ == 0 ? static_cast<std::size_t>(offsets.back() + counts.back()) : 0);
  MPI_Gatherv(local.data(), n, MPI_BYTE, all.data(), counts.data(), offsets.data(), MPI_BYTE, 0, comm_of(*this));
  std::vector<std::vector<std::byte>> out;
  if (rank_ != 0) return out;
  out.resize(static_cast<std::size_t>(size_));
  for (int q = 0; q < size_; ++q) out[q].assign(all.begin() + offsets[q], all.begin() + offsets[q] + counts[q]);
  return out;
}

void Communicator::barrier() const {
  if (size_ == 1) return;
  ++traffic_.collectives;
  MPI_Barrier(comm_of(*this));
}

void Communicator::abort(int code) const {
  MPI_Abort(comm_of(*this), code);
  std::exit(code);  // (MPI_Abort does not return)
}

MpiSession::MpiSession(int& argc, char**& argv) {
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  started_ = true;
  auto& world = Communicator::mutable_world();
  MPI_Comm_rank(MPI_COMM_WORLD, &world.rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &world.size_);
}

MpiSession::~MpiSession() {
  if (started_) MPI_Finalize();
}

#else

bool Communicator::built_with_mpi() { return false; }
const void* Communicator::native_handle() const { throw std::logic_error("communicator: this build has no MPI"); }
double Communicator::min(double value) const { return value; }
double Communicator::max(double value) const { return value; }
unsigned long long Communicator::min(unsigned long long value) const { return value; }
unsigned long long Communicator::sum(unsigned long long value) const { return value; }
bool Communicator::any(bool flag) const { return flag; }
void Communicator::exchange(const std::vector<std::vector<std::byte>>& send,
                            std::vector<std::vector<std::byte>>& receive) const {
  if (!send.empty() && !receive.empty()) receive[0] = send[0];
}
std::vector<std::vector<std::byte>> Communicator::exchange(const std::vector<std::vector<std::byte>>& send) const {
  return {send.at(0)};
}
std::vector<std::vector<std::byte>> Communicator::all_gather(const std::vector<std::byte>& local) const { return {local}; }
std::vector<std::vector<std::byte>> Communicator::gather(const std::vector<std::byte>& local) const { return {local}; }
void Communicator::barrier() const {}
void Communicator::abort(int code) const { std::exit(code); }
MpiSession::MpiSession(int&, char**&) {}
MpiSession::~MpiSession() = default;

#endif

}  // namespace sph
