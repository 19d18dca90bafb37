#include "libsph/io/progress.hpp"

#include <cstdio>
#include <iostream>
#include <sstream>
#include <unistd.h>

namespace sph {

Progress::Progress(std::string label, bool quiet)
    : label_(std::move(label)), quiet_(quiet), terminal_(isatty(fileno(stderr)) != 0),
      start_(std::chrono::steady_clock::now()), last_print_(start_) {}

std::string Progress::line(const StepInfo& info, double elapsed) const {
  const double span = static_cast<double>(info.end_time - info.start_time);
  const double done = span > 0 ? static_cast<double>(info.time - info.start_time) / span : 1.0;
  const double steps_per_s = elapsed > 0 ? static_cast<double>(info.step) / elapsed : 0.0;
  std::ostringstream s;
  s.precision(4);
  s << label_ << ": t = " << info.time << " / " << info.end_time << " (" << static_cast<int>(100 * done) << "%), "
    << info.step << " steps, " << static_cast<long>(steps_per_s) << " steps/s";
  if (done > 0 && done < 1) s << ", about " << static_cast<long>(elapsed * (1 - done) / done + 0.5) << " s left";
  return s.str();
}

void Progress::update(const StepInfo& info) {
  if (quiet_) return;
  const auto now = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  if (terminal_) {
    if (now - last_print_ < std::chrono::milliseconds(200)) return;
    last_print_ = now;
    std::cerr << '\r' << line(info, elapsed) << "\x1b[K" << std::flush;
    printed_ = true;
    return;
  }
  const double span = static_cast<double>(info.end_time - info.start_time);
  const double done = span > 0 ? static_cast<double>(info.time - info.start_time) / span : 1.0;
  if (done * 10 + 1e-9 >= next_tenth_) {
    while (done * 10 + 1e-9 >= next_tenth_) ++next_tenth_;
    std::cerr << line(info, elapsed) << '\n';
  }
}

void Progress::finish() {
  if (!quiet_ && terminal_ && printed_) std::cerr << '\n';
}

}  // namespace sph
