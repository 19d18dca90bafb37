#pragma once
// report.json of a run (the run contract every scene follows):
//   scene, status ("completed" | "failed"), message, wall_time_s, simulated_time, steps,
//   particles {body: count}, parameters {key: value}, results {name: number},
//   errors {name: number} and reference (text) for scenes that compare with a reference,
//   memory_bytes {body: bytes}, threads.

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

namespace sph {

struct RunReport {
  std::string scene;
  std::string status = "completed";
  std::string message;
  double wall_time_s = 0;
  double simulated_time = 0;
  std::size_t steps = 0;
  std::size_t threads = 0;
  nlohmann::json particles = nlohmann::json::object();
  nlohmann::json memory_bytes = nlohmann::json::object();
  nlohmann::json parameters = nlohmann::json::object();
  nlohmann::json results = nlohmann::json::object();
  nlohmann::json errors = nlohmann::json::object();
  std::string reference;

  nlohmann::json to_json() const;
  void write(const std::filesystem::path& path) const;
};

}  // namespace sph
