#include "apps/run_scene.hpp"

#include <chrono>
#include <iostream>

#include "libsph/core/numerical_failure.hpp"
#include "libsph/core/parallel.hpp"

namespace cardiosph {
namespace {

namespace fs = std::filesystem;

// An existing output folder is replaced only if it is empty or holds an earlier run (report.json).
void check_output_folder(const fs::path& output) {
  std::error_code ec;
  if (!fs::exists(output, ec)) return;
  if (!fs::is_directory(output, ec))
    throw sph::ParameterError("output '" + output.string() + "' exists and is not a folder");
  if (fs::is_empty(output, ec) || fs::exists(output / "report.json", ec)) return;
  throw sph::ParameterError("output folder '" + output.string() +
                            "' exists and does not hold an earlier run (no report.json); choose another --output");
}

void replace_folder(const fs::path& staging, const fs::path& output) {
  if (fs::exists(output)) fs::remove_all(output);
  fs::rename(staging, output);
}

}  // namespace

SceneRunResult run_scene(const std::string& scene_name, const CommonOptions& options,
                         const std::vector<std::string>& extra) {
  SceneRunResult result;
  const SceneEntry* entry = find_scene(scene_name);
  if (!entry) throw sph::ParameterError("unknown scene '" + scene_name + "' (see 'cardiosph list')");

  // 1. Parameters: defaults, config file, --resolution/--end-time, --set, extra, then the chosen
  // presets on what those left alone; then checks.
  auto scene = entry->make();
  sph::Parameters parameters;
  scene->declare(parameters);
  if (!options.config.empty()) parameters.load_file(options.config);
  if (!options.resolution.empty()) parameters.set("resolution", options.resolution, "--resolution");
  if (!options.end_time.empty()) parameters.set("end_time", options.end_time, "--end-time");
  for (const auto& a : options.assignments) parameters.set_assignment(a, "--set");
  for (const auto& a : extra) parameters.set_assignment(a, "--sweep");
  parameters.apply_presets();
  parameters.check();
  scene->check();
  if (options.threads < 0) throw sph::ParameterError("option '--threads' = " + std::to_string(options.threads) + ": must be >= 0");
  if (options.check_only) return result;
  if (options.print_parameters_only) {
    std::cout << "parameters of " << scene_name << ":\n" << parameters.describe();
    return result;
  }

  const fs::path output = options.output.empty() ? fs::path("output") / scene_name : options.output;
  check_output_folder(output);
  result.output = output;
  if (!options.quiet) std::cout << "cardiosph " << scene_name << ", parameters:\n" << parameters.describe() << std::flush;

  // 2. Run into a staging folder.
  const fs::path staging = fs::path(output.string() + ".partial");
  fs::remove_all(staging);
  fs::create_directories(staging);
  sph::ThreadLimit thread_limit(static_cast<std::size_t>(options.threads));
  RunContext ctx{staging, options.quiet, {}};
  ctx.report.scene = scene_name;
  ctx.report.parameters = parameters.to_json();
  ctx.report.threads = sph::active_thread_count();
  const auto start = std::chrono::steady_clock::now();
  try {
    scene->run(ctx);
  } catch (const sph::ParameterError&) {
    fs::remove_all(staging);
    throw;
  } catch (const std::invalid_argument& error) {
    // Input the scene could only reject while building (e.g. a geometry): nothing is kept.
    fs::remove_all(staging);
    throw sph::ParameterError(error.what());
  } catch (const std::exception& error) {
    ctx.report.status = "failed";
    ctx.report.message = error.what();
    result.exit_code = exit_run_failed;
    std::cerr << "cardiosph " << scene_name << ": run failed: " << error.what() << '\n';
  }
  ctx.report.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ctx.report.write(staging / "report.json");
  replace_folder(staging, output);
  result.report = ctx.report;
  return result;
}

}  // namespace cardiosph
