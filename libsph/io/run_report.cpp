#include "libsph/io/run_report.hpp"

#include <utility>

#include <nlohmann/json.hpp>

#include "libsph/io/atomic_file.hpp"

namespace sph {

ReportSection::ReportSection() : object_(std::make_unique<nlohmann::json>(nlohmann::json::object())) {}
ReportSection::~ReportSection() = default;
ReportSection::ReportSection(const ReportSection& other) : object_(std::make_unique<nlohmann::json>(*other.object_)) {}
ReportSection::ReportSection(ReportSection&& other) noexcept : object_(std::make_unique<nlohmann::json>(nlohmann::json::object())) {
  object_.swap(other.object_);
}
ReportSection& ReportSection::operator=(const ReportSection& other) {
  *object_ = *other.object_;
  return *this;
}
ReportSection& ReportSection::operator=(ReportSection&& other) noexcept {
  object_.swap(other.object_);
  return *this;
}
ReportSection& ReportSection::operator=(const nlohmann::json& object) {
  *object_ = object;
  return *this;
}
nlohmann::json& ReportSection::operator[](const std::string& key) { return (*object_)[key]; }
const nlohmann::json& ReportSection::operator[](const std::string& key) const { return std::as_const(*object_)[key]; }
const nlohmann::json& ReportSection::at(const std::string& key) const { return object_->at(key); }
bool ReportSection::contains(const std::string& key) const { return object_->contains(key); }
bool ReportSection::empty() const { return object_->empty(); }
double ReportSection::value(const std::string& key, double fallback) const { return object_->value(key, fallback); }
void ReportSection::set(const std::string& key, double value) { (*object_)[key] = value; }
void ReportSection::set(const std::string& key, std::size_t value) { (*object_)[key] = value; }
void ReportSection::set(const std::string& key, const std::string& value) { (*object_)[key] = value; }
std::string ReportSection::dump(int indent) const { return object_->dump(indent); }

nlohmann::json RunReport::to_json() const {
  nlohmann::json out;
  out["scene"] = scene;
  out["status"] = status;
  if (!message.empty()) out["message"] = message;
  out["wall_time_s"] = wall_time_s;
  out["simulated_time"] = simulated_time;
  out["steps"] = steps;
  out["threads"] = threads;
  if (ranks > 1) out["ranks"] = ranks;
  out["particles"] = particles.json();
  out["memory_bytes"] = memory_bytes.json();
  out["parameters"] = parameters.json();
  out["results"] = results.json();
  if (!errors.empty() || !reference.empty()) {
    out["errors"] = errors.json();
    out["reference"] = reference;
  }
  return out;
}

void RunReport::write(const std::filesystem::path& path) const { write_file_atomically(path, to_json().dump(2) + "\n"); }

}  // namespace sph
