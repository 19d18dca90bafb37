// Analytic shapes, their volumes, and particle generation with relaxation.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "geometry/particle_generation.hpp"
#include "geometry/shape.hpp"
#include "libsph/core/parallel.hpp"

namespace {

using geometry::Vec3;
const double pi = std::acos(-1.0);

// Distance from p to the ellipsoid surface by brute force over a fine parametric sampling.
double sampled_ellipsoid_distance(const Vec3& p, const Vec3& radii, int n) {
  double best = 1e300;
  for (int a = 0; a <= n; ++a) {
    const double u = pi * a / n;
    for (int b = 0; b < 2 * n; ++b) {
      const double v = pi * b / n;
      const Vec3 s(radii.x() * std::sin(u) * std::cos(v), radii.y() * std::sin(u) * std::sin(v), radii.z() * std::cos(u));
      best = std::min(best, (p - s).norm());
    }
  }
  return best;
}

TEST(Shapes, EllipsoidDistanceMatchesBruteForce) {
  const Vec3 radii(3, 2, 1);
  const auto ellipsoid = geometry::make_ellipsoid(Vec3::Zero(), radii);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(-4, 4);
  double worst = 0;
  for (int n = 0; n < 40; ++n) {
    const Vec3 p(coordinate(random), coordinate(random), coordinate(random));
    const double exact = std::abs(ellipsoid->signed_distance(p));
    worst = std::max(worst, std::abs(exact - sampled_ellipsoid_distance(p, radii, 400)));
    EXPECT_EQ(ellipsoid->signed_distance(p) < 0, p.cwiseQuotient(radii).squaredNorm() < 1);
  }
  // Points on axes and in coordinate planes (the special cases of the root finding).
  EXPECT_NEAR(ellipsoid->signed_distance(Vec3::Zero()), -1.0, 1e-12);
  EXPECT_NEAR(ellipsoid->signed_distance(Vec3(5, 0, 0)), 2.0, 1e-12);
  EXPECT_NEAR(ellipsoid->signed_distance(Vec3(0, 0, 0.5)), -0.5, 1e-12);
  for (const Vec3& p : {Vec3(1, 0.5, 0), Vec3(0, 1, 0.2), Vec3(2, 0, 0.3), Vec3(0.5, 0, 0)}) {
    const double sampled = sampled_ellipsoid_distance(p, radii, 400);
    worst = std::max(worst, std::abs(std::abs(ellipsoid->signed_distance(p)) - sampled));
  }
  std::cout << "[ measured ] largest |exact - sampled| ellipsoid distance = " << worst << " (bound 2e-3)\n";
  EXPECT_LT(worst, 2e-3);  // the sampling itself is about 1e-3 coarse
}

TEST(Shapes, BooleanVolumesByOctreeIntegration) {
  const auto outer = geometry::make_ellipsoid(Vec3::Zero(), Vec3(2, 2, 2));
  const auto inner = geometry::make_ellipsoid(Vec3::Zero(), Vec3(1, 1, 1));
  const double shell = 4.0 / 3.0 * pi * (8 - 1);
  const double integrated = geometry::shape_volume(*geometry::make_difference(outer, inner), 0.02);
  std::cout << "[ measured ] spherical shell volume relative error = " << integrated / shell - 1 << " (bound 1e-3)\n";
  EXPECT_NEAR(integrated / shell, 1.0, 1e-3);
  // Half of the sphere by a half-space through the centre; a cylinder cut by a box.
  const auto half = geometry::make_intersection(outer, geometry::make_half_space(Vec3::Zero(), Vec3(0, 0, 1)));
  EXPECT_NEAR(geometry::shape_volume(*half, 0.02) / (0.5 * 4.0 / 3.0 * pi * 8), 1.0, 1e-3);
  const auto cylinder = geometry::make_cylinder(Vec3(0, 0, 0), Vec3(0, 0, 2), 1);
  const auto cut = geometry::make_intersection(cylinder, geometry::make_box(Vec3(-5, -5, -5), Vec3(5, 5, 1)));
  EXPECT_NEAR(geometry::shape_volume(*cut, 0.01) / pi, 1.0, 1e-3);
  EXPECT_NEAR(*cylinder->volume(), 2 * pi, 1e-12);
  const auto both = geometry::make_union(geometry::make_box(Vec3(0, 0, 0), Vec3(2, 1, 1)), geometry::make_box(Vec3(1, 0, 0), Vec3(3, 1, 1)));
  EXPECT_NEAR(geometry::shape_volume(*both, 0.01), 3.0, 1e-9);
}

TEST(Shapes, NormalsPointOutwards) {
  const auto shell = geometry::make_difference(geometry::make_ellipsoid(Vec3::Zero(), Vec3(2, 2, 2)),
                                               geometry::make_ellipsoid(Vec3::Zero(), Vec3(1, 1, 1)));
  EXPECT_LT((shell->normal(Vec3(1.9, 0, 0)) - Vec3(1, 0, 0)).norm(), 1e-6);
  EXPECT_LT((shell->normal(Vec3(1.1, 0, 0)) - Vec3(-1, 0, 0)).norm(), 1e-6);
  const auto box = geometry::make_box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  EXPECT_LT((box->normal(Vec3(0.5, 0.5, 0.9)) - Vec3(0, 0, 1)).norm(), 1e-6);
}

TEST(ParticleGeneration, BoxLatticeFillsExactly) {
  const auto box = geometry::make_box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  geometry::ParticleGenerationSettings settings;
  settings.spacing = 0.1;
  const auto body = geometry::generate_particles(*box, settings);
  EXPECT_EQ(body.size(), 1000u);
  std::cout << "[ measured ] box: volume error " << body.volume_relative_error << ", spread " << body.density_spread
            << ", residual " << body.residual_initial << " -> " << body.residual_final << " in "
            << body.relaxation_steps_done << " steps\n";
  EXPECT_LT(std::abs(body.volume_relative_error), 0.01);
}

TEST(ParticleGeneration, SphereVolumeAndConfinement) {
  const auto sphere = geometry::make_ellipsoid(Vec3::Zero(), Vec3(1, 1, 1));
  geometry::ParticleGenerationSettings settings;
  settings.spacing = 0.1;
  const auto body = geometry::generate_particles(*sphere, settings);
  double deepest_outside = -1e300;
  for (const auto& p : body.positions) deepest_outside = std::max(deepest_outside, p.norm() - 1);
  std::cout << "[ measured ] sphere r = 1, dp = 0.1: " << body.size() << " particles, N dp^3 / V = "
            << body.size() * 1e-3 / body.shape_volume << ", volume error " << body.volume_relative_error
            << ", spread " << body.density_spread << ", V/dp^3 in [" << body.volume_min_ratio << ", "
            << body.volume_max_ratio << "], nearest neighbour / dp in [" << body.spacing_min_ratio << " (bound 0.8), "
            << body.spacing_max_ratio << "], mean " << body.spacing_mean_ratio << ", residual " << body.residual_initial
            << " -> " << body.residual_final << " in " << body.relaxation_steps_done << " steps\n";
  // Every particle at least 0.1 dp inside, up to the level set's interpolation error (~dp^2 / 8R).
  EXPECT_LT(deepest_outside, -0.01 + 2e-3);
  EXPECT_LT(std::abs(body.volume_relative_error), 0.01);
  EXPECT_LT(body.density_spread, 0.01);
  EXPECT_LT(body.residual_final, 0.2 * body.residual_initial);
  EXPECT_GT(body.spacing_min_ratio, 0.8);  // no two particles pressed together
}


// Positions and volumes bit for bit equal.
long count_differences(const geometry::BodyParticles& a, const geometry::BodyParticles& b) {
  if (a.size() != b.size()) return -1;
  long differences = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a.positions[i] != b.positions[i] || a.volumes[i] != b.volumes[i]) ++differences;
  return differences;
}

// The relaxation's neighbour lists hold the particles and outside nodes within support + skin and are
// reused until a particle has moved skin / 2: the particles must come out exactly as with lists built
// at every step (skin 0), whatever the skin.
TEST(ParticleGeneration, ReusedNeighbourListsGiveTheParticlesOfListsBuiltEveryStep) {
  // A body with a concave edge, so that the outside nodes matter: a sphere cut by a box.
  const auto shape = geometry::make_difference(geometry::make_ellipsoid(Vec3::Zero(), Vec3(1, 1, 1)),
                                               geometry::make_box(Vec3(0.3, 0.3, -2), Vec3(2, 2, 2)));
  geometry::ParticleGenerationSettings settings;
  settings.spacing = 0.15;
  settings.relaxation_steps = 30;
  settings.neighbour_skin = 0;
  const auto every_step = geometry::generate_particles(*shape, settings);
  for (double skin : {0.3, 1.0}) {
    settings.neighbour_skin = skin;
    const auto reused = geometry::generate_particles(*shape, settings);
    const long differences = count_differences(every_step, reused);
    std::cout << "[ measured ] skin " << skin << " dp: " << reused.neighbour_builds << " list builds in "
              << reused.relaxation_steps_done << " steps (skin 0: " << every_step.neighbour_builds << "), "
              << differences << " of " << reused.size() << " particles differ (bound 0)\n";
    EXPECT_EQ(differences, 0);
    EXPECT_LT(reused.neighbour_builds, every_step.neighbour_builds / 2);
  }
  EXPECT_EQ(every_step.neighbour_builds, every_step.relaxation_steps_done + 1);
}

TEST(ParticleGeneration, SameParticlesForOneAndTwoThreads) {
  const auto sphere = geometry::make_ellipsoid(Vec3::Zero(), Vec3(1, 0.8, 0.6));
  geometry::ParticleGenerationSettings settings;
  settings.spacing = 0.1;
  settings.relaxation_steps = 30;
  auto run = [&](std::size_t threads) {
    sph::ThreadLimit limit(threads);
    return geometry::generate_particles(*sphere, settings);
  };
  const auto one = run(1), two = run(2);
  const long differences = count_differences(one, two);
  std::cout << "[ measured ] " << differences << " of " << one.size() << " particles differ between 1 and 2 threads (bound 0)\n";
  EXPECT_EQ(differences, 0);
  EXPECT_EQ(one.volume_relative_error, two.volume_relative_error);
  EXPECT_EQ(one.spacing_mean_ratio, two.spacing_mean_ratio);
}

}  // namespace

namespace {

// A block with a fin thinner than the spacing (0.6 dp) standing on it, and a block one spacing
// thin: relaxation puts particles into both, with too few neighbours or a flat neighbourhood.
// The geometry stage must see them, name the place and the spacing that resolves them.
TEST(ParticleGeneration, ThinFeaturesAreFoundAndNamed) {
  geometry::ParticleGenerationSettings settings;
  settings.spacing = 1.0;
  settings.relaxation_steps = 50;
  const auto block = geometry::make_box(Vec3(0, 0, 0), Vec3(10, 10, 6));
  // Healthy: the block alone.
  const auto healthy = geometry::generate_particles(*block, settings);
  std::cout << "[ measured ] block 10 x 10 x 6 at dp 1: neighbours median " << healthy.neighbours_median << ", min "
            << healthy.neighbours_min << ", conditioning min " << healthy.conditioning_min << ", nearest "
            << healthy.spacing_min_ratio << " dp\n";
  EXPECT_TRUE(healthy.thin.empty());
  EXPECT_NO_THROW(geometry::require_no_thin_features(healthy, 1.0, "block"));

  for (const auto& [name, shape] : std::vector<std::pair<std::string, geometry::ShapePtr>>{
           {"fin 0.6 dp thick", geometry::make_union(block, geometry::make_box(Vec3(5.2, 1, 6), Vec3(5.8, 9, 12)))},
           {"sheet 1 dp thick", geometry::make_box(Vec3(0, 0, 0), Vec3(12, 12, 1.0))}}) {
    const auto body = geometry::generate_particles(*shape, settings);
    std::cout << "[ measured ] " << name << ": " << body.thin.size() << " of " << body.size()
              << " particles flagged; neighbours median " << body.neighbours_median << ", min " << body.neighbours_min
              << ", conditioning min " << body.conditioning_min << ", nearest " << body.spacing_min_ratio << " dp\n";
    EXPECT_FALSE(body.thin.empty()) << name;
    try {
      geometry::require_no_thin_features(body, 1.0, name);
      ADD_FAILURE() << name << ": not refused";
    } catch (const std::invalid_argument& e) {
      const std::string m = e.what();
      std::cout << "[ refused  ] " << m << '\n';
      EXPECT_NE(m.find("thinner than the spacing"), std::string::npos) << m;
      EXPECT_NE(m.find("a spacing of"), std::string::npos) << m;
    }
  }
}

}  // namespace
