#pragma once
// Checkpoints: the complete state of a run at one time, in one file that a later run continues
// from bitwise as if it had never stopped (the run harness writes and loads them,
// libsph/io/run_harness.hpp; the records come from the components, libsph/core/state_archive.hpp).
//
// File format (version 1, little-endian):
//   "CARDIOSPH-CHECKPOINT\n"  magic, 21 bytes
//   u32 format version
//   u64 length of the payload
//   payload: str scene, str parameters (JSON of every parameter's value), f64 time,
//            u64 record count, then per record: str key, str bytes     (str = u64 length + bytes)
//   u64 FNV-1a hash of the payload
// A file of another format version, a truncated or damaged file (length or hash) and one of another
// scene are refused with sph::ParameterError naming the file and the problem.

#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>

#include "libsph/core/state_archive.hpp"

namespace sph {

inline constexpr std::uint32_t checkpoint_format_version = 1;
/// The file name of a run's checkpoint in its output folder.
inline constexpr const char* checkpoint_file_name = "checkpoint.bin";
/// The checkpoint of rank `rank` of a distributed run: rank 0's is checkpoint_file_name (with the
/// scene and parameters, like a one-rank run's), rank r's checkpoint.rank<r>.bin. Each holds that
/// rank's part of the state; a run resumes on the rank count that wrote them.
std::string checkpoint_file_of_rank(int rank);
/// How many ranks wrote the checkpoint in `folder` (1 + its checkpoint.rank<r>.bin files).
int checkpoint_ranks(const std::filesystem::path& folder);

struct Checkpoint {
  std::string scene;
  std::string parameters;  ///< JSON object: parameter -> value, as in report.json
  double time = 0;         ///< simulated time of the state
  StateRecords records;
};

std::string serialise_checkpoint(const Checkpoint& checkpoint);
/// Parses a checkpoint; `source` names it in errors (sph::ParameterError).
Checkpoint parse_checkpoint(std::string_view bytes, const std::string& source);
/// Reads and parses `path` (ParameterError if it is missing, unreadable or not a valid checkpoint).
Checkpoint read_checkpoint(const std::filesystem::path& path);
/// Writes `path` atomically (a temporary name, then a rename).
void write_checkpoint(const std::filesystem::path& path, const Checkpoint& checkpoint);

/// What a run does about checkpoints (RunHarness::Options::checkpoint).
struct CheckpointPlan {
  bool enabled = false;     ///< the scene saves its whole state: interruptions and checkpoints are honoured
  double interval = 0;      ///< > 0: a checkpoint at the first step at or after every multiple of it
  double interrupt_at = std::numeric_limits<double>::infinity();  ///< stop (with a checkpoint) at the first step at or after
  std::shared_ptr<Checkpoint> resume;  ///< continue from this state
  std::string scene;        ///< written into the checkpoint
  std::string parameters;   ///< written into the checkpoint
};

/// The run stopped on request (signal or interrupt time) after writing its checkpoint.
class RunInterrupted : public std::runtime_error {
 public:
  RunInterrupted(double time, std::filesystem::path checkpoint);
  double time() const { return time_; }
  const std::filesystem::path& checkpoint() const { return checkpoint_; }

 private:
  double time_;
  std::filesystem::path checkpoint_;
};

/// Asks the running harness to write a checkpoint and stop after the current step; safe to call
/// from a signal handler.
void request_interrupt() noexcept;
bool interrupt_requested() noexcept;
void clear_interrupt() noexcept;

}  // namespace sph
