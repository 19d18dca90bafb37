#pragma once
// Sets a scene's parameters and runs it the way the application does (check, then run) in a fresh
// temporary folder of this process, quietly, removes the folder and returns the run report.
#include <chrono>
#include <filesystem>
#include <fstream>
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

/// Results without the keys that measure the run rather than the physics.
inline nlohmann::json physics_only(const nlohmann::json& j) {
  if (!j.is_object()) return j;
  nlohmann::json out = nlohmann::json::object();
  for (auto it = j.begin(); it != j.end(); ++it) {
    const std::string& k = it.key();
    const bool measures_the_run = k.find("second") != std::string::npos || k.find("wall") != std::string::npos ||
                                  k.find("rss") != std::string::npos || k.find("timing") != std::string::npos ||
                                  k.find("microseconds") != std::string::npos || k.find("per_second") != std::string::npos ||
                                  k.find("from_cache") != std::string::npos || k == "threads";
    if (!measures_the_run) out[k] = physics_only(it.value());
  }
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

}  // namespace test
