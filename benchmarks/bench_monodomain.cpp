// One monodomain step (cells over dt/2, diffusion sub-steps over dt, cells over dt/2) on a 3D
// lattice of about 1e5 particles (46^3), for Aliev-Panfilov and ten Tusscher-Panfilov 2006 with the
// reaction-by-reaction QSS scheme, D = 0.1 mm^2/ms along x and 0.01 across, dp = 0.2 mm,
// dt = 0.05 ms. Reports particle-steps per second ("items_per_second"), the share of the
// reaction in the step and the roofline (benchmarks/roofline.hpp).
//
// Bytes a step must move, per particle: the cell state read and written in each reaction half
// step (n_states values), V stored before the step and read for the activation time; per diffusion
// sub-step the pair's index and coefficient, and V and its rate read and written. Flops: the
// diffusion's 3 per pair only (the reaction is dominated by exponentials, not counted).
#include <benchmark/benchmark.h>

#include <type_traits>
#include <variant>

#include "benchmarks/roofline.hpp"
#include "cardio/monodomain.hpp"
#include "geometry/lattice.hpp"
#include "libsph/core/parallel.hpp"

namespace {

using sph::Real;
using Vec3 = sph::Vec<3>;

void monodomain_step(benchmark::State& state) {
  const auto per_side = static_cast<long>(state.range(0));
  const Real dp = Real(0.2);
  auto body = geometry::lattice_box<3>("tissue", Vec3::Zero(), Vec3::Constant(dp * static_cast<Real>(per_side)), dp);
  const auto relation = sph::build_inner_relation<3>(body.position, sph::make_kernel<3>("wendland_c2"), Real(1.3) * dp);
  cardio::Monodomain<3>::Settings settings;
  settings.cell_model = sph::make_cell_model(sph::cell_model_names[static_cast<std::size_t>(state.range(1))]);
  settings.numerics.time_step = Real(0.05);
  settings.diffusion_tensor = {sph::transversely_isotropic_tensor<3>(Real(0.1), Real(0.01), Vec3(1, 0, 0))};
  std::vector<std::size_t> corner;
  for (std::size_t i = 0; i < body.n_particles(); ++i)
    if ((body.position[i].array() < 1).all()) corner.push_back(i);
  settings.stimuli = {{"corner", corner, {0, 2, 50, 0, 1}}};
  cardio::Monodomain<3> monodomain(body, relation, settings);
  Real t = 0;
  for (auto _ : state) {
    monodomain.advance(t, settings.numerics.time_step);
    t += settings.numerics.time_step;
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long>(body.n_particles()));
  state.SetLabel(std::string(sph::cell_model_names[static_cast<std::size_t>(state.range(1))]));
  const auto& timing = monodomain.timings();
  state.counters["particles"] = static_cast<double>(body.n_particles());
  state.counters["reaction_share"] = timing.reaction / (timing.reaction + timing.diffusion);
  state.counters["diffusion_substeps"] = static_cast<double>(monodomain.diffusion_substeps()) / static_cast<double>(state.iterations());
  state.counters["field_bytes_per_particle"] = static_cast<double>(body.bytes_per_particle());
  state.counters["threads"] = static_cast<double>(sph::active_thread_count());
  const double states = static_cast<double>(std::visit([](const auto& m) { return std::decay_t<decltype(m)>::n_states; },
                                                       settings.cell_model));
  const double substeps = static_cast<double>(monodomain.diffusion_substeps()) / static_cast<double>(state.iterations());
  const double pairs = static_cast<double>(relation.n_pairs()) / static_cast<double>(body.n_particles());
  const double real = sizeof(Real);
  const double bytes = 2 * 2 * states * real + 3 * real + substeps * (pairs * (sizeof(sph::Index) + real) + 4 * real);
  bench::set_roofline(state, static_cast<double>(body.n_particles()), bytes, substeps * pairs * 3);
}
// Model index into sph::cell_model_names: 1 = Aliev-Panfilov, 2 = ten Tusscher-Panfilov 2006.
BENCHMARK(monodomain_step)->Args({46, 1})->Args({46, 2})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
