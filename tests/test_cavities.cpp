// The cavities as a system on the solid's particles (cardio/cavities.hpp) and the boundary springs
// (cardio/boundary_springs.hpp): a closed tetrahedral cavity whose vertices move with single
// particles, so every force has a closed form; the loads of the interactions in the solid's loads
// slot at the mid-step time, the volume penalty of a coupled cavity, and the springs' normal and
// full restoring forces.

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "cardio/boundary_springs.hpp"
#include "cardio/cavities.hpp"
#include "tests/tetrahedral_cavity.hpp"

namespace {

using sph::Real;
using Vec3 = sph::Vec<3>;
using tetrahedral_cavity::Block;
using tetrahedral_cavity::corners;
using tetrahedral_cavity::tetrahedron;

TEST(Cavities, VolumeFollowsTheSolidAndThePressureLoadIsTheFaceForceAtMidStep) {
  Block b;
  const auto p = corners(b.body);
  const cardio::CavityPressureSettings ramp{cardio::CavityPressureMode::ramp, 3, 1, 10};
  cardio::Cavities cavities(b.solid, {tetrahedron(b.body, p, cardio::label_lv_endo)}, ramp);
  ASSERT_TRUE(cavities.loaded());
  EXPECT_EQ(cavities.name(0), "lv");
  EXPECT_EQ(*cavities.find(cardio::label_lv_endo), 0u);
  EXPECT_FALSE(cavities.find(cardio::label_rv_endo).has_value());
  EXPECT_NEAR(cavities.volume(0), 8.0 / 6, 1e-12);  // legs of 2: 2^3 / 6
  b.body.position[p[1]][0] += 1;                     // F stays I: the vertex follows its particle
  EXPECT_NEAR(cavities.volume(0), 12.0 / 6, 1e-12);

  // Over the step [2, 4] the ramp p(t) = 3 min(1, t / 10) is taken at t = 3: 0.9.
  const auto force = b.body.field(b.solid.external_force_field());
  std::fill(force.begin(), force.end(), Vec3::Zero());
  interact(b.solid, cavities, sph::same_particles, 2, 2);
  std::vector<Vec3> expected(b.body.n_particles(), Vec3::Zero());
  const auto F = b.body.field(b.solid.deformation_gradient_field());
  const auto X = b.body.field(b.solid.reference_position_field());
  const double p_mid = cavities.pressure(0).at(3);
  EXPECT_NEAR(p_mid, 0.9, 1e-12);
  cavities.surface(0).add_pressure_forces(Real(p_mid), b.body.position, F, X, expected);
  Vec3 total = Vec3::Zero();
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(force[i], expected[i]);
    total += force[i];
  }
  EXPECT_GT(expected[p[1]][0], 0);  // the pressure pushes the wall out of the cavity
  EXPECT_LT(total.norm(), 1e-12);   // a closed surface: no net force

  // Coupled: p = p_ref + (V_b - V) / C_c at the current volume V = 2.
  cavities.couple(0, {1, 2.5, 0.25});
  std::fill(force.begin(), force.end(), Vec3::Zero());
  interact(b.solid, cavities, sph::same_particles, 2, 2);
  std::fill(expected.begin(), expected.end(), Vec3::Zero());
  cavities.surface(0).add_pressure_forces(Real(1 + (2.5 - 2.0) / 0.25), b.body.position, F, X, expected);
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR((force[i] - expected[i]).norm(), 0, 1e-12);
}

TEST(Cavities, WithoutAPressureModeTheyAreNotLoadedAndTheyRefuseAnotherSolid) {
  Block b, other;
  const cardio::CavityPressureSettings none{cardio::CavityPressureMode::none, 3, 1, 10};
  const cardio::Cavities cavities(b.solid, {tetrahedron(b.body, corners(b.body), cardio::label_rv_endo)}, none);
  EXPECT_FALSE(cavities.loaded());
  EXPECT_EQ(cavities.name(0), "rv");
  EXPECT_THROW(interact(other.solid, cavities, sph::same_particles, 0, 1), std::invalid_argument);
}

TEST(BoundarySprings, EpicardiumHoldsAlongTheNormalAndTheBaseInEveryDirection) {
  Block b;
  const auto p = corners(b.body);
  auto epi = tetrahedron(b.body, p, cardio::label_epi), base = tetrahedron(b.body, p, cardio::label_base);
  base.loaded_particles = {p[2]};
  base.area_normals = {Vec3(0, 0, 2)};
  EXPECT_THROW(cardio::BoundarySprings(b.solid, {epi}, 1, 1), std::invalid_argument);  // no base to hold
  const cardio::BoundarySprings springs(b.solid, {epi, base}, Real(0.5), Real(10));
  ASSERT_EQ(springs.springs().size(), 2u);
  EXPECT_TRUE(springs.springs()[0].normal_only);
  const cardio::BoundarySprings base_only(b.solid, {epi, base}, 0, Real(10));  // a spring of stiffness 0 is left out
  EXPECT_EQ(base_only.springs().size(), 1u);

  const Vec3 u(0.1, -0.2, 0.3);
  for (const auto i : {p[0], p[1], p[2]}) b.body.position[i] += u;
  const auto force = b.body.field(b.solid.external_force_field());
  std::fill(force.begin(), force.end(), Vec3::Zero());
  interact(b.solid, springs, sph::same_particles, 0, 1);
  // Epicardium: -k (u . n) n |A|, with A = (0, 0, -2) at p0 and (3, 4, 0) at p1; base: -k |A| u at p2.
  EXPECT_NEAR((force[p[0]] - Vec3(0, 0, -0.5 * 0.3 * 2)).norm(), 0, 1e-12);
  EXPECT_NEAR((force[p[1]] + Real(0.5) * (u.dot(Vec3(0.6, 0.8, 0))) * Vec3(3, 4, 0)).norm(), 0, 1e-12);
  EXPECT_NEAR((force[p[2]] + Real(10 * 2) * u).norm(), 0, 1e-12);
  EXPECT_EQ(force[p[3]], Vec3::Zero());
}

}  // namespace
