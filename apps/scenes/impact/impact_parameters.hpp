#pragma once
// Parameters every impact scene declares the same way.

#include <string>

#include "libsph/io/parameters.hpp"

namespace cardiosph {

/// Monaghan's artificial viscosity coefficients.
inline void declare_artificial_viscosity(sph::Parameters& p, double& alpha, double& beta) {
  p.add("alpha", alpha, "-", "artificial viscosity: linear coefficient (Monaghan 1992)", sph::Range::non_negative());
  p.add("beta", beta, "-", "artificial viscosity: quadratic coefficient", sph::Range::non_negative());
}

/// The simulated time and the interval of particle outputs, in the scene's time unit.
inline void declare_run_length(sph::Parameters& p, double& end_time, double& output_interval, const std::string& unit) {
  p.add("end_time", end_time, unit, "simulated time", sph::Range::positive());
  p.add("output_interval", output_interval, unit, "time between particle outputs (0: first and last state only)",
        sph::Range::non_negative());
}

}  // namespace cardiosph
