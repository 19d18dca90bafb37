#pragma once
// A scene: a typed parameter struct with defaults that run out of the box, a declaration of those
// parameters (unit, range, help), checks that reject bad input before any file is written, and a
// run that fills the run report. Applications and tests build scenes the same way.

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

// Scenes write their report's sections (results, errors) as JSON values.
#include <nlohmann/json.hpp>

#include "libsph/io/checkpoint.hpp"
#include "libsph/io/parameters.hpp"
#include "libsph/io/run_report.hpp"

namespace cardiosph {

struct RunContext {
  std::filesystem::path output_dir;  ///< exists and is empty when the run starts
  bool quiet = false;
  sph::RunReport report;
  /// Checkpoints asked for (--checkpoint-interval, --interrupt-at, signals, --resume); a scene that
  /// saves its whole state passes it to its run harness (RunHarness::Options::checkpoint).
  sph::CheckpointPlan checkpoint = {};
};

class Scene {
 public:
  virtual ~Scene() = default;
  /// Binds the scene's parameters; every scene has `resolution` and `end_time`.
  virtual void declare(sph::Parameters& parameters) = 0;
  /// Checks that involve several parameters or derived quantities; throws sph::ParameterError.
  virtual void check() const {}
  /// Runs the scene into ctx.output_dir and fills ctx.report (results, errors, particles, steps).
  virtual void run(RunContext& ctx) = 0;
  /// Whether the run saves its whole state in checkpoints, so that it can be interrupted and resumed.
  virtual bool checkpoints() const { return false; }
  /// Whether the scene runs on several MPI ranks (libsph/core/distribution.hpp).
  virtual bool distributes() const { return false; }
};

struct SceneEntry {
  std::string name;
  std::string summary;
  std::function<std::unique_ptr<Scene>()> make;
  /// Parameters also given as positional arguments (in order), e.g. `cardiosph particles MESH`.
  std::vector<std::string> positional = {};
  /// Parameters also given as `--key value`.
  std::vector<std::string> shortcuts = {};
};

/// Every scene of the application, in the order `cardiosph list` shows them.
const std::vector<SceneEntry>& scene_registry();

/// The entry named `name`, or nullptr.
const SceneEntry* find_scene(const std::string& name);

}  // namespace cardiosph
