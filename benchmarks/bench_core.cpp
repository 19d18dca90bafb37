// Measures the 3D neighbour-list build (anew and rebuilt in place) and one kernel summation over it,
// with the particles in lattice order, shuffled, or shuffled and then sorted along the cell list;
// run build/benchmarks/bench_core.

#include <cstddef>
#include <cstdint>
#include <random>
#include <span>
#include <vector>

#include <benchmark/benchmark.h>

#include "libsph/core/kernels.hpp"
#include "libsph/core/neighbour_relation.hpp"
#include "libsph/core/parallel.hpp"
#include "libsph/core/particle_sorting.hpp"
#include "libsph/core/types.hpp"

namespace {

constexpr sph::Real dp = 1.0;
constexpr sph::Real smoothing_length = 1.3 * dp;

/// side^3 particles on a cubic lattice of spacing dp, each shifted by a fixed-seed jitter of up to 0.1 dp.
std::vector<sph::Vec<3>> jittered_lattice(std::size_t side) {
  std::mt19937_64 engine(20240601);
  const auto jitter = [&] { return 0.1 * dp * (2.0 * static_cast<sph::Real>(engine() >> 11) * 0x1.0p-53 - 1.0); };
  std::vector<sph::Vec<3>> positions;
  positions.reserve(side * side * side);
  for (std::size_t z = 0; z < side; ++z)
    for (std::size_t y = 0; y < side; ++y)
      for (std::size_t x = 0; x < side; ++x) {
        const sph::Vec<3> lattice_point(x * dp, y * dp, z * dp);
        positions.push_back(lattice_point + sph::Vec<3>(jitter(), jitter(), jitter()));
      }
  return positions;
}

/// The positions in a fixed-seed random order (Fisher-Yates on the engine's raw bits).
std::vector<sph::Vec<3>> shuffled(std::vector<sph::Vec<3>> positions) {
  std::mt19937_64 engine(7);
  for (std::size_t i = positions.size(); i > 1; --i) std::swap(positions[i - 1], positions[engine() % i]);
  return positions;
}

/// Order 0: lattice order; 1: shuffled; 2: shuffled, then sorted along the cell list.
std::vector<sph::Vec<3>> positions_in_order(std::size_t side, long order) {
  auto positions = jittered_lattice(side);
  if (order == 0) return positions;
  positions = shuffled(std::move(positions));
  if (order == 1) return positions;
  const auto permutation = sph::cell_order<3>(positions, 2 * smoothing_length);
  std::vector<sph::Vec<3>> sorted(positions.size());
  for (std::size_t k = 0; k < sorted.size(); ++k) sorted[k] = positions[permutation[k]];
  return sorted;
}

void bm_rebuild_inner_relation_in_place(benchmark::State& state) {
  const auto positions = jittered_lattice(static_cast<std::size_t>(state.range(0)));
  const sph::AnyKernel<3> kernel = sph::WendlandC2<3>{};
  auto relation = sph::build_inner_relation<3>(std::span<const sph::Vec<3>>(positions), kernel, smoothing_length);
  // One rebuild first: it gives the relation the storage that later rebuilds reuse (its counting
  // pass keeps the candidates it finds, which a relation built once does not hold).
  sph::rebuild_inner_relation<3>(relation, std::span<const sph::Vec<3>>(positions), kernel, smoothing_length);
  for (auto _ : state) {
    sph::rebuild_inner_relation<3>(relation, std::span<const sph::Vec<3>>(positions), kernel, smoothing_length);
    benchmark::DoNotOptimize(relation.neighbour.data());
  }
  state.counters["particles_per_second"] =
      benchmark::Counter(static_cast<double>(positions.size()), benchmark::Counter::kIsIterationInvariantRate);
}

void bm_build_inner_relation(benchmark::State& state) {
  const auto positions = jittered_lattice(static_cast<std::size_t>(state.range(0)));
  const sph::AnyKernel<3> kernel = sph::WendlandC2<3>{};
  const double n = static_cast<double>(positions.size());
  double pairs = 0, bytes = 0;
  for (auto _ : state) {
    auto relation = sph::build_inner_relation<3>(std::span<const sph::Vec<3>>(positions), kernel, smoothing_length);
    benchmark::DoNotOptimize(relation.neighbour.data());
    pairs = static_cast<double>(relation.n_pairs());
    bytes = static_cast<double>(relation.bytes());
  }
  state.counters["particles_per_second"] = benchmark::Counter(n, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["pairs_per_particle"] = pairs / n;
  state.counters["bytes_per_particle"] = bytes / n;
}

void bm_kernel_summation(benchmark::State& state) {
  const auto positions = positions_in_order(static_cast<std::size_t>(state.range(0)), state.range(1));
  const sph::AnyKernel<3> kernel = sph::WendlandC2<3>{};
  const auto relation =
      sph::build_inner_relation<3>(std::span<const sph::Vec<3>>(positions), kernel, smoothing_length);
  const std::size_t n = positions.size();
  const std::vector<sph::Real> volume(n, dp * dp * dp);
  std::vector<sph::Real> sigma(n);
  const sph::Real self_weight = sph::WendlandC2<3>::value(0, smoothing_length);

  for (auto _ : state) {
    sph::parallel_for(n, [&](std::size_t i) {
      sph::Real sum = self_weight * volume[i];
      for (std::size_t k = relation.offsets[i]; k < relation.offsets[i + 1]; ++k)
        sum += volume[relation.neighbour[k]] * relation.kernel_value[k];
      sigma[i] = sum;
    });
    benchmark::DoNotOptimize(sigma.data());
    benchmark::ClobberMemory();
  }
  const double n_real = static_cast<double>(n);
  state.counters["particles_per_second"] = benchmark::Counter(n_real, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["pairs_per_particle"] = static_cast<double>(relation.n_pairs()) / n_real;
  // Bytes the loop reads and writes: per pair the neighbour index and W_ij, per particle the row
  // offset, the volume and the result (the volumes of neighbours mostly come from cache).
  const double pair_bytes = static_cast<double>(relation.n_pairs() * (sizeof(sph::Index) + sizeof(sph::Real)));
  state.counters["bytes_per_particle"] =
      (pair_bytes + n_real * static_cast<double>(sizeof(std::size_t) + 2 * sizeof(sph::Real))) / n_real;
}

}  // namespace

BENCHMARK(bm_build_inner_relation)->Arg(46)->Arg(100)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(bm_rebuild_inner_relation_in_place)->Arg(46)->Arg(100)->Unit(benchmark::kMillisecond)->UseRealTime();
// Second argument: 0 lattice order, 1 shuffled, 2 shuffled then sorted along the cell list.
BENCHMARK(bm_kernel_summation)
    ->ArgsProduct({{46, 100}, {0, 1, 2}})
    ->ArgNames({"side", "order"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK_MAIN();
