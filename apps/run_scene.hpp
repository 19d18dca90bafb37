#pragma once
// Runs one scene under the run contract: parameters from defaults, config file and --set;
// everything checked before a file is written; the run goes into "<output>.partial" and is renamed
// to <output> when it ends (a failed run keeps its last good state and a report with status
// "failed"); report.json written last.
//
// Checkpoints (scenes whose checkpoints() is true): --checkpoint-interval writes <output>/checkpoint.bin
// every so much simulated time; Ctrl-C, SIGTERM or --interrupt-at write it and stop the run there
// (status "interrupted", exit code 3, the folder renamed to <output> as for any run). `--resume DIR`
// reads DIR/checkpoint.bin (DIR: an interrupted run, or the ".partial" folder of a killed one),
// takes the scene's parameters from it, copies DIR into "<output>.resume", continues the run there
// and replaces <output> with it when it ends. A checkpoint of another scene, format version, or a
// truncated or damaged one is refused (exit 2) before anything is written.

#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "apps/scenes/scene.hpp"

namespace cardiosph {

struct CommonOptions {
  std::filesystem::path output;          ///< empty: output/<scene>
  std::string config;                    ///< .toml or .json
  std::vector<std::string> assignments;  ///< key=value
  std::string resolution, end_time;      ///< shortcuts for --set resolution=, end_time=
  long threads = 0;                      ///< 0: all cores
  bool quiet = false;
  bool output_pieces = false;            ///< distributed runs: .pvtu pieces per rank (libsph/io/particle_output.hpp)
  bool print_parameters_only = false;  ///< print the parameters (after checks) and stop
  bool check_only = false;             ///< check the parameters and stop, silently
  double checkpoint_interval = 0;      ///< > 0: a checkpoint every this much simulated time
  /// Stop with a checkpoint at the first step at or after this time (NaN: not asked for).
  double interrupt_at = std::numeric_limits<double>::quiet_NaN();
  std::filesystem::path resume;        ///< continue the run in this folder from its checkpoint
};

/// 3: the run stopped on request (signal or --interrupt-at) with a checkpoint to resume from.
enum ExitCode { exit_ok = 0, exit_run_failed = 1, exit_bad_input = 2, exit_interrupted = 3 };

struct SceneRunResult {
  int exit_code = exit_ok;
  sph::RunReport report;
  std::filesystem::path output;
};

/// Runs `scene_name` with `options`, plus `extra` assignments applied last (used by studies).
SceneRunResult run_scene(const std::string& scene_name, const CommonOptions& options,
                         const std::vector<std::string>& extra = {});

}  // namespace cardiosph
