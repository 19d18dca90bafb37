#pragma once
// The discretisation every particle scene declares the same way: the kernel, the smoothing length
// over the particle spacing, and the interval of the particle output. The numerical choices of the
// physics are declared by the library components themselves (sph::DiffusionNumerics,
// sph::SolidNumerics, cardio::MonodomainNumerics and their declare_parameters).

#include <string>
#include <vector>

#include "libsph/core/kernels.hpp"
#include "libsph/io/parameters.hpp"

namespace cardiosph {

struct Discretisation {
  double smoothing_length_ratio = 1.3;  ///< h / dp
  std::string kernel = "wendland_c2";   ///< one of sph::kernel_names
  double output_interval = 0;           ///< time between particle outputs; 0 = first and last state
};

/// Declares smoothing_length_ratio, kernel and output_interval [time_unit].
inline void declare_parameters(sph::Parameters& p, Discretisation& d, const std::string& time_unit) {
  p.add("smoothing_length_ratio", d.smoothing_length_ratio, "-", "smoothing length over particle spacing h/dp",
        sph::Range::closed(1.0, 2.5));
  p.add_choice("kernel", d.kernel, std::vector<std::string>(std::begin(sph::kernel_names), std::end(sph::kernel_names)),
               "smoothing kernel");
  p.add("output_interval", d.output_interval, time_unit, "time between particle outputs (0: first and last state only)",
        sph::Range::non_negative());
}

}  // namespace cardiosph
