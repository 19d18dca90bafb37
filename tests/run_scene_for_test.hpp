#pragma once
// Sets a scene's parameters and runs it the way the application does (check, then run) in a fresh
// temporary folder of this process, quietly, removes the folder and returns the run report.
#include <chrono>
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
