// One TLSPH step (deformation gradient, stress, momentum with hourglass control, Verlet update) on
// a 3D lattice block, Holzapfel-Ogden law with fibres, h = 1.3 dp, Wendland C4. Reports particle-steps
// per second ("items_per_second") and the bytes per particle of fields and relation.
#include <benchmark/benchmark.h>

#include <cmath>

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
  sph::ElasticSolid<3> solid(body, relation, settings);
  solid.clamp(std::vector<sph::Index>{0});
  auto v = body.field(solid.velocity_field());
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = Vec3(0, Real(0.1) * body.position[i][0], 0);  // a shearing motion
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
}
BENCHMARK(tlsph_step)->Arg(20)->Arg(46)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
