#include "libsph/core/distribution.hpp"

#include <algorithm>
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

/// The objects this rank hands to Zoltan: the slice [begin, end) of the global ids, all of weight 1.
template <int Dim>
struct ZoltanSlice {
  const std::vector<Vec<Dim>>* position;
  std::size_t begin, end;
};

template <int Dim>
int slice_count(void* data, int* error) {
  const auto& s = *static_cast<ZoltanSlice<Dim>*>(data);
  *error = ZOLTAN_OK;
  return static_cast<int>(s.end - s.begin);
}

template <int Dim>
void slice_list(void* data, int, int, ZOLTAN_ID_PTR global, ZOLTAN_ID_PTR local, int weight_dim, float* weights,
                int* error) {
  const auto& s = *static_cast<ZoltanSlice<Dim>*>(data);
  for (std::size_t k = 0; k < s.end - s.begin; ++k) {
    global[k] = static_cast<ZOLTAN_ID_TYPE>(s.begin + k);
    local[k] = static_cast<ZOLTAN_ID_TYPE>(k);
    for (int w = 0; w < weight_dim; ++w) weights[k * static_cast<std::size_t>(weight_dim) + static_cast<std::size_t>(w)] = 1.0f;
  }
  *error = ZOLTAN_OK;
}

template <int Dim>
int slice_dimension(void*, int* error) {
  *error = ZOLTAN_OK;
  return Dim;
}

template <int Dim>
void slice_geometry(void* data, int, int, int n, ZOLTAN_ID_PTR global, ZOLTAN_ID_PTR, int dim, double* coordinates,
                    int* error) {
  const auto& s = *static_cast<ZoltanSlice<Dim>*>(data);
  for (int k = 0; k < n; ++k)
    for (int d = 0; d < dim; ++d)
      coordinates[static_cast<std::size_t>(k * dim + d)] = double((*s.position)[global[k]][d]);
  *error = ZOLTAN_OK;
}

/// The rank of every particle: Zoltan's recursive coordinate bisection, each rank contributing a
/// slice of the global ids, the answer shared with every rank.
template <int Dim>
std::vector<int> owners_by_rcb(const std::vector<Vec<Dim>>& position, const Communicator& comm) {
  static const bool initialised = [] {
    float version = 0;
    return Zoltan_Initialize(0, nullptr, &version) == ZOLTAN_OK;
  }();
  if (!initialised) throw std::runtime_error("distribution: Zoltan did not initialise");
  const std::size_t n = position.size(), ranks = static_cast<std::size_t>(comm.size()),
                    r = static_cast<std::size_t>(comm.rank());
  ZoltanSlice<Dim> slice{&position, n * r / ranks, n * (r + 1) / ranks};
  MPI_Comm mpi = *static_cast<const MPI_Comm*>(comm.native_handle());
  Zoltan_Struct* zz = Zoltan_Create(mpi);
  Zoltan_Set_Param(zz, "DEBUG_LEVEL", "0");
  Zoltan_Set_Param(zz, "LB_METHOD", "RCB");
  Zoltan_Set_Param(zz, "NUM_GID_ENTRIES", "1");
  Zoltan_Set_Param(zz, "NUM_LID_ENTRIES", "1");
  Zoltan_Set_Param(zz, "OBJ_WEIGHT_DIM", "1");
  Zoltan_Set_Param(zz, "RETURN_LISTS", "PARTS");
  Zoltan_Set_Param(zz, "RCB_RECTILINEAR_BLOCKS", "0");
  Zoltan_Set_Num_Obj_Fn(zz, slice_count<Dim>, &slice);
  Zoltan_Set_Obj_List_Fn(zz, slice_list<Dim>, &slice);
  Zoltan_Set_Num_Geom_Fn(zz, slice_dimension<Dim>, &slice);
  Zoltan_Set_Geom_Multi_Fn(zz, slice_geometry<Dim>, &slice);
  int changes = 0, n_gid = 0, n_lid = 0, n_import = 0, n_export = 0;
  ZOLTAN_ID_PTR import_global = nullptr, import_local = nullptr, export_global = nullptr, export_local = nullptr;
  int *import_procs = nullptr, *import_to_part = nullptr, *export_procs = nullptr, *export_to_part = nullptr;
  const int status = Zoltan_LB_Partition(zz, &changes, &n_gid, &n_lid, &n_import, &import_global, &import_local,
                                         &import_procs, &import_to_part, &n_export, &export_global, &export_local,
                                         &export_procs, &export_to_part);
  if (status != ZOLTAN_OK) {
    Zoltan_Destroy(&zz);
    throw std::runtime_error("distribution: Zoltan's partition failed (code " + std::to_string(status) + ")");
  }
  // With RETURN_LISTS = PARTS the export lists name the part of every object of the slice.
  std::vector<int> mine(slice.end - slice.begin, static_cast<int>(r));
  for (int k = 0; k < n_export; ++k) mine[export_global[k] - slice.begin] = export_to_part[k];
  Zoltan_LB_Free_Part(&import_global, &import_local, &import_procs, &import_to_part);
  Zoltan_LB_Free_Part(&export_global, &export_local, &export_procs, &export_to_part);
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
void distribute(ParticleSet<Dim>& particles, Real ghost_radius, const Communicator& comm) {
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

  const std::vector<int> owner = owners_by_rcb<Dim>(particles.position, comm);
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

template void distribute<2>(ParticleSet<2>&, Real, const Communicator&);
template void distribute<3>(ParticleSet<3>&, Real, const Communicator&);
template GlobalParticle<2> first_over_ranks<2>(const ParticleSet<2>&, std::size_t);
template GlobalParticle<3> first_over_ranks<3>(const ParticleSet<3>&, std::size_t);
template void gather_particles<2>(const ParticleSet<2>&, ParticleSet<2>&);
template void gather_particles<3>(const ParticleSet<3>&, ParticleSet<3>&);

}  // namespace sph
