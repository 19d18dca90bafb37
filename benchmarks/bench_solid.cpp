// One TLSPH step (deformation gradient, stress, momentum with hourglass control, Verlet update) on
// a 3D lattice block of 10,648, 97,336 and 1,000,000 particles, Holzapfel-Ogden law with fibres and
// active stress, h = 1.3 dp, Wendland C4. Reports particle-steps per second ("items_per_second"),
// the bytes per particle of fields and relation, and the roofline (benchmarks/roofline.hpp).
//
// Bytes a step must move, per particle (pairs streamed once per pass; the neighbours' fields are
// gathered from the caches, the particles being in lattice order):
//   pass 1 (F and stress): per pair the index and the solid's single-precision grad0 W_ij and
//     hourglass weight (16 bytes); per particle x, V, B0, f0, s0, T_a read, F and P B0 written;
//   pass 2 (forces, velocity): per pair the index, the same 16 bytes and X_ij (12 bytes); per
//     particle x, V, F, P B0 read, a written, v read and written;
//   the position updates: x and v read, x written twice, the last good x and v written.
// Flops per pair (counted from the loops): pass 1, 25 (x_ij 3, V_j dW 1, scaling 3, outer-product
// sum 18); pass 2, 30 without hourglass (w 4, sum of w 3, P_j B_j w 18, ...) plus 55 for the
// hourglass term; per particle about 400 for the Holzapfel-Ogden stress with active tension.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>

#include "benchmarks/roofline.hpp"
#include "geometry/lattice.hpp"
#include "libsph/core/parallel.hpp"
#include "libsph/solid/elastic_solid.hpp"

namespace {

using sph::Real;
using Vec3 = sph::Vec<3>;

void tlsph_step(benchmark::State& state) {
  const auto per_side = static_cast<long>(state.range(0));
  const Real dp = Real(1) / static_cast<Real>(per_side);
  auto body = geometry::lattice_box<3>("block", Vec3::Zero(), Vec3::Ones(), dp);
  const auto relation = sph::build_inner_relation<3>(body.position, sph::make_kernel<3>("wendland_c4"), Real(1.3) * dp);
  sph::ElasticSolid<3>::Settings settings;
  settings.material = sph::holzapfel_ogden_2009_kpa<3>(100);
  settings.numerics.hourglass_coefficient = Real(0.1);
  settings.active_stress = true;
  sph::ElasticSolid<3> solid(body, relation, settings);
  solid.clamp(std::vector<sph::Index>{0});
  auto v = body.field(solid.velocity_field());
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = Vec3(0, Real(0.1) * body.position[i][0], 0);  // a shearing motion
  auto tension = body.field(solid.active_tension_field());
  std::fill(tension.begin(), tension.end(), Real(1));
  const Real dt = solid.stable_time_step();
  Real t = 0;
  for (auto _ : state) {
    solid.advance(t, dt);
    t += dt;
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long>(body.n_particles()));
  state.counters["particles"] = static_cast<double>(body.n_particles());
  state.counters["pairs_per_particle"] = static_cast<double>(relation.n_pairs()) / static_cast<double>(body.n_particles());
  state.counters["field_bytes_per_particle"] = static_cast<double>(body.bytes_per_particle());
  state.counters["relation_bytes_per_particle"] = static_cast<double>(relation.bytes()) / static_cast<double>(body.n_particles());
  state.counters["threads"] = static_cast<double>(sph::active_thread_count());
  const double pairs = static_cast<double>(relation.n_pairs()) / static_cast<double>(body.n_particles());
  const double index = sizeof(sph::Index), real = sizeof(Real), vec = sizeof(Vec3), mat = sizeof(sph::Mat<3>);
  const double per_pair = (index + 4 * sizeof(float)) + (index + 7 * sizeof(float));
  const double per_particle = (vec + real + mat + 2 * vec + real + 2 * mat) + (vec + real + 2 * mat + vec + 2 * vec) +
                              (2 * vec + 2 * vec + 2 * vec);
  bench::set_roofline(state, static_cast<double>(body.n_particles()), pairs * per_pair + per_particle, pairs * 110 + 400);
}
BENCHMARK(tlsph_step)->Arg(22)->Arg(46)->Arg(100)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
