#pragma once
// Progress of a long run on stderr: on a terminal one line rewritten in place (simulated time,
// steps per second, estimated time left); otherwise a plain line at every tenth of the simulated
// interval; nothing when quiet.

#include <chrono>
#include <string>

#include "libsph/core/time_stepper.hpp"

namespace sph {

class Progress {
 public:
  Progress(std::string label, bool quiet);
  void update(const StepInfo& info);
  /// Ends the line on a terminal.
  void finish();

 private:
  std::string line(const StepInfo& info, double elapsed) const;
  std::string label_;
  bool quiet_, terminal_;
  std::chrono::steady_clock::time_point start_, last_print_;
  int next_tenth_ = 1;
  bool printed_ = false;
};

}  // namespace sph
