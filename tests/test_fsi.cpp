// Fluid-structure interaction (libsph/fsi) and open boundaries (libsph/fluid/open_boundaries):
// momentum of fluid + solid, the recorded wall forces against the weight of water, Archimedes on a
// rigid body, particle creation and deletion with every field and relation consistent, and the
// refusals of a too thin solid and a too fast inflow.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "geometry/lattice.hpp"
#include "geometry/wall_particles.hpp"
#include "libsph/core/interaction.hpp"
#include "libsph/core/time_stepper.hpp"
#include "libsph/fluid/open_boundaries.hpp"
#include "libsph/fluid/weakly_compressible_fluid.hpp"
#include "libsph/fsi/rigid_body.hpp"
#include "libsph/fsi/solid_fluid_coupling.hpp"
#include "apps/scenes/fsi/fsi_common.hpp"
#include "libsph/solid/elastic_solid.hpp"

namespace {

using sph::Real;
using Vec2 = sph::Vec<2>;
using Fluid = sph::WeaklyCompressibleFluid<2>;
using Solid = sph::ElasticSolid<2>;

Fluid::Settings basic_settings(Real dp, Real c0) {
  Fluid::Settings s;
  s.equation_of_state.sound_speed = c0;
  s.particle_spacing = dp;
  s.smoothing_length = Real(1.3) * dp;
  s.numerics.sort_interval = 0;
  return s;
}

// Outward normals of an axis-aligned box at each particle: the direction of the nearest face.
std::vector<Vec2> box_normals(const sph::ParticleSet<2>& body, const Vec2& lower, const Vec2& upper) {
  std::vector<Vec2> n(body.n_particles());
  for (std::size_t i = 0; i < n.size(); ++i) {
    const auto& x = body.position[i];
    const Real d[4] = {x[0] - lower[0], upper[0] - x[0], x[1] - lower[1], upper[1] - x[1]};
    const Vec2 dirs[4] = {Vec2(-1, 0), Vec2(1, 0), Vec2(0, -1), Vec2(0, 1)};
    int best = 0;
    for (int k = 1; k < 4; ++k)
      if (d[k] < d[best]) best = k;
    n[i] = dirs[best];
  }
  return n;
}

// Four layers of wall particles around a tank of width W and height 2 H.
geometry::WallParticles<2> tank_walls(Real dp, Real W, Real H) {
  const auto box = geometry::make_box(geometry::Vec3(0, 0, -1), geometry::Vec3(W, 2 * H, 1));
  return geometry::wall_particles<2>("tank", *box, Vec2(-4 * dp, -4 * dp), Vec2(W + 4 * dp, 2 * H + 4 * dp), dp, 4 * dp);
}

// Water at rest with its free surface at height H: p = rho0 g (H - y), the lattice volume kept.
void set_hydrostatic(Fluid& fluid, Real g, Real H) {
  auto& water = fluid.particles();
  auto rho = water.field(fluid.density_field());
  auto m = water.field(fluid.mass_field());
  for (std::size_t i = 0; i < water.n_particles(); ++i) {
    rho[i] = fluid.settings().equation_of_state.density(g * (H - water.position[i][1]));
    m[i] = rho[i] * water.volume[i];
  }
  fluid.update_pressure();
}

Solid::Settings soft_solid(Real density, Real young) {
  Solid::Settings s;
  Real lambda = 0, mu = 0;
  sph::lame_constants(young, Real(0.3), lambda, mu);
  s.material = sph::SaintVenantKirchhoff<2>{lambda, mu};
  s.density = density;
  return s;
}

TEST(ParticleSet, SelectDeletesAndCopiesEveryField) {
  auto body = geometry::lattice_box<2>("b", Vec2::Zero(), Vec2(4, 1), Real(1));
  const auto f = body.register_field<Real>("f", Real(0));
  for (std::size_t i = 0; i < 4; ++i) body.field(f)[i] = Real(i);
  const std::vector<sph::Index> order{3, 1, 1};
  body.select(order);
  ASSERT_EQ(body.n_particles(), 3u);
  EXPECT_EQ(body.volume.size(), 3u);
  EXPECT_EQ(body.field(f).size(), 3u);
  EXPECT_EQ(body.field(f)[0], 3);
  EXPECT_EQ(body.field(f)[2], 1);
  EXPECT_EQ(body.position[2], body.position[1]);
  const std::vector<sph::Index> wrong{5};
  EXPECT_THROW(body.select(wrong), std::invalid_argument);
}

// A free elastic block, finer than the fluid (h_fluid / h_solid = 2), moving through an inviscid
// fluid block without walls or gravity: the pair forces between the two are recorded and returned
// with the opposite sign, the fluid's own pressure pairs and the solid's stress and hourglass pairs
// are antisymmetric, so the total momentum stays at its initial value to round-off while a large
// part of it passes from the solid to the fluid. (The fluid's viscosity is off: its renormalised
// Laplacian weighs the two particles of a pair differently near a free surface.)
TEST(Fsi, MomentumOfFluidAndSolidIsConservedAcrossSubCycling) {
  const Real dp = Real(0.05), c0 = 10;
  auto water = geometry::lattice_box<2>("water", Vec2::Zero(), Vec2(1, 1), dp);
  // A hole for the block: drop the fluid particles inside [0.35, 0.65]^2.
  const Vec2 lo(Real(0.35), Real(0.35)), hi(Real(0.65), Real(0.65));
  std::vector<sph::Index> keep;
  for (std::size_t i = 0; i < water.n_particles(); ++i) {
    const auto& x = water.position[i];
    if (!(x[0] > lo[0] && x[0] < hi[0] && x[1] > lo[1] && x[1] < hi[1])) keep.push_back(static_cast<sph::Index>(i));
  }
  water.select(keep);
  auto block = geometry::lattice_box<2>("block", lo, hi, dp / 2);
  auto relation = sph::build_inner_relation<2>(block.position, sph::WendlandC2<2>{}, Real(1.3) * dp / 2);
  Solid solid(block, relation, soft_solid(Real(2), Real(400)));
  for (auto& v : block.field(solid.velocity_field())) v = Vec2(Real(0.5), Real(0.2));
  Fluid fluid(water, basic_settings(dp, c0));
  sph::SolidFluidCoupling<2> coupling(fluid, solid, box_normals(block, lo, hi), {dp / 2, true});

  auto momentum = [&] {
    const auto vf = water.field(fluid.velocity_field());
    const auto m = water.field(fluid.mass_field());
    const auto vs = block.field(solid.velocity_field());
    Vec2 fluid_part = Vec2::Zero(), solid_part = Vec2::Zero();
    for (std::size_t i = 0; i < water.n_particles(); ++i) fluid_part += m[i] * vf[i];
    for (std::size_t j = 0; j < block.n_particles(); ++j) solid_part += solid.settings().density * block.volume[j] * vs[j];
    return std::pair{fluid_part, solid_part};
  };
  const auto [f0, s0] = momentum();
  sph::SectionTimers timers;
  sph::Stage step = fluid.advection_stage(timers);
  coupling.fill(step, timers);
  sph::TimeStepper stepper(0, Real(0.1));
  stepper.add_stage(std::move(step));
  stepper.run();
  const auto [f1, s1] = momentum();
  const double initial = (f0 + s0).norm(), drift = ((f1 + s1) - (f0 + s0)).norm();
  std::printf("momentum: initial %.6e, solid %.4f -> %.4f, fluid %.4f -> %.4f, drift %.2e relative; %zu acoustic, "
              "%zu solid steps\n",
              initial, double(s0.norm()), double(s1.norm()), double(f0.norm()), double(f1.norm()), drift / initial,
              fluid.acoustic_steps(), coupling.solid_steps());
  EXPECT_GT(coupling.solid_steps(), fluid.acoustic_steps());  // the solid sub-cycles
  EXPECT_GT(f1.norm(), 0.1 * s0.norm());                       // momentum did pass to the fluid
  EXPECT_LT(drift / initial, 1e-10);
}

// Water at rest in a tank (hydrostatic start): the recorded force of the fluid on the tank is the
// weight of the water, rho g H W per unit depth, within 2 % (the wall pressure is extrapolated
// hydrostatically; the small rest is the free-surface row and the discrete wall).
TEST(Fsi, RecordedWallForceOfWaterAtRestIsItsWeight) {
  const Real dp = Real(0.05), g = 1, H = 1, W = 1;
  auto water = geometry::lattice_box<2>("water", Vec2::Zero(), Vec2(W, H), dp);
  auto wall_set = tank_walls(dp, W, H);
  sph::FluidWall<2> tank(wall_set.particles, wall_set.normals);
  auto settings = basic_settings(dp, 10 * std::sqrt(g * H));
  settings.body_force = Vec2(0, -g);
  settings.reference_speed = std::sqrt(g * H);
  Fluid fluid(water, settings);
  const std::size_t k = fluid.add_wall(tank, sph::WallForces::record);
  set_hydrostatic(fluid, g, H);
  sph::SectionTimers timers;
  sph::TimeStepper stepper(0, Real(0.5));
  stepper.add_stage(fluid.advection_stage(timers));
  stepper.run();
  std::vector<Vec2> fp(wall_set.particles.n_particles()), fv(fp.size());
  fluid.wall_forces(k, fp, fv);
  Vec2 total = Vec2::Zero();
  for (std::size_t j = 0; j < fp.size(); ++j) total += fp[j] + fv[j];
  double weight = 0;
  for (std::size_t i = 0; i < water.n_particles(); ++i) weight += water.field(fluid.mass_field())[i] * g;
  std::printf("force on the tank (%.5f, %.5f) against the weight %.5f: %.2f %%\n", double(total[0]), double(total[1]),
              weight, 100 * (-total[1] - weight) / weight);
  EXPECT_NEAR(-total[1], weight, 0.02 * weight);
  EXPECT_NEAR(total[0], 0, 0.005 * weight);
}

// A disc of twice the water's density released in water at rest: buoyancy (Archimedes) and the
// added mass of a circular cylinder (C_a rho_f V with C_a = 1, e.g. Newman, Marine Hydrodynamics,
// 1977, sec. 4.13) give the acceleration -g (rho_s - rho_f) / (rho_s + rho_f) = -g / 3 while the
// flow is still potential; within 5 % as the mean over the first 0.1 time units (ten acoustic times
// r / c0, in which the added mass builds up; measured 1.8 %). Later the mean falls further below
// (9.7 % at 0.2, 17 % at 0.3) as the disc's wake and the Riemann dissipation start to brake it.
TEST(Fsi, RigidDiscSinksWithTheArchimedesAcceleration) {
  const Real dp = Real(0.025), g = 1, H = 1, W = 1;
  auto all = geometry::lattice_box<2>("water", Vec2::Zero(), Vec2(W, H), dp);
  const Vec2 c(Real(0.5), Real(0.5));
  const Real radius = Real(0.1);
  std::vector<sph::Index> fluid_ids, disc_ids;
  for (std::size_t i = 0; i < all.n_particles(); ++i)
    ((all.position[i] - c).norm() < radius ? disc_ids : fluid_ids).push_back(static_cast<sph::Index>(i));
  std::vector<Vec2> disc_x;
  std::vector<Real> disc_v;
  for (const auto i : disc_ids) {
    disc_x.push_back(all.position[i]);
    disc_v.push_back(all.volume[i]);
  }
  sph::ParticleSet<2> disc("disc", disc_x, disc_v);
  auto& water = all;
  water.select(fluid_ids);
  std::vector<Vec2> normals;
  for (const auto& x : disc.position) normals.push_back((x - c).norm() > 0 ? Vec2((x - c).normalized()) : Vec2(0, 1));
  auto wall_set = tank_walls(dp, W, H);
  sph::FluidWall<2> tank(wall_set.particles, wall_set.normals);
  auto settings = basic_settings(dp, 10 * std::sqrt(g * H));
  settings.body_force = Vec2(0, -g);
  settings.reference_speed = std::sqrt(g * H);
  Fluid fluid(water, settings);
  fluid.add_wall(tank);
  set_hydrostatic(fluid, g, H);
  sph::RigidBody<2> body(fluid, disc, normals, {Real(2), sph::RigidMotion::free, Vec2::Zero(), Vec2(0, -g)});
  sph::SectionTimers timers;
  sph::Stage step = fluid.advection_stage(timers);
  step.fill(fluid.acoustic_slot(), "rigid body 'disc'", sph::coupling(body, fluid, body.wall()));
  const Real T = Real(0.1);
  sph::TimeStepper stepper(0, T);
  stepper.add_stage(std::move(step));
  stepper.run();
  const double measured = 2 * (body.centre()[1] - c[1]) / (T * T);  // y = y0 + a t^2 / 2
  const double exact = -g / 3.0;
  std::printf("disc: mean acceleration %.4f against %.4f (%.1f %%), angle %.2e\n", measured, exact,
              100 * (measured - exact) / -exact, double(body.angle()));
  EXPECT_NEAR(measured, exact, 0.05 * -exact);
  EXPECT_LT(std::abs(body.angle()), 1e-3);
}

// A channel with an emitter at the inlet and an outflow zone at the outlet: after many advection
// steps the particle count is the initial one plus the emitted minus the deleted, every field and
// relation has the new size, and the emitter has kept the buffer full.
TEST(OpenBoundaries, EmissionAndDeletionKeepFieldsAndRelationsConsistent) {
  const Real dp = Real(0.05), U = Real(0.5), c0 = 10;
  const Real L = 2, D = 0.5;
  auto water = geometry::lattice_box<2>("water", Vec2(-0.5, 0), Vec2(L, D), dp);
  const auto channel = geometry::make_box(geometry::Vec3(-1, 0, -1), geometry::Vec3(L + 1, D, 1));
  auto wall_set = geometry::wall_particles<2>("walls", *channel, Vec2(-0.5, -4 * dp), Vec2(L + 0.5, D + 4 * dp), dp,
                                              4 * dp);
  sph::FluidWall<2> walls(wall_set.particles, wall_set.normals);
  auto settings = basic_settings(dp, c0);
  settings.reference_speed = U;
  settings.viscosity = Real(0.01);
  settings.numerics.density_reinitialisation = sph::DensityReinitialisation::free_surface;
  Fluid fluid(water, settings);
  fluid.add_wall(walls);
  sph::InflowZone<2>::Settings inflow;
  inflow.lower = Vec2(-0.5, 0);
  inflow.upper = Vec2(0, D);
  inflow.mean_speed = U;
  inflow.velocity = [&](const Vec2&, Real) { return Vec2(U, 0); };
  sph::InflowZone<2> inlet(fluid, inflow);
  sph::OutflowZone<2> outlet(fluid, L);
  sph::SectionTimers timers;
  sph::Stage step = fluid.advection_stage(timers);
  step.fill(fluid.particles_slot(), "inflow emission", [&](Real, Real) { inlet.emit(); });
  step.fill(fluid.particles_slot(), "outflow", [&](Real, Real) { outlet.remove(); });
  step.fill(fluid.acoustic_slot(), "inflow velocity", sph::coupling(fluid, inlet, sph::same_particles));
  const std::size_t n0 = water.n_particles();
  sph::TimeStepper stepper(0, Real(1.5));
  stepper.add_stage(std::move(step));
  stepper.run();
  const std::size_t n = water.n_particles();
  std::printf("particles %zu -> %zu: %zu emitted, %zu deleted\n", n0, n, inlet.emitted(), outlet.removed());
  EXPECT_GT(inlet.emitted(), 0u);
  EXPECT_GT(outlet.removed(), 0u);
  EXPECT_EQ(n, n0 + inlet.emitted() - outlet.removed());
  EXPECT_EQ(water.volume.size(), n);
  for (const auto& f : water.fields()) EXPECT_EQ(f->size(), n) << f->name();
  fluid.update_neighbours();  // the relations of the particles as they now are
  const auto& inner = fluid.inner_relation();
  ASSERT_EQ(inner.offsets.size(), n + 1);
  for (const auto j : inner.neighbour) ASSERT_LT(static_cast<std::size_t>(j), n);
  ASSERT_EQ(fluid.wall_relation(0).offsets.size(), n + 1);
  // The buffer is full: its rows hold the lattice's count of particles (10 across, 10 along).
  std::size_t in_buffer = 0;
  for (const auto& x : water.position)
    if (x[0] >= -0.5 && x[0] < 0) ++in_buffer;
  EXPECT_NEAR(double(in_buffer), 100.0, 10.0);
}

TEST(OpenBoundaries, InflowFasterThanATenthOfTheSoundSpeedIsRefused) {
  auto water = geometry::lattice_box<2>("water", Vec2::Zero(), Vec2(1, 1), Real(0.1));
  Fluid fluid(water, basic_settings(Real(0.1), 10));
  sph::InflowZone<2>::Settings inflow;
  inflow.lower = Vec2(0, 0);
  inflow.upper = Vec2(Real(0.2), 1);
  inflow.mean_speed = Real(1.5);
  inflow.velocity = [](const Vec2&, Real) { return Vec2(Real(1.5), 0); };
  try {
    sph::InflowZone<2> zone(fluid, inflow);
    FAIL() << "an inflow at Mach 0.15 was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("exceeds c0 / 10"), std::string::npos) << e.what();
  }
}

TEST(Fsi, SolidThinnerThanOneFluidParticleIsRefused) {
  const Real dp = Real(0.05);
  auto water = geometry::lattice_box<2>("water", Vec2(0, 0), Vec2(1, 0.5), dp);
  Fluid fluid(water, basic_settings(dp, 10));
  const Vec2 lo(0, -0.025), hi(1, 0);  // a plate half a fluid spacing thick, at dp / 4
  auto plate = geometry::lattice_box<2>("plate", lo, hi, dp / 4);
  auto relation = sph::build_inner_relation<2>(plate.position, sph::WendlandC2<2>{}, Real(1.3) * dp / 4);
  Solid solid(plate, relation, soft_solid(1, 100));
  try {
    sph::SolidFluidCoupling<2> coupling(fluid, solid, box_normals(plate, lo, hi), {dp / 4, true});
    FAIL() << "a plate of half a fluid spacing was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("thinner than one fluid particle spacing"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("0.025"), std::string::npos) << e.what();
  }
  // One fluid spacing thick is accepted.
  const Vec2 lo2(0, -0.05);
  auto plate2 = geometry::lattice_box<2>("plate2", lo2, hi, dp / 4);
  auto relation2 = sph::build_inner_relation<2>(plate2.position, sph::WendlandC2<2>{}, Real(1.3) * dp / 4);
  Solid solid2(plate2, relation2, soft_solid(1, 100));
  sph::SolidFluidCoupling<2> coupling(fluid, solid2, box_normals(plate2, lo2, hi), {dp / 4, true});
  EXPECT_NEAR(coupling.thickness(), 0.05, 1e-6);
  // The acceleration relaxation must lie in (0, 1].
  for (Real theta : {Real(0), Real(-0.1), Real(1.5)}) {
    try {
      sph::SolidFluidCoupling<2> relaxed(fluid, solid2, box_normals(plate2, lo2, hi), {dp / 4, true, theta});
      FAIL() << "acceleration relaxation " << theta << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("acceleration relaxation"), std::string::npos) << e.what();
    }
  }
}

}  // namespace


// The oscillation statistics of the FSI scenes: a sine of amplitude 0.8 about 0.1 at frequency 0.2,
// sampled every 0.04 over 100 time units, with one noise spike of +0.3 on the crest at t = 61.24. The half range of
// the whole window takes the spike (0.95); the mean of the periods' half ranges (Turek & Hron's
// per-period amplitude) moves by the spike's share of one period in twenty (0.8 + 0.15 / 20).
TEST(FsiStatistics, PeriodAmplitudeIsTheMeanOverPeriodsAndTheHalfRangeTakesTheSpike) {
  std::vector<double> t, y;
  for (int k = 0; k <= 2500; ++k) {
    t.push_back(0.04 * k);
    y.push_back(0.1 + 0.8 * std::sin(2 * M_PI * 0.2 * t.back()) + (k == 1531 ? 0.3 : 0.0));
  }
  const auto o = cardiosph::analyse_oscillation(t, y, 0);
  EXPECT_NEAR(o.frequency, 0.2, 0.002);
  EXPECT_NEAR(o.amplitude, 0.8 + 0.15, 0.01);
  EXPECT_NEAR(o.period_amplitude, 0.8 + 0.15 / 20, 0.01);
  EXPECT_NEAR(o.period_mean, 0.1 + 0.15 / 20, 0.01);
}
