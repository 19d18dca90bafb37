#pragma once
// report.json of a run (the run contract every scene follows):
//   scene, status ("completed" | "failed"), message, wall_time_s, simulated_time, steps,
//   particles {body: count}, parameters {key: value}, results {name: number},
//   errors {name: number} and reference (text) for scenes that compare with a reference,
//   memory_bytes {body: bytes}, threads, and ranks when the run is distributed over several.
//
// The sections are JSON objects held out of sight (only <nlohmann/json_fwd.hpp> here): a scene
// that writes `report.results["name"] = value` includes <nlohmann/json.hpp> itself; set() writes a
// number or a text without it.

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>

#include <nlohmann/json_fwd.hpp>

namespace sph {

/// One section of the report: a JSON object, starting empty.
class ReportSection {
 public:
  ReportSection();
  ~ReportSection();
  ReportSection(const ReportSection& other);
  ReportSection(ReportSection&& other) noexcept;
  ReportSection& operator=(const ReportSection& other);
  ReportSection& operator=(ReportSection&& other) noexcept;
  /// Replaces the whole section (an object).
  ReportSection& operator=(const nlohmann::json& object);

  /// The entry `key`, created (null) if absent.
  nlohmann::json& operator[](const std::string& key);
  /// The entry `key`, which must exist (as nlohmann::json's const operator[]).
  const nlohmann::json& operator[](const std::string& key) const;
  /// The entry `key`; throws if absent.
  const nlohmann::json& at(const std::string& key) const;
  bool contains(const std::string& key) const;
  bool empty() const;
  /// The number under `key`, or `fallback` if there is none.
  double value(const std::string& key, double fallback) const;
  void set(const std::string& key, double value);
  void set(const std::string& key, std::size_t value);
  void set(const std::string& key, const std::string& value);
  /// The section as text (nlohmann::json::dump).
  std::string dump(int indent = -1) const;
  nlohmann::json& json() { return *object_; }
  const nlohmann::json& json() const { return *object_; }

 private:
  std::unique_ptr<nlohmann::json> object_;
};

struct RunReport {
  std::string scene;
  std::string status = "completed";
  std::string message;
  double wall_time_s = 0;
  double simulated_time = 0;
  std::size_t steps = 0;
  std::size_t threads = 0;
  std::size_t ranks = 1;  ///< MPI ranks of a distributed run
  ReportSection particles;
  ReportSection memory_bytes;
  ReportSection parameters;
  ReportSection results;
  ReportSection errors;
  std::string reference;

  nlohmann::json to_json() const;
  void write(const std::filesystem::path& path) const;
};

}  // namespace sph
