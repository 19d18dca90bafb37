#pragma once
// Runs a scene the way the application does (check, then run) in a fresh temporary folder, quietly,
// removes the folder and returns the run report.
#include <chrono>
#include <filesystem>
#include <string>

#include "apps/scenes/scene.hpp"

namespace test {

inline sph::RunReport run_scene(cardiosph::Scene& scene, const std::string& name) {
  namespace fs = std::filesystem;
  cardiosph::RunContext ctx;
  ctx.output_dir = fs::temp_directory_path() / ("cardiosph_validation_" + name);
  fs::remove_all(ctx.output_dir);
  fs::create_directories(ctx.output_dir);
  ctx.quiet = true;
  scene.check();
  const auto start = std::chrono::steady_clock::now();
  scene.run(ctx);
  ctx.report.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  fs::remove_all(ctx.output_dir);
  return ctx.report;
}

}  // namespace test
