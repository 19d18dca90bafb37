#pragma once
// Particle storage as a structure of arrays.
//
// Every particle set has positions and volumes. Any other field is registered on first request by
// the dynamics that needs it (`register_field`), which returns a typed handle; loops fetch the
// array once through the handle (`field(handle)`) and then index it directly, so there is no string
// lookup inside a particle loop and a scene pays only for the fields its dynamics use. The name of a
// field is its label for output only. permute() reorders every particle's entries together (for
// sorting along the cell list, particle_sorting.hpp); select() also deletes and copies particles
// (open boundaries of a fluid), every field with them.
//
// A distributed set (libsph/core/distribution.hpp) holds this rank's owned particles followed by
// ghosts; n_owned() says where the ghosts begin (all particles are owned in a serial run), and
// partition() describes the layout.

#include <cstring>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <typeinfo>
#include <vector>

#include "libsph/core/partition.hpp"
#include "libsph/core/state_archive.hpp"
#include "libsph/core/types.hpp"

namespace sph {

/// values[k] = old values[order[k]] for k < order.size(), through `scratch` (which keeps its storage
/// for the next call); `order` may leave entries out and repeat others.
template <class T>
void select_values(std::vector<T>& values, std::span<const Index> order, std::vector<T>& scratch) {
  scratch.resize(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) scratch[k] = values[order[k]];
  values.swap(scratch);
}

/// Type-erased base of one field array (output and bookkeeping only, never in a hot loop).
class FieldArrayBase {
 public:
  FieldArrayBase(std::string name, bool write_output) : name_(std::move(name)), write_output_(write_output) {}
  virtual ~FieldArrayBase() = default;
  const std::string& name() const { return name_; }
  bool write_output() const { return write_output_; }
  void set_write_output(bool on) { write_output_ = on; }
  virtual const std::type_info& value_type() const = 0;
  virtual std::size_t size() const = 0;
  virtual std::size_t bytes_per_particle() const = 0;
  /// values[k] = old values[order[k]] for every k of `order` (the new size).
  virtual void select(std::span<const Index> order) = 0;
  /// Keeps the first n values, or appends default ones up to n.
  virtual void resize(std::size_t n) = 0;
  /// Saves or loads the values under the field's name (checkpoints).
  virtual void checkpoint(StateArchive& archive) = 0;
  /// Appends the bytes of the values of `which` to `out` (messages between ranks; plain data only).
  virtual void pack(std::span<const Index> which, std::vector<std::byte>& out) const = 0;
  /// Reads the values of `where` from `in` (as pack() wrote them); returns the bytes read.
  virtual std::size_t unpack(std::span<const Index> where, const std::byte* in) = 0;
  /// An array of the same name, type and output flag holding n default values.
  virtual std::unique_ptr<FieldArrayBase> make_like(std::size_t n) const = 0;

 private:
  std::string name_;
  bool write_output_;
};

template <class T>
class FieldArray final : public FieldArrayBase {
 public:
  FieldArray(std::string name, std::size_t n, const T& initial, bool write_output)
      : FieldArrayBase(std::move(name), write_output), values(n, initial) {}
  const std::type_info& value_type() const override { return typeid(T); }
  std::size_t size() const override { return values.size(); }
  std::size_t bytes_per_particle() const override { return sizeof(T); }
  void select(std::span<const Index> order) override { select_values(values, order, scratch_); }
  void resize(std::size_t n) override { values.resize(n); }
  void checkpoint(StateArchive& archive) override {
    if constexpr (is_plain_data_v<T>) archive.io(name(), values);
    else throw std::logic_error("field '" + name() + "' cannot be checkpointed: its values are not plain data");
  }
  void pack(std::span<const Index> which, std::vector<std::byte>& out) const override {
    if constexpr (is_plain_data_v<T>) {
      const std::size_t start = out.size();
      out.resize(start + which.size() * sizeof(T));
      for (std::size_t k = 0; k < which.size(); ++k)
        std::memcpy(out.data() + start + k * sizeof(T), &values[which[k]], sizeof(T));
    } else {
      throw std::logic_error("field '" + name() + "' cannot be sent between ranks: its values are not plain data");
    }
  }
  std::size_t unpack(std::span<const Index> where, const std::byte* in) override {
    if constexpr (is_plain_data_v<T>) {
      for (std::size_t k = 0; k < where.size(); ++k) std::memcpy(static_cast<void*>(&values[where[k]]), in + k * sizeof(T), sizeof(T));
      return where.size() * sizeof(T);
    } else {
      throw std::logic_error("field '" + name() + "' cannot be sent between ranks: its values are not plain data");
    }
  }
  std::unique_ptr<FieldArrayBase> make_like(std::size_t n) const override {
    if constexpr (requires { T::Zero(); }) return std::make_unique<FieldArray<T>>(name(), n, T(T::Zero()), write_output());
    else return std::make_unique<FieldArray<T>>(name(), n, T{}, write_output());
  }
  std::vector<T> values;

 private:
  std::vector<T> scratch_;
};

/// Typed handle to a registered field; cheap to copy, valid for the particle set that issued it.
template <class T>
struct FieldHandle {
  std::size_t slot = static_cast<std::size_t>(-1);
  bool valid() const { return slot != static_cast<std::size_t>(-1); }
};

template <int Dim>
class ParticleSet {
 public:
  using VecD = Vec<Dim>;

  ParticleSet() = default;
  ParticleSet(std::string name, std::vector<VecD> positions, std::vector<Real> volumes)
      : position(std::move(positions)), volume(std::move(volumes)), name_(std::move(name)) {
    if (position.size() != volume.size())
      throw std::invalid_argument("particle set '" + name_ + "': positions and volumes differ in count");
  }

  const std::string& name() const { return name_; }
  /// Local particles: owned and ghosts.
  std::size_t n_particles() const { return position.size(); }
  /// Particles this rank computes: the first n_owned() (all of them unless distributed).
  std::size_t n_owned() const { return partition_ ? partition_->n_owned : n_particles(); }
  /// The layout of a distributed set, or nullptr.
  const Partition<Dim>* partition() const { return partition_.get(); }
  /// Makes this set one rank's part (distribution.hpp); the particles must already be in its layout.
  void set_partition(std::shared_ptr<const Partition<Dim>> partition) {
    if (partition && partition->global_id.size() != n_particles())
      throw std::invalid_argument("particle set '" + name_ + "': partition of the wrong length");
    partition_ = std::move(partition);
  }
  /// Adds, for every field of `other` that this set lacks, a field of the same name and type
  /// (default values), in the order of `other` (the whole set gathered from a distributed one).
  void register_fields_like(const ParticleSet& other) {
    for (const auto& f : other.fields_) {
      bool present = false;
      for (const auto& mine : fields_) present = present || mine->name() == f->name();
      if (!present) fields_.push_back(f->make_like(n_particles()));
    }
  }

  /// Registers `name` with the initial value, or returns the handle of the existing field of that
  /// name (its values are kept). Registering the same name with another type is a logic error.
  template <class T>
  FieldHandle<T> register_field(const std::string& name, const T& initial = T{}, bool write_output = true) {
    for (std::size_t s = 0; s < fields_.size(); ++s) {
      if (fields_[s]->name() != name) continue;
      if (fields_[s]->value_type() != typeid(T))
        throw std::logic_error("field '" + name + "' of particle set '" + name_ + "' exists with another type");
      return FieldHandle<T>{s};
    }
    fields_.push_back(std::make_unique<FieldArray<T>>(name, n_particles(), initial, write_output));
    return FieldHandle<T>{fields_.size() - 1};
  }

  /// Handle of an existing field, or an invalid handle.
  template <class T>
  FieldHandle<T> find_field(const std::string& name) const {
    for (std::size_t s = 0; s < fields_.size(); ++s)
      if (fields_[s]->name() == name && fields_[s]->value_type() == typeid(T)) return FieldHandle<T>{s};
    return {};
  }

  template <class T>
  std::span<T> field(FieldHandle<T> handle) {
    return static_cast<FieldArray<T>&>(*fields_.at(handle.slot)).values;
  }
  template <class T>
  std::span<const T> field(FieldHandle<T> handle) const {
    return static_cast<const FieldArray<T>&>(*fields_.at(handle.slot)).values;
  }

  /// All registered fields (for writers and memory reports).
  const std::vector<std::unique_ptr<FieldArrayBase>>& fields() const { return fields_; }

  /// Bytes per particle of everything stored (positions, volumes and registered fields).
  std::size_t bytes_per_particle() const {
    std::size_t bytes = sizeof(VecD) + sizeof(Real);
    for (const auto& f : fields_) bytes += f->bytes_per_particle();
    return bytes;
  }

  /// Reorders the particles: particle k becomes the old particle order[k], in the positions, the
  /// volumes and every field. Relations and particle indices held elsewhere (constraints, probes)
  /// refer to the old order and must be rebuilt.
  void permute(std::span<const Index> order) {
    if (order.size() != n_particles())
      throw std::invalid_argument("particle set '" + name_ + "': permutation of the wrong length");
    select(order);
  }

  /// Keeps, deletes and copies particles: particle k becomes the old particle order[k] for every k of
  /// `order`, whose length is the new number of particles (an old particle left out is deleted, one
  /// named twice is copied). Relations and indices held elsewhere must be rebuilt, as after permute().
  void select(std::span<const Index> order) {
    if (partition_)
      throw std::logic_error("particle set '" + name_ + "': the particles of a distributed set cannot be reordered");
    for (const Index k : order)
      if (static_cast<std::size_t>(k) >= n_particles())
        throw std::invalid_argument("particle set '" + name_ + "': selection names particle " + std::to_string(k) +
                                    " of " + std::to_string(n_particles()));
    select_values(position, order, position_scratch_);
    select_values(volume, order, volume_scratch_);
    for (auto& f : fields_) f->select(order);
  }

  /// Keeps the first n particles, or appends particles at the origin with no volume and default
  /// field values up to n, and drops the partition: for a distributed set whose particles arrive in
  /// messages (distribution.cpp), which sets its new partition once they are in place.
  void resize(std::size_t n) {
    partition_.reset();
    position.resize(n, VecD::Zero());
    volume.resize(n, Real(0));
    for (auto& f : fields_) f->resize(n);
  }

  /// Saves or loads the positions, the volumes and every registered field (checkpoints). Loading
  /// takes the particle count of the saved state and refuses a field of another length.
  void checkpoint(StateArchive& archive) {
    archive.io("position", position);
    archive.io("volume", volume);
    for (auto& f : fields_) f->checkpoint(archive);
    if (partition_) {  // this rank's part: the state must be of the same particles, in the same places
      std::vector<Index> ids = partition_->global_id;
      std::size_t owned = partition_->n_owned;
      archive.io("partition_global_id", ids);
      archive.io("partition_owned", owned);
      if (archive.loading() && (ids != partition_->global_id || owned != partition_->n_owned))
        throw StateError("particle set '" + name_ + "': the state holds other particles on this rank (another partition)");
    }
    if (archive.loading()) {
      if (volume.size() != position.size())
        throw StateError("particle set '" + name_ + "': the state has " + std::to_string(position.size()) + " positions and " +
                         std::to_string(volume.size()) + " volumes");
      for (const auto& f : fields_)
        if (f->size() != position.size())
          throw StateError("particle set '" + name_ + "': field '" + f->name() + "' has " + std::to_string(f->size()) +
                           " values for " + std::to_string(position.size()) + " particles");
    }
  }

  std::vector<VecD> position;  ///< current position [length unit of the scene]
  std::vector<Real> volume;    ///< particle volume [length^Dim]

 private:
  std::string name_;
  std::vector<std::unique_ptr<FieldArrayBase>> fields_;
  std::shared_ptr<const Partition<Dim>> partition_;
  std::vector<VecD> position_scratch_;
  std::vector<Real> volume_scratch_;
};

}  // namespace sph
