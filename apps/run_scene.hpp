#pragma once
// Runs one scene under the run contract: parameters from defaults, config file and --set;
// everything checked before a file is written; the run goes into "<output>.partial" and is renamed
// to <output> when it ends (a failed run keeps its last good state and a report with status
// "failed"); report.json written last.

#include <filesystem>
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
  bool print_parameters_only = false;  ///< print the parameters (after checks) and stop
  bool check_only = false;             ///< check the parameters and stop, silently
};

enum ExitCode { exit_ok = 0, exit_run_failed = 1, exit_bad_input = 2 };

struct SceneRunResult {
  int exit_code = exit_ok;
  sph::RunReport report;
  std::filesystem::path output;
};

/// Runs `scene_name` with `options`, plus `extra` assignments applied last (used by studies).
SceneRunResult run_scene(const std::string& scene_name, const CommonOptions& options,
                         const std::vector<std::string>& extra = {});

}  // namespace cardiosph
