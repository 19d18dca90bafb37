#pragma once
// Wall time spent in named parts of a run (reaction, diffusion, mechanics, output, ...), for run
// reports. `timed(name, action)` wraps a stage phase so that its time is added to `name`.

#include <chrono>
#include <map>
#include <string>
#include <utility>

#include "libsph/core/state_archive.hpp"
#include "libsph/core/time_stepper.hpp"

namespace sph {

class SectionTimers {
 public:
  /// Runs work() and adds its wall time to `name`.
  template <class Work>
  void measure(const std::string& name, Work&& work) {
    Section& section = sections_[name];
    const auto start = std::chrono::steady_clock::now();
    std::forward<Work>(work)();
    section.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ++section.calls;
  }
  /// The phase `action`, timed under `name`. The timers must outlive the stage.
  StepAction timed(const std::string& name, StepAction action) {
    Section& section = sections_[name];  // std::map keeps the reference valid
    return [&section, action = std::move(action)](Real time, Real dt) {
      const auto start = std::chrono::steady_clock::now();
      action(time, dt);
      section.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      ++section.calls;
    };
  }
  /// The action phases of `stage` (not its slots or nested stages), timed under `name` with one call
  /// counted per step of the stage. The timers must outlive the stage.
  Stage timed(const std::string& name, Stage stage) {
    Section& section = sections_[name];
    bool first = true;
    for (auto& phase : stage.phases) {
      if (phase.slot || !phase.nested.empty()) continue;
      phase.action = [&section, count = first, action = std::move(phase.action)](Real time, Real dt) {
        const auto start = std::chrono::steady_clock::now();
        action(time, dt);
        section.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (count) ++section.calls;
      };
      first = false;
    }
    return stage;
  }
  double seconds(const std::string& name) const {
    const auto it = sections_.find(name);
    return it == sections_.end() ? 0.0 : it->second.seconds;
  }
  /// Number of timed calls of `name`.
  std::size_t calls(const std::string& name) const {
    const auto it = sections_.find(name);
    return it == sections_.end() ? 0 : it->second.calls;
  }
  /// Saves or loads every section (checkpoints): a resumed run reports the whole run's calls and time.
  void checkpoint(StateArchive& archive) {
    std::string names;
    std::vector<double> seconds;
    std::vector<std::size_t> calls;
    for (const auto& [name, section] : sections_) names += name + '\n', seconds.push_back(section.seconds), calls.push_back(section.calls);
    archive.io("names", names);
    archive.io("seconds", seconds);
    archive.io("calls", calls);
    if (archive.saving()) return;
    std::size_t k = 0, start = 0;
    for (std::size_t end = names.find('\n'); end != std::string::npos; start = end + 1, end = names.find('\n', start), ++k) {
      if (k >= seconds.size() || k >= calls.size()) throw StateError("the state's timers list more names than values");
      Section& section = sections_[names.substr(start, end - start)];  // in place: timed() holds references
      section.seconds = seconds[k];
      section.calls = calls[k];
    }
  }
  /// name -> seconds, for report.json.
  std::map<std::string, double> all() const {
    std::map<std::string, double> out;
    for (const auto& [name, section] : sections_) out[name] = section.seconds;
    return out;
  }

 private:
  struct Section {
    double seconds = 0;
    std::size_t calls = 0;
  };
  std::map<std::string, Section> sections_;
};

}  // namespace sph
