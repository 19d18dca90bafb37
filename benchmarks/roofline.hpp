#pragma once
// The roofline of a particle step: the machine's memory bandwidth, measured here with the STREAM
// triad (a = b + s c, 24 bytes per element; McCalpin 1995) through the project's parallel loop on
// arrays far beyond the caches (best of five), against the bytes a step must move at least.
//
// A benchmark states its bytes and flops per particle-step (a count of what its loops read, write
// and compute, given next to it) and gets the counters
//   bytes_per_particle_step, flops_per_particle_step,
//   bandwidth_GBps         the triad bandwidth of this run, 1e9 bytes per second,
//   bound_per_s            bandwidth / bytes: the particle-steps per second if memory were the limit,
//   fraction_of_bound      the measured particle-steps per second over that bound.

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <vector>

#include <benchmark/benchmark.h>

#include "libsph/core/parallel.hpp"

namespace bench {

/// Triad bandwidth [bytes/s] on the threads the parallel loops use now (measured once).
inline double triad_bandwidth() {
  static const double bandwidth = [] {
    constexpr std::size_t n = std::size_t(1) << 23;  // 64 MiB per array
    std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
    sph::parallel_for(n, [&](std::size_t i) { a[i] = b[i] + 0.5 * c[i]; });  // first touch
    double best = 0;
    for (int repeat = 0; repeat < 5; ++repeat) {
      const auto start = std::chrono::steady_clock::now();
      sph::parallel_for(n, [&](std::size_t i) { a[i] = b[i] + 3.0 * c[i]; });
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      benchmark::DoNotOptimize(a.data());
      best = std::max(best, 24.0 * double(n) / seconds);
    }
    return best;
  }();
  return bandwidth;
}

/// Sets the roofline counters of a benchmark that processes `particles` particle-steps per iteration.
inline void set_roofline(benchmark::State& state, double particles, double bytes_per_particle_step,
                         double flops_per_particle_step) {
  const double bandwidth = triad_bandwidth();
  const double bound = bandwidth / bytes_per_particle_step;
  state.counters["bytes_per_particle_step"] = bytes_per_particle_step;
  state.counters["flops_per_particle_step"] = flops_per_particle_step;
  state.counters["bandwidth_GBps"] = bandwidth / 1e9;
  state.counters["bound_per_s"] = bound;
  state.counters["fraction_of_bound"] = benchmark::Counter(particles / bound, benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace bench
