#include "libsph/core/distribution.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

#include "libsph/core/cell_linked_list.hpp"

#ifdef CARDIOSPH_WITH_MPI
#include <mpi.h>
#include <zoltan.h>
#endif

namespace sph {
namespace {

#ifdef CARDIOSPH_WITH_MPI

/// The objects this rank hands to Zoltan: points with their global ids, all of weight 1.
template <int Dim>
struct ZoltanPoints {
  std::vector<Vec<Dim>> position;
  std::vector<Index> id;
};

template <int Dim>
int points_count(void* data, int* error) {
  *error = ZOLTAN_OK;
  return static_cast<int>(static_cast<ZoltanPoints<Dim>*>(data)->id.size());
}

template <int Dim>
void points_list(void* data, int, int, ZOLTAN_ID_PTR global, ZOLTAN_ID_PTR local, int weight_dim, float* weights,
                 int* error) {
  const auto& s = *static_cast<ZoltanPoints<Dim>*>(data);
  for (std::size_t k = 0; k < s.id.size(); ++k) {
    global[k] = static_cast<ZOLTAN_ID_TYPE>(s.id[k]);
    local[k] = static_cast<ZOLTAN_ID_TYPE>(k);
    for (int w = 0; w < weight_dim; ++w) weights[k * static_cast<std::size_t>(weight_dim) + static_cast<std::size_t>(w)] = 1.0f;
  }
  *error = ZOLTAN_OK;
}

template <int Dim>
int points_dimension(void*, int* error) {
  *error = ZOLTAN_OK;
  return Dim;
}

template <int Dim>
void points_geometry(void* data, int, int, int n, ZOLTAN_ID_PTR, ZOLTAN_ID_PTR local, int dim, double* coordinates,
                     int* error) {
  const auto& s = *static_cast<ZoltanPoints<Dim>*>(data);
  for (int k = 0; k < n; ++k)
    for (int d = 0; d < dim; ++d) coordinates[static_cast<std::size_t>(k * dim + d)] = double(s.position[local[k]][d]);
  *error = ZOLTAN_OK;
}

void initialise_zoltan() {
  static const bool initialised = [] {
    float version = 0;
    return Zoltan_Initialize(0, nullptr, &version) == ZOLTAN_OK;
  }();
  if (!initialised) throw std::runtime_error("distribution: Zoltan did not initialise");
}

/// Zoltan's recursive coordinate bisection of every rank's `points` (which must outlive the
/// returned structure): one part per rank, equal counts. With `parts`, the part of each of this
/// rank's points; with `keep_cuts`, the cuts stay in the structure for point and box assignment.
/// The caller destroys the structure.
template <int Dim>
Zoltan_Struct* bisect(const Communicator& comm, ZoltanPoints<Dim>& points, bool keep_cuts, std::vector<int>* parts) {
  initialise_zoltan();
  Zoltan_Struct* zz = Zoltan_Create(*static_cast<const MPI_Comm*>(comm.native_handle()));
  Zoltan_Set_Param(zz, "DEBUG_LEVEL", "0");
  Zoltan_Set_Param(zz, "LB_METHOD", "RCB");
  Zoltan_Set_Param(zz, "NUM_GID_ENTRIES", "1");
  Zoltan_Set_Param(zz, "NUM_LID_ENTRIES", "1");
  Zoltan_Set_Param(zz, "OBJ_WEIGHT_DIM", "1");
  Zoltan_Set_Param(zz, "RETURN_LISTS", parts ? "PARTS" : "NONE");
  Zoltan_Set_Param(zz, "RCB_RECTILINEAR_BLOCKS", "0");
  Zoltan_Set_Param(zz, "KEEP_CUTS", keep_cuts ? "1" : "0");
  Zoltan_Set_Num_Obj_Fn(zz, points_count<Dim>, &points);
  Zoltan_Set_Obj_List_Fn(zz, points_list<Dim>, &points);
  Zoltan_Set_Num_Geom_Fn(zz, points_dimension<Dim>, &points);
  Zoltan_Set_Geom_Multi_Fn(zz, points_geometry<Dim>, &points);
  int changes = 0, n_gid = 0, n_lid = 0, n_import = 0, n_export = 0;
  ZOLTAN_ID_PTR import_global = nullptr, import_local = nullptr, export_global = nullptr, export_local = nullptr;
  int *import_procs = nullptr, *import_to_part = nullptr, *export_procs = nullptr, *export_to_part = nullptr;
  const int status = Zoltan_LB_Partition(zz, &changes, &n_gid, &n_lid, &n_import, &import_global, &import_local,
                                         &import_procs, &import_to_part, &n_export, &export_global, &export_local,
                                         &export_procs, &export_to_part);
  if (status == ZOLTAN_OK && parts) {
    // With RETURN_LISTS = PARTS the export lists name the part of every object of this rank.
    parts->assign(points.id.size(), comm.rank());
    for (int k = 0; k < n_export; ++k) (*parts)[export_local[k]] = export_to_part[k];
  }
  Zoltan_LB_Free_Part(&import_global, &import_local, &import_procs, &import_to_part);
  Zoltan_LB_Free_Part(&export_global, &export_local, &export_procs, &export_to_part);
  if (status != ZOLTAN_OK) {
    Zoltan_Destroy(&zz);
    throw std::runtime_error("distribution: Zoltan's partition failed (code " + std::to_string(status) + ")");
  }
  return zz;
}

/// The rank of every particle: each rank hands Zoltan a slice of the global ids; the answer is
/// shared with every rank.
template <int Dim>
std::vector<int> owners_by_rcb(const std::vector<Vec<Dim>>& position, const Communicator& comm) {
  const std::size_t n = position.size(), ranks = static_cast<std::size_t>(comm.size()),
                    r = static_cast<std::size_t>(comm.rank());
  ZoltanPoints<Dim> slice;
  for (std::size_t g = n * r / ranks; g < n * (r + 1) / ranks; ++g) {
    slice.position.push_back(position[g]);
    slice.id.push_back(static_cast<Index>(g));
  }
  std::vector<int> mine;
  Zoltan_Struct* zz = bisect<Dim>(comm, slice, false, &mine);
  Zoltan_Destroy(&zz);

  std::vector<std::byte> bytes(mine.size() * sizeof(int));
  std::memcpy(bytes.data(), mine.data(), bytes.size());
  std::vector<int> owner;
  owner.reserve(n);
  for (const auto& part : comm.all_gather(bytes)) {
    const std::size_t count = part.size() / sizeof(int);
    const std::size_t at = owner.size();
    owner.resize(at + count);
    std::memcpy(owner.data() + at, part.data(), part.size());
  }
  return owner;
}

#else

template <int Dim>
std::vector<int> owners_by_rcb(const std::vector<Vec<Dim>>& position, const Communicator&) {
  return std::vector<int>(position.size(), 0);
}

#endif

}  // namespace

template <int Dim>
void distribute(ParticleSet<Dim>& particles, Real ghost_radius, const Communicator& comm, std::span<const Index> keep_together) {
  if (comm.size() == 1) return;
  if (particles.partition()) throw std::logic_error("particle set '" + particles.name() + "' is already distributed");
  const std::size_t n = particles.n_particles(), ranks = static_cast<std::size_t>(comm.size());
  if (double(n) != comm.min(double(n)) || double(n) != comm.max(double(n)))
    throw std::invalid_argument("particle set '" + particles.name() + "': the ranks built different particle sets (" +
                                std::to_string(n) + " particles on rank " + std::to_string(comm.rank()) + ")");
  if (n < ranks)
    throw std::invalid_argument("particle set '" + particles.name() + "' has " + std::to_string(n) + " particles for " +
                                std::to_string(ranks) + " ranks; run on fewer ranks");
  if (!(ghost_radius > 0)) throw std::invalid_argument("distribution: the ghost radius must be positive");

  if (!keep_together.empty() && keep_together.size() != n)
    throw std::invalid_argument("particle set '" + particles.name() + "': " + std::to_string(keep_together.size()) +
                                " particles to keep together for " + std::to_string(n));
  std::vector<int> owner = owners_by_rcb<Dim>(particles.position, comm);
  if (!keep_together.empty()) {
    const std::vector<int> by_position = owner;
    for (std::size_t g = 0; g < n; ++g) owner[g] = by_position.at(keep_together[g]);
  }
  const int me = comm.rank();
  std::vector<Index> owned;
  for (std::size_t g = 0; g < n; ++g)
    if (owner[g] == me) owned.push_back(static_cast<Index>(g));
  if (comm.any(owned.empty()))  // every rank throws, so that none waits for the others
    throw std::invalid_argument("particle set '" + particles.name() + "' of " + std::to_string(n) +
                                " particles: a rank was given no particles by the partition; run on fewer ranks");

  // Ghosts: other ranks' particles within the ghost radius of an owned one; and what each rank q
  // holds of ours (the same distance test seen from q's side, so both sides list the same pairs).
  const CellLinkedList<Dim> cells(particles.position, ghost_radius);
  const Real radius2 = ghost_radius * ghost_radius;
  std::vector<char> is_ghost(n, 0);
  std::vector<std::vector<Index>> send_ids(ranks);
  for (const Index i : owned) {
    cells.for_each_candidate(particles.position[i], [&](Index j) {
      if (owner[j] == me || !((particles.position[i] - particles.position[j]).squaredNorm() < radius2)) return;
      is_ghost[j] = 1;
      auto& list = send_ids[static_cast<std::size_t>(owner[j])];
      if (list.empty() || list.back() != i) list.push_back(i);
    });
  }
  std::vector<Index> ghosts;
  for (std::size_t g = 0; g < n; ++g)
    if (is_ghost[g]) ghosts.push_back(static_cast<Index>(g));

  auto partition = std::make_shared<Partition<Dim>>();
  partition->n_global = n;
  partition->n_owned = owned.size();
  Vec<Dim> lower = Vec<Dim>::Constant(std::numeric_limits<Real>::max());
  for (const auto& x : particles.position) lower = lower.cwiseMin(x);  // as CellLinkedList::rebuild finds it
  partition->grid_origin = lower;
  partition->global_id = owned;
  partition->global_id.insert(partition->global_id.end(), ghosts.begin(), ghosts.end());
  partition->id_order.resize(partition->global_id.size());
  std::merge(owned.begin(), owned.end(), ghosts.begin(), ghosts.end(), partition->id_order.begin());
  // id_order holds global ids so far; turn them into local indices.
  auto local_of = [&](Index g) -> Index {
    const auto o = std::lower_bound(owned.begin(), owned.end(), g);
    if (o != owned.end() && *o == g) return static_cast<Index>(o - owned.begin());
    const auto h = std::lower_bound(ghosts.begin(), ghosts.end(), g);
    return static_cast<Index>(owned.size() + static_cast<std::size_t>(h - ghosts.begin()));
  };
  for (auto& k : partition->id_order) k = local_of(k);
  partition->send.resize(ranks);
  partition->receive.resize(ranks);
  for (std::size_t q = 0; q < ranks; ++q) {
    auto& ids = send_ids[q];
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    for (const Index g : ids) partition->send[q].push_back(local_of(g));
  }
  for (const Index g : ghosts) partition->receive[static_cast<std::size_t>(owner[g])].push_back(local_of(g));

  particles.select(partition->global_id);
  particles.set_partition(std::move(partition));
}

template <int Dim>
GlobalParticle<Dim> first_over_ranks(const ParticleSet<Dim>& particles, std::size_t local) {
  GlobalParticle<Dim> out;
  const Partition<Dim>* p = particles.partition();
  if (!p) {
    if (local < particles.n_particles()) out = {true, local, particles.position[local]};
    return out;
  }
  struct Entry {
    unsigned long long id;
    Vec<Dim> position;
  };
  if (!Communicator::world().any(local < p->n_owned)) return out;
  Entry mine{std::numeric_limits<unsigned long long>::max(), Vec<Dim>::Zero()};
  if (local < p->n_owned) mine = {p->global_id[local], particles.position[local]};
  std::vector<std::byte> bytes(sizeof(Entry));
  std::memcpy(bytes.data(), &mine, sizeof(Entry));
  for (const auto& part : Communicator::world().all_gather(bytes)) {
    Entry e;
    std::memcpy(static_cast<void*>(&e), part.data(), sizeof(Entry));
    if (e.id != std::numeric_limits<unsigned long long>::max() && (!out.found || e.id < out.id))
      out = {true, static_cast<std::size_t>(e.id), e.position};
  }
  return out;
}

template <int Dim>
void gather_particles(const ParticleSet<Dim>& particles, ParticleSet<Dim>& whole) {
  const Partition<Dim>* p = particles.partition();
  if (!p) throw std::logic_error("gather_particles: particle set '" + particles.name() + "' is not distributed");
  std::vector<Index> owned(p->n_owned);
  for (std::size_t i = 0; i < owned.size(); ++i) owned[i] = static_cast<Index>(i);
  std::vector<std::byte> bytes(owned.size() * sizeof(Index));
  std::memcpy(bytes.data(), p->global_id.data(), bytes.size());
  const auto append = [&](const auto& values) {
    const std::size_t at = bytes.size(), size = sizeof(values[0]);
    bytes.resize(at + owned.size() * size);
    std::memcpy(bytes.data() + at, values.data(), owned.size() * size);
  };
  append(particles.position);
  append(particles.volume);
  for (const auto& f : particles.fields()) f->pack(owned, bytes);
  const auto parts = Communicator::world().gather(bytes);
  if (!Communicator::world().is_root()) return;

  if (whole.n_particles() != p->n_global)
    whole = ParticleSet<Dim>(particles.name(), std::vector<Vec<Dim>>(p->n_global), std::vector<Real>(p->n_global));
  whole.register_fields_like(particles);
  for (const auto& part : parts) {
    std::size_t per_particle = sizeof(Index) + sizeof(Vec<Dim>) + sizeof(Real);
    for (const auto& f : particles.fields()) per_particle += f->bytes_per_particle();
    const std::size_t count = part.size() / per_particle;
    std::vector<Index> ids(count);
    std::memcpy(ids.data(), part.data(), count * sizeof(Index));
    const std::byte* in = part.data() + count * sizeof(Index);
    for (std::size_t k = 0; k < count; ++k) std::memcpy(static_cast<void*>(&whole.position[ids[k]]), in + k * sizeof(Vec<Dim>), sizeof(Vec<Dim>));
    in += count * sizeof(Vec<Dim>);
    for (std::size_t k = 0; k < count; ++k) std::memcpy(&whole.volume[ids[k]], in + k * sizeof(Real), sizeof(Real));
    in += count * sizeof(Real);
    for (std::size_t s = 0; s < particles.fields().size(); ++s) {
      // The fields of `whole` with the names of the local ones (the same order once registered).
      auto& target = *whole.fields()[s];
      if (target.name() != particles.fields()[s]->name())
        throw std::logic_error("gather_particles: the fields of '" + particles.name() + "' differ from the gathered set's");
      in += target.unpack(ids, in);
    }
  }
}


namespace {

/// Appends particles `which` of `particles` to `out`: their count, global ids (`id` of each local
/// particle), positions, volumes and every field, each as one block.
template <int Dim>
void pack_particles(const ParticleSet<Dim>& particles, std::span<const Index> id, std::span<const Index> which,
                    std::vector<std::byte>& out) {
  const auto append = [&](const void* data, std::size_t bytes) {
    const std::size_t at = out.size();
    out.resize(at + bytes);
    if (bytes) std::memcpy(out.data() + at, data, bytes);
  };
  const std::uint64_t count = which.size();
  append(&count, sizeof(count));
  for (const Index i : which) append(&id[i], sizeof(Index));
  for (const Index i : which) append(&particles.position[i], sizeof(Vec<Dim>));
  for (const Index i : which) append(&particles.volume[i], sizeof(Real));
  for (const auto& f : particles.fields()) f->pack(which, out);
}

/// The global ids of a message of pack_particles.
inline std::vector<Index> packed_ids(const std::vector<std::byte>& in) {
  std::uint64_t count = 0;
  if (in.empty()) return {};
  std::memcpy(&count, in.data(), sizeof(count));
  std::vector<Index> ids(count);
  if (count) std::memcpy(ids.data(), in.data() + sizeof(count), count * sizeof(Index));
  return ids;
}

/// Writes the particles of a message of pack_particles to the local places `where`.
template <int Dim>
void unpack_particles(ParticleSet<Dim>& particles, const std::vector<std::byte>& in, std::span<const Index> where) {
  if (in.empty()) return;
  const std::byte* at = in.data() + sizeof(std::uint64_t) + where.size() * sizeof(Index);
  for (const Index i : where) {
    std::memcpy(static_cast<void*>(&particles.position[i]), at, sizeof(Vec<Dim>));
    at += sizeof(Vec<Dim>);
  }
  for (const Index i : where) {
    std::memcpy(&particles.volume[i], at, sizeof(Real));
    at += sizeof(Real);
  }
  for (const auto& f : particles.fields()) at += f->unpack(where, at);
}

/// Sends list[q] of the local particles to every rank q and makes what arrives the local particles
/// [first, first + arriving), in increasing global id; returns their global ids and, per sender,
/// the places its particles went to (in the order it sent them).
template <int Dim>
std::pair<std::vector<Index>, std::vector<std::vector<Index>>> send_particles(
    ParticleSet<Dim>& particles, std::span<const Index> id, const std::vector<std::vector<Index>>& list,
    std::size_t first, const Communicator& comm) {
  std::vector<std::vector<std::byte>> send(list.size());
  for (std::size_t q = 0; q < list.size(); ++q) pack_particles<Dim>(particles, id, list[q], send[q]);
  const auto receive = comm.exchange(send);
  std::vector<std::pair<Index, std::pair<std::size_t, std::size_t>>> arriving;  // (id, (sender, k))
  std::vector<std::vector<Index>> ids(receive.size()), where(receive.size());
  for (std::size_t q = 0; q < receive.size(); ++q) {
    ids[q] = packed_ids(receive[q]);
    for (std::size_t k = 0; k < ids[q].size(); ++k) arriving.push_back({ids[q][k], {q, k}});
    where[q].resize(ids[q].size());
  }
  std::sort(arriving.begin(), arriving.end());
  std::vector<Index> arrived(arriving.size());
  for (std::size_t m = 0; m < arriving.size(); ++m) {
    arrived[m] = arriving[m].first;
    where[arriving[m].second.first][arriving[m].second.second] = static_cast<Index>(first + m);
  }
  particles.resize(first + arriving.size());
  for (std::size_t q = 0; q < receive.size(); ++q) unpack_particles<Dim>(particles, receive[q], where[q]);
  return {std::move(arrived), std::move(where)};
}

}  // namespace

#ifdef CARDIOSPH_WITH_MPI

template <int Dim>
struct MovingPartition<Dim>::Cuts {
  Zoltan_Struct* zz = nullptr;
  ZoltanPoints<Dim> points;
  ~Cuts() {
    if (zz) Zoltan_Destroy(&zz);
  }
  /// This rank's region (Zoltan_RCB_Box: the cuts that bound it, +-DBL_MAX where none does).
  std::array<double, 3> lower{}, upper{};
  void cut(const Communicator& comm) {
    if (zz) Zoltan_Destroy(&zz);
    zz = bisect<Dim>(comm, points, true, nullptr);
    int dim = 0;
    if (Zoltan_RCB_Box(zz, comm.rank(), &dim, &lower[0], &lower[1], &lower[2], &upper[0], &upper[1], &upper[2]) != ZOLTAN_OK)
      throw std::runtime_error("distribution: Zoltan gave no region for rank " + std::to_string(comm.rank()));
  }
  /// Whether x lies inside this rank's region farther than `margin` from its every side. Such a
  /// point is this rank's (margin 0), and with margin r no other region lies within r of it: the
  /// point and box queries below would answer this rank alone, and are skipped.
  bool inside(const Vec<Dim>& x, Real margin) const {
    for (int d = 0; d < Dim; ++d)
      if (!(lower[d] + double(margin) < double(x[d]) && double(x[d]) < upper[d] - double(margin))) return false;
    return true;
  }
  int owner(const Vec<Dim>& x) const {
    double c[3] = {0, 0, 0};
    for (int d = 0; d < Dim; ++d) c[d] = double(x[d]);
    int proc = -1, part = -1;
    if (Zoltan_LB_Point_PP_Assign(zz, c, &proc, &part) != ZOLTAN_OK || part < 0)
      throw std::runtime_error("distribution: Zoltan placed no rank at " + std::to_string(c[0]));
    return part;
  }
  /// The ranks whose regions meet the box of half-width r around x.
  void near(const Vec<Dim>& x, Real r, std::vector<int>& parts, std::vector<int>& procs) const {
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    for (int d = 0; d < Dim; ++d) {
      lo[d] = double(x[d] - r);
      hi[d] = double(x[d] + r);
    }
    int n_procs = 0, n_parts = 0;
    if (Zoltan_LB_Box_PP_Assign(zz, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2], procs.data(), &n_procs, parts.data(),
                                &n_parts) != ZOLTAN_OK)
      throw std::runtime_error("distribution: Zoltan's box assignment failed");
    parts.resize(static_cast<std::size_t>(n_parts));
  }
};

#else

template <int Dim>
struct MovingPartition<Dim>::Cuts {};

#endif

template <int Dim>
MovingPartition<Dim>::MovingPartition(Real ghost_radius, std::size_t rebalance_interval, const Communicator& comm)
    : cuts_(std::make_unique<Cuts>()), ghost_radius_(ghost_radius), interval_(std::max<std::size_t>(rebalance_interval, 1)),
      comm_(comm) {
  if (!(ghost_radius > 0)) throw std::invalid_argument("distribution: the ghost radius must be positive");
}

template <int Dim>
MovingPartition<Dim>::~MovingPartition() = default;

template <int Dim>
void MovingPartition<Dim>::update(ParticleSet<Dim>& particles) {
  if (comm_.size() == 1) return;
#ifdef CARDIOSPH_WITH_MPI
  const std::size_t ranks = static_cast<std::size_t>(comm_.size()), me = static_cast<std::size_t>(comm_.rank());
  std::size_t n_global = 0;
  std::vector<Index> id;  // global id of every local particle
  std::size_t n_owned = 0;
  if (!particles.partition()) {
    // Every rank holds the whole set: keep a slice of it as owned until the first cut.
    if (updates_ > 0) throw std::logic_error("particle set '" + particles.name() + "' lost its partition");
    n_global = particles.n_particles();
    if (double(n_global) != comm_.min(double(n_global)) || double(n_global) != comm_.max(double(n_global)))
      throw std::invalid_argument("particle set '" + particles.name() + "': the ranks built different particle sets (" +
                                  std::to_string(n_global) + " particles on rank " + std::to_string(me) + ")");
    if (n_global < ranks)
      throw std::invalid_argument("particle set '" + particles.name() + "' has " + std::to_string(n_global) +
                                  " particles for " + std::to_string(ranks) + " ranks; run on fewer ranks");
    for (std::size_t g = n_global * me / ranks; g < n_global * (me + 1) / ranks; ++g) id.push_back(static_cast<Index>(g));
    particles.select(id);
    n_owned = id.size();
  } else {
    const auto& p = *particles.partition();
    n_global = p.n_global;
    n_owned = p.n_owned;
    id = p.global_id;
  }
  auto& cuts = *cuts_;
  if (updates_ % interval_ == 0) {
    cuts.points.position.assign(particles.position.begin(), particles.position.begin() + static_cast<std::ptrdiff_t>(n_owned));
    cuts.points.id.assign(id.begin(), id.begin() + static_cast<std::ptrdiff_t>(n_owned));
    cuts.cut(comm_);
    ++rebalances_;
  }
  ++updates_;

  // 1. Every owned particle to the rank of its region (this one included).
  std::vector<std::vector<Index>> go(ranks);
  for (std::size_t i = 0; i < n_owned; ++i) {
    const Vec<Dim>& x = particles.position[i];
    go[cuts.inside(x, 0) ? me : static_cast<std::size_t>(cuts.owner(x))].push_back(static_cast<Index>(i));
  }
  auto [owned, arrived_from] = send_particles<Dim>(particles, id, go, 0, comm_);
  (void)arrived_from;

  // 2. Ghosts: each owned particle to the other ranks whose regions lie within the ghost radius.
  std::vector<std::vector<Index>> ghost_to(ranks);
  std::vector<int> parts(ranks), procs(ranks);
  for (std::size_t i = 0; i < owned.size(); ++i) {
    if (cuts.inside(particles.position[i], ghost_radius_)) continue;
    parts.resize(ranks);
    cuts.near(particles.position[i], ghost_radius_, parts, procs);
    for (const int q : parts)
      if (static_cast<std::size_t>(q) != me) ghost_to[static_cast<std::size_t>(q)].push_back(static_cast<Index>(i));
  }
  auto [ghosts, ghost_places] = send_particles<Dim>(particles, owned, ghost_to, owned.size(), comm_);

  auto partition = std::make_shared<Partition<Dim>>();
  partition->n_global = n_global;
  partition->n_owned = owned.size();
  partition->global_id = owned;
  partition->global_id.insert(partition->global_id.end(), ghosts.begin(), ghosts.end());
  partition->id_order.resize(partition->global_id.size());
  std::vector<Index> local(partition->global_id.size());
  for (std::size_t k = 0; k < local.size(); ++k) local[k] = static_cast<Index>(k);
  std::merge(local.begin(), local.begin() + static_cast<std::ptrdiff_t>(owned.size()),
             local.begin() + static_cast<std::ptrdiff_t>(owned.size()), local.end(), partition->id_order.begin(),
             [&](Index a, Index b) { return partition->global_id[a] < partition->global_id[b]; });
  Vec<Dim> lower = Vec<Dim>::Constant(std::numeric_limits<Real>::max());
  for (std::size_t i = 0; i < owned.size(); ++i) lower = lower.cwiseMin(particles.position[i]);
  for (int d = 0; d < Dim; ++d) lower[d] = static_cast<Real>(comm_.min(double(lower[d])));
  partition->grid_origin = lower;
  partition->send = std::move(ghost_to);
  partition->receive = std::move(ghost_places);
  partition->moves = true;
  particles.set_partition(std::move(partition));
#else
  (void)particles;
#endif
}

template class MovingPartition<2>;
template class MovingPartition<3>;
template void distribute<2>(ParticleSet<2>&, Real, const Communicator&, std::span<const Index>);
template void distribute<3>(ParticleSet<3>&, Real, const Communicator&, std::span<const Index>);
template GlobalParticle<2> first_over_ranks<2>(const ParticleSet<2>&, std::size_t);
template GlobalParticle<3> first_over_ranks<3>(const ParticleSet<3>&, std::size_t);
template void gather_particles<2>(const ParticleSet<2>&, ParticleSet<2>&);
template void gather_particles<3>(const ParticleSet<3>&, ParticleSet<3>&);

}  // namespace sph
