// The machine's memory bandwidth, the bound of the roofline the other benchmarks are held against:
// STREAM-style copy (a = b, 16 bytes per element) and triad (a = b + s c, 24 bytes per element;
// McCalpin 1995) on arrays of 2^24 doubles (128 MiB each, far beyond the caches), on one thread and
// on all threads through the same parallel loop as the SPH kernels. bytes_per_second is the
// bandwidth; run build/benchmarks/bench_bandwidth.

#include <cstddef>
#include <vector>

#include <benchmark/benchmark.h>

#include "libsph/core/parallel.hpp"

namespace {

constexpr std::size_t kElements = std::size_t(1) << 24;

struct Arrays {
  std::vector<double> a, b, c;
  Arrays() : a(kElements, 0.0), b(kElements, 1.0), c(kElements, 2.0) {
    // First touch in parallel, so that the pages lie where the threads that use them run.
    sph::parallel_for(kElements, [&](std::size_t i) { a[i] = 0.5 * b[i] + c[i]; });
  }
};

Arrays& arrays() {
  static Arrays arrays;
  return arrays;
}

void BM_Copy(benchmark::State& state) {
  sph::ThreadLimit limit(static_cast<std::size_t>(state.range(0)));
  auto& x = arrays();
  for (auto _ : state) {
    sph::parallel_for(kElements, [&](std::size_t i) { x.a[i] = x.b[i]; });
    benchmark::ClobberMemory();
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * int64_t(kElements) * 16);
}

void BM_Triad(benchmark::State& state) {
  sph::ThreadLimit limit(static_cast<std::size_t>(state.range(0)));
  auto& x = arrays();
  const double s = 3.0;
  for (auto _ : state) {
    sph::parallel_for(kElements, [&](std::size_t i) { x.a[i] = x.b[i] + s * x.c[i]; });
    benchmark::ClobberMemory();
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * int64_t(kElements) * 24);
}

}  // namespace

BENCHMARK(BM_Copy)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Triad)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
