#pragma once
// The state of a run as named byte records, and the archive through which every component saves
// and restores its part of it (checkpoint and restart, libsph/io/checkpoint.hpp).
//
// A component lists its changing members once, in a function that serves both directions:
//
//   void checkpoint(sph::StateArchive& a) {
//     a.io("steps", steps_);            // any plain value (is_plain_data_v)
//     a.io("previous", previous_);      // a std::vector of plain values
//     a.io("log", log_text_);           // a std::string
//   }
//
// Saving copies the bytes into the record `<prefix>/<key>`; loading copies them back, and throws
// StateError naming the record when it is missing or has the wrong size. What a component rebuilds
// from its parameters (neighbour lists in the reference configuration, settings, constants) is not
// saved: a resumed run first builds the scene exactly as at the start and then loads the records
// over it.

#include <Eigen/Core>
#include <array>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace sph {

/// Values that are copied as their bytes: trivially copyable types, fixed-size Eigen matrices (which
/// hold only their coefficients but declare copy constructors) and std::arrays of either.
template <class T>
struct is_plain_data : std::is_trivially_copyable<T> {};
template <class S, int R, int C, int O, int MR, int MC>
  requires(R > 0 && C > 0 && std::is_arithmetic_v<S>)
struct is_plain_data<Eigen::Matrix<S, R, C, O, MR, MC>> : std::true_type {};
template <class T, std::size_t N>
struct is_plain_data<std::array<T, N>> : is_plain_data<T> {};
template <class T>
inline constexpr bool is_plain_data_v = is_plain_data<T>::value;

/// A record missing from a state, or of the wrong size.
class StateError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Named byte records (key -> bytes), in key order.
using StateRecords = std::map<std::string, std::string>;

class StateArchive {
 public:
  enum class Mode { save, load };

  StateArchive(StateRecords& records, Mode mode, std::string prefix = {})
      : records_(records), mode_(mode), prefix_(std::move(prefix)) {}

  bool saving() const { return mode_ == Mode::save; }
  bool loading() const { return mode_ == Mode::load; }
  /// The archive of a part: its keys are `<prefix>/<name>/...`.
  StateArchive part(const std::string& name) const { return StateArchive(records_, mode_, key(name)); }

  template <class T>
    requires is_plain_data_v<T>
  void io(const std::string& name, T& value) {
    if (saving()) {
      records_[key(name)].assign(reinterpret_cast<const char*>(&value), sizeof(T));
      return;
    }
    const std::string& bytes = find(name);
    if (bytes.size() != sizeof(T))
      throw StateError("state record '" + key(name) + "' holds " + std::to_string(bytes.size()) + " bytes, expected " +
                       std::to_string(sizeof(T)));
    std::memcpy(static_cast<void*>(&value), bytes.data(), sizeof(T));
  }

  /// A vector keeps the length it was saved with.
  template <class T>
    requires is_plain_data_v<T>
  void io(const std::string& name, std::vector<T>& values) {
    if (saving()) {
      records_[key(name)].assign(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
      return;
    }
    const std::string& bytes = find(name);
    if (bytes.size() % sizeof(T) != 0)
      throw StateError("state record '" + key(name) + "' holds " + std::to_string(bytes.size()) +
                       " bytes, not a whole number of " + std::to_string(sizeof(T)) + "-byte values");
    values.resize(bytes.size() / sizeof(T));
    if (!bytes.empty()) std::memcpy(static_cast<void*>(values.data()), bytes.data(), bytes.size());
  }

  void io(const std::string& name, std::string& text) {
    if (saving()) records_[key(name)] = text;
    else text = find(name);
  }

  /// Loading only: whether the record exists.
  bool has(const std::string& name) const { return records_.count(key(name)) > 0; }

 private:
  std::string key(const std::string& name) const { return prefix_.empty() ? name : prefix_ + "/" + name; }
  const std::string& find(const std::string& name) const {
    const auto it = records_.find(key(name));
    if (it == records_.end()) throw StateError("the state has no record '" + key(name) + "'");
    return it->second;
  }

  StateRecords& records_;
  Mode mode_;
  std::string prefix_;
};

}  // namespace sph
