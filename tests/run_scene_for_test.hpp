#pragma once
// Sets a scene's parameters and runs it the way the application does (check, then run) in a fresh
// temporary folder of this process, quietly, removes the folder and returns the run report.
#include <chrono>
#include <filesystem>
#include <memory>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "apps/scenes/scene.hpp"
#include "libsph/io/parameters.hpp"
#include "temporary_folder.hpp"

namespace test {

/// Declares the scene's parameters into `parameters` (which must outlive the run), turns the
/// geometry cache off, applies the assignments ("key=value") and the presets, and checks them.
inline void set_parameters(cardiosph::Scene& scene, sph::Parameters& parameters, const std::vector<std::string>& assignments) {
  scene.declare(parameters);
  if (parameters.has("cache")) parameters.set("cache", "none", "test");
  for (const auto& a : assignments) parameters.set_assignment(a, "test");
  parameters.apply_presets();
  parameters.check();
}

/// The bytes of a file.
inline std::string bytes_of(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The keys of report.json that measure the run (time, memory, threads, the geometry cache) rather
/// than the physics, matched exactly at any depth of the results (an object under one of them, such
/// as the harness's "seconds" per timer, goes with it). Where each is written:
inline const std::set<std::string>& keys_that_measure_the_run() {
  static const std::set<std::string> keys{
      // The report itself (libsph/io/run_report.cpp), should a whole report be compared.
      "wall_time_s", "threads", "memory_bytes",
      // The partition of a distributed run (ranks, owned and ghost particles).
      "distribution",
      // The run harness (libsph/io/run_harness.cpp): seconds per timer and of the time loop, peak RSS.
      "seconds", "peak_rss_mb",
      // Electrophysiology (apps/scenes/electrophysiology/ep_run.cpp, ecg_output.cpp, cell.cpp) and the
      // fluid run (apps/scenes/fluid/fluid_run.cpp).
      "reaction_seconds", "diffusion_seconds", "particle_steps_per_second", "seconds_per_step", "seconds_per_sample",
      "cvode_wall_s",
      // The heart (apps/scenes/electromechanics/heart.cpp) and the geometry stage
      // (apps/scenes/geometry/particles.cpp): timings, and whether the geometry came from the cache,
      // which a resumed run finds that the first run made.
      "seconds_per_beat", "total_seconds", "mechanics_microseconds_per_particle_step", "geometry_seconds", "from_cache",
      "geometry_from_cache"};
  return keys;
}

/// Results without the keys that measure the run rather than the physics (keys_that_measure_the_run).
inline nlohmann::json physics_only(const nlohmann::json& j) {
  if (!j.is_object()) return j;
  nlohmann::json out = nlohmann::json::object();
  for (auto it = j.begin(); it != j.end(); ++it)
    if (!keys_that_measure_the_run().count(it.key())) out[it.key()] = physics_only(it.value());
  return out;
}

inline sph::RunReport run_scene(cardiosph::Scene& scene, const std::string& name) {
  const TemporaryFolder folder("validation_" + name);
  cardiosph::RunContext ctx;
  ctx.output_dir = folder.path();
  ctx.quiet = true;
  scene.check();
  const auto start = std::chrono::steady_clock::now();
  scene.run(ctx);
  ctx.report.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return ctx.report;
}

/// A fresh scene with the assignments ("key=value") set, run as run_scene does.
inline sph::RunReport run_scene(std::unique_ptr<cardiosph::Scene> scene, const std::vector<std::string>& assignments,
                                const std::string& name) {
  sph::Parameters parameters;
  set_parameters(*scene, parameters, assignments);
  return run_scene(*scene, name);
}

/// A number of the report's results.
inline double result(const sph::RunReport& r, const std::string& key) { return r.results.at(key).get<double>(); }

}  // namespace test
