#pragma once
// Runs a scene the way the application does (check, then run) in a fresh temporary folder of this
// process, quietly, removes the folder and returns the run report.
#include <chrono>
#include <string>

#include "apps/scenes/scene.hpp"
#include "temporary_folder.hpp"

namespace test {

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
