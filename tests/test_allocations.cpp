// Hot steps allocate nothing in steady state. This test binary replaces the global operator new
// and counts every allocation; each test warms a step up (first calls size their scratch), then
// expects zero allocations over further steps: the TLSPH step with active stress and hourglass
// control, the diffusion step, the monodomain step with its nested diffusion stage, a relation
// rebuilt in place, and the time stepper's own loop over nested stages.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "cardio/monodomain.hpp"
#include "geometry/lattice.hpp"
#include "geometry/wall_particles.hpp"
#include "libsph/core/neighbour_relation.hpp"
#include "libsph/core/time_stepper.hpp"
#include "libsph/diffusion/diffusion_system.hpp"
#include "libsph/fluid/weakly_compressible_fluid.hpp"
#include "libsph/solid/elastic_solid.hpp"

namespace {
std::atomic<std::size_t> allocations{0};

void* counted(std::size_t n, std::size_t alignment = 0) {
  allocations.fetch_add(1, std::memory_order_relaxed);
  void* p = alignment ? std::aligned_alloc(alignment, (n + alignment - 1) / alignment * alignment) : std::malloc(n ? n : 1);
  if (!p) throw std::bad_alloc();
  return p;
}
}  // namespace

void* operator new(std::size_t n) { return counted(n); }
void* operator new[](std::size_t n) { return counted(n); }
void* operator new(std::size_t n, std::align_val_t a) { return counted(n, static_cast<std::size_t>(a)); }
void* operator new[](std::size_t n, std::align_val_t a) { return counted(n, static_cast<std::size_t>(a)); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }

namespace {

using sph::Real;
using Vec3 = sph::Vec<3>;

/// Allocations made by work().
template <class Work>
std::size_t allocations_in(Work&& work) {
  const std::size_t before = allocations.load();
  work();
  return allocations.load() - before;
}

TEST(Allocations, TlsphStepWithActiveStressAllocatesNothing) {
  auto body = geometry::lattice_box<3>("block", Vec3::Zero(), Vec3(1, 0.5, 0.5), Real(0.1));
  const auto kernel = sph::make_kernel<3>("wendland_c4");
  const auto relation = sph::build_inner_relation<3>(body.position, kernel, Real(0.13));
  sph::ElasticSolid<3>::Settings settings;
  settings.material = sph::holzapfel_ogden_2009_kpa<3>(Real(100));
  settings.numerics.hourglass_coefficient = Real(0.1);
  settings.damping_rate = Real(0.1);
  settings.active_stress = true;
  sph::ElasticSolid<3> solid(body, relation, settings);
  std::vector<sph::Index> clamped;
  for (std::size_t i = 0; i < body.n_particles(); ++i)
    if (body.position[i][0] < Real(0.1)) clamped.push_back(sph::Index(i));
  solid.clamp(clamped);
  auto T_a = body.field(solid.active_tension_field());
  for (auto& t : T_a) t = Real(1);
  Real t = 0;
  const Real dt = solid.stable_time_step();
  for (int k = 0; k < 30; ++k, t += dt) solid.advance(t, dt);  // warm-up, past a tangent-modulus update
  const auto n = allocations_in([&] {
    for (int k = 0; k < 30; ++k, t += dt) solid.advance(t, solid.stable_time_step());
  });
  EXPECT_EQ(n, 0u);
}

// A fluid advection step with its wall (rebuild, density, forces, acoustic sub-steps) allocates
// nothing once warm; a re-sort (every sort_interval steps) is left out of the counted window.
TEST(Allocations, FluidStepWithWallAllocatesNothing) {
  using Vec2 = sph::Vec<2>;
  const Real dp = Real(0.05);
  auto water = geometry::lattice_box<2>("water", Vec2::Zero(), Vec2(1, Real(0.5)), dp);
  auto box = geometry::make_box({0, 0, -1}, {1, 1, 1});
  auto walls = geometry::wall_particles<2>("tank", *box, Vec2(-3 * dp, -3 * dp), Vec2(1 + 3 * dp, 1 + 3 * dp), dp, 3 * dp);
  sph::FluidWall<2> wall(walls.particles, walls.normals);
  sph::WeaklyCompressibleFluid<2>::Settings settings;
  settings.equation_of_state.sound_speed = 10;
  settings.body_force = Vec2(0, -1);
  settings.viscosity = Real(0.01);
  settings.particle_spacing = dp;
  settings.smoothing_length = Real(1.3) * dp;
  settings.numerics.sort_interval = 0;
  settings.numerics.transport_velocity = Real(0.1);
  sph::WeaklyCompressibleFluid<2> fluid(water, settings);
  fluid.add_wall(wall);
  auto step = [&] {
    fluid.update_neighbours();
    fluid.reinitialise_density();
    fluid.compute_prior_acceleration();
    for (int k = 0; k < 4; ++k) {
      const Real dt = fluid.acoustic_time_step();
      fluid.first_half(dt);
      fluid.second_half(dt);
    }
    fluid.check_state(0);
  };
  for (int k = 0; k < 5; ++k) step();  // warm-up
  EXPECT_EQ(allocations_in([&] {
              for (int k = 0; k < 5; ++k) step();
            }),
            0u);
}

TEST(Allocations, DiffusionAndMonodomainStepsAllocateNothing) {
  auto body = geometry::lattice_box<3>("slab", Vec3::Zero(), Vec3(2, 1, 1), Real(0.1));
  const auto kernel = sph::make_kernel<3>("wendland_c2");
  const auto relation = sph::build_inner_relation<3>(body.position, kernel, Real(0.13));
  cardio::Monodomain<3>::Settings settings;
  settings.cell_model = sph::AlievPanfilov::nash_panfilov_2004();
  settings.diffusion_tensor = {Real(0.1) * sph::Mat<3>::Identity()};
  cardio::Monodomain<3>::StimulusRegion stimulus{"corner", {0, 1, 2}, {}};
  stimulus.protocol.duration = 2;
  stimulus.protocol.strength = 50;
  settings.stimuli.push_back(stimulus);
  cardio::Monodomain<3> monodomain(body, relation, settings);
  for (int k = 0; k < 5; ++k) monodomain.advance(Real(k) * Real(0.1), Real(0.1));
  EXPECT_EQ(allocations_in([&] {
              for (int k = 5; k < 30; ++k) monodomain.advance(Real(k) * Real(0.1), Real(0.1));
            }),
            0u);

  auto other = geometry::lattice_box<3>("other", Vec3::Zero(), Vec3(2, 1, 1), Real(0.1));
  sph::ScalarDiffusionSystem<3>::Settings ds;
  ds.diffusion_tensor = {sph::Mat<3>::Identity()};
  sph::ScalarDiffusionSystem<3> diffusion(other, relation, ds);
  diffusion.advance(0, diffusion.stable_time_step());
  EXPECT_EQ(allocations_in([&] {
              for (int k = 0; k < 10; ++k) diffusion.advance(0, diffusion.stable_time_step());
            }),
            0u);
}

TEST(Allocations, RelationRebuiltInPlaceAllocatesNothing) {
  auto body = geometry::lattice_box<3>("block", Vec3::Zero(), Vec3(1, 1, 1), Real(0.05));
  const auto kernel = sph::make_kernel<3>("wendland_c2");
  auto relation = sph::build_inner_relation<3>(body.position, kernel, Real(0.065));
  for (auto& x : body.position) x *= Real(0.999);  // moved a little; the pair count does not grow
  sph::rebuild_inner_relation<3>(relation, body.position, kernel, Real(0.065));
  EXPECT_EQ(allocations_in([&] { sph::rebuild_inner_relation<3>(relation, body.position, kernel, Real(0.065)); }), 0u);
}

TEST(Allocations, TimeStepperLoopAllocatesNothingPerStep) {
  // The allocations of a run do not grow with its number of steps.
  auto count_for = [](Real end_time) {
    sph::TimeStepper stepper(0, end_time);
    Real sum = 0;
    sph::Stage outer{"outer", [] { return Real(0.01); }, {}};
    outer.then("work", [&](Real, Real dt) { sum += dt; })
        .sub_cycle(sph::make_stage("inner", [] { return Real(0.003); }, [&](Real, Real dt) { sum += dt; }));
    stepper.add_stage(std::move(outer));
    stepper.add_periodic_callback(Real(0.5), [&](const sph::StepInfo&) { sum += 1; });
    return allocations_in([&] { stepper.run(); });
  };
  EXPECT_EQ(count_for(Real(1)), count_for(Real(10)));
}

}  // namespace
