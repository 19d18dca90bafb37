// One acoustic step (pressure force and continuity: the pair loops) and one neighbour rebuild of a
// weakly-compressible fluid block, in 2D and 3D, at about 1e5 and 1e6 particles, as particle-steps
// per second of wall time (items_per_second, all threads), with the roofline of the acoustic step
// (benchmarks/roofline.hpp); run build/benchmarks/bench_fluid.
//
// Bytes an acoustic step must move, per particle: in each of its two pair loops (pressure force,
// continuity) the pair's index, dW/dr and e_ij (the neighbours' packed state is gathered from the
// caches); per particle the state read and written by the two halves: x, v, a, the prior a and
// the packed state (v, p, V) as vectors, rho, drho/dt, p, V and m as scalars, each read and written. Flops per pair: about 45 in the force loop (Riemann
// pressure with the limiter) and 15 in the continuity loop.

#include <cmath>
#include <cstddef>

#include <benchmark/benchmark.h>

#include "benchmarks/roofline.hpp"
#include "geometry/lattice.hpp"
#include "libsph/fluid/weakly_compressible_fluid.hpp"

namespace {

using sph::Real;

template <int Dim>
struct Block {
  sph::ParticleSet<Dim> particles;
  sph::WeaklyCompressibleFluid<Dim> fluid;
  explicit Block(std::size_t n_target)
      : particles(make_particles(n_target)), fluid(particles, settings()) {
    // A smooth velocity and density field, so that every branch of the pair terms is taken.
    auto v = particles.field(fluid.velocity_field());
    auto rho = particles.field(fluid.density_field());
    for (std::size_t i = 0; i < particles.n_particles(); ++i) {
      const auto& x = particles.position[i];
      for (int d = 0; d < Dim; ++d) v[i][d] = Real(0.1) * std::sin(Real(0.3) * x[(d + 1) % Dim]);
      rho[i] = Real(1) + Real(1e-3) * std::cos(Real(0.2) * x[0]);
    }
    fluid.update_pressure();
    fluid.update_neighbours();
  }
  static sph::ParticleSet<Dim> make_particles(std::size_t n_target) {
    const auto side = static_cast<Real>(std::round(std::pow(double(n_target), 1.0 / Dim)));
    return geometry::lattice_box<Dim>("fluid", sph::Vec<Dim>::Zero(), sph::Vec<Dim>::Constant(side), Real(1));
  }
  static typename sph::WeaklyCompressibleFluid<Dim>::Settings settings() {
    typename sph::WeaklyCompressibleFluid<Dim>::Settings s;
    s.equation_of_state.sound_speed = 10;
    s.particle_spacing = 1;
    s.smoothing_length = Real(1.3);
    s.numerics.sort_interval = 0;
    return s;
  }
};

template <int Dim>
void acoustic_step(benchmark::State& state) {
  Block<Dim> block(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) {
    block.fluid.first_half(Real(1e-4));
    block.fluid.second_half(Real(1e-4));
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long>(block.particles.n_particles()));
  const double pairs = double(block.fluid.inner_relation().n_pairs()) / double(block.particles.n_particles());
  state.counters["pairs_per_particle"] = pairs;
  const double per_pair = 2 * (sizeof(sph::Index) + sizeof(Real) + sizeof(sph::Vec<Dim>));
  const double per_particle = 2 * (5 * sizeof(sph::Vec<Dim>) + 7 * sizeof(Real));
  bench::set_roofline(state, double(block.particles.n_particles()), pairs * per_pair + per_particle, pairs * 60);
}

template <int Dim>
void neighbour_rebuild(benchmark::State& state) {
  Block<Dim> block(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) block.fluid.update_neighbours();
  state.SetItemsProcessed(state.iterations() * static_cast<long>(block.particles.n_particles()));
}

BENCHMARK(acoustic_step<2>)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(acoustic_step<3>)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(neighbour_rebuild<2>)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(neighbour_rebuild<3>)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
