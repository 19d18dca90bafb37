#pragma once
// The error every integrator throws when its state becomes invalid (NaN/Inf, J <= 0, time-step
// collapse, ...). It names the body, the particle, its position, the time and the quantity, so the
// run can stop with a diagnostic instead of continuing silently.

#include <sstream>
#include <stdexcept>
#include <string>

#include "libsph/core/types.hpp"

namespace sph {

class NumericalFailure : public std::runtime_error {
 public:
  NumericalFailure(const std::string& body, std::size_t particle, const std::string& position, Real time,
                   const std::string& quantity, const std::string& problem)
      : std::runtime_error(compose(body, particle, position, time, quantity, problem)) {}

  /// A number as the messages show it (6 significant digits).
  static std::string format_value(double value) {
    std::ostringstream s;
    s << value;
    return s.str();
  }
  template <class VecT>
  static std::string format_position(const VecT& x) {
    std::ostringstream s;
    s << '(';
    for (int d = 0; d < x.size(); ++d) s << (d ? ", " : "") << x[d];
    s << ')';
    return s.str();
  }

 private:
  static std::string compose(const std::string& body, std::size_t particle, const std::string& position, Real time,
                             const std::string& quantity, const std::string& problem) {
    std::ostringstream s;
    s << "numerical failure in body '" << body << "', particle " << particle << " at " << position << ", time "
      << time << ": " << quantity << ' ' << problem;
    return s.str();
  }
};

}  // namespace sph
