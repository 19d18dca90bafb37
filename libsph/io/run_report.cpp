#include "libsph/io/run_report.hpp"

#include "libsph/io/atomic_file.hpp"

namespace sph {

nlohmann::json RunReport::to_json() const {
  nlohmann::json out;
  out["scene"] = scene;
  out["status"] = status;
  if (!message.empty()) out["message"] = message;
  out["wall_time_s"] = wall_time_s;
  out["simulated_time"] = simulated_time;
  out["steps"] = steps;
  out["threads"] = threads;
  out["particles"] = particles;
  out["memory_bytes"] = memory_bytes;
  out["parameters"] = parameters;
  out["results"] = results;
  if (!errors.empty() || !reference.empty()) {
    out["errors"] = errors;
    out["reference"] = reference;
  }
  return out;
}

void RunReport::write(const std::filesystem::path& path) const { write_file_atomically(path, to_json().dump(2) + "\n"); }

}  // namespace sph
