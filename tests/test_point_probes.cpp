// The observer mechanism: the linear moving-least-squares fit is exact on linear fields at interior,
// edge and corner points; with the particles' gradients it is exact on quadratic fields (where the
// plain fit is not); built on current positions, update() follows moved particles.
#include <gtest/gtest.h>

#include <cstdio>

#include "geometry/lattice.hpp"
#include "libsph/core/point_probes.hpp"
#include "tests/precision.hpp"

namespace {

using sph::Real;
using Vec3 = sph::Vec<3>;
using Mat3 = sph::Mat<3>;

const Mat3 A = (Mat3() << 1.1, 0.2, -0.3, 0.1, 0.9, 0.4, -0.2, 0.3, 1.2).finished();

// A quadratic vector field (a bending-like map) and its exact gradient.
Vec3 quadratic(const Vec3& X) { return A * X + Vec3(0.5 * X[0] * X[0], 0.3 * X[0] * X[1], -0.4 * X[2] * X[2]); }
Mat3 quadratic_gradient(const Vec3& X) {
  Mat3 G = A;
  G(0, 0) += X[0];
  G(1, 0) += 0.3 * X[1];
  G(1, 1) += 0.3 * X[0];
  G(2, 2) += -0.8 * X[2];
  return G;
}

struct Lattice {
  sph::ParticleSet<3> body = geometry::lattice_box<3>("cube", Vec3::Zero(), Vec3::Ones(), Real(0.1));
  sph::AnyKernel<3> kernel = sph::make_kernel<3>("wendland_c2");
  Real h = Real(0.13);
};

TEST(PointProbes, LinearFitIsExactOnLinearFieldsAlsoAtCorners) {
  Lattice l;
  const std::vector<Vec3> points{Vec3::Constant(0.5), Vec3(1, 0.5, 0.5), Vec3(1, 1, 0), Vec3::Ones()};
  const sph::PointProbes<3> probes(points, l.body.position, l.body.volume, l.kernel, l.h);
  std::vector<Vec3> values;
  for (const auto& x : l.body.position) values.push_back(A * x + Vec3(1, 2, 3));
  for (std::size_t p = 0; p < points.size(); ++p)
    EXPECT_LT((probes.sample_value<Vec3>(p, values) - (A * points[p] + Vec3(1, 2, 3))).norm(), test::bound(1e-12, 1e-5));
}

TEST(PointProbes, WithGradientsTheFitIsExactOnQuadraticFields) {
  Lattice l;
  const std::vector<Vec3> points{Vec3::Constant(0.5), Vec3(1, 0.5, 0.5), Vec3::Ones()};
  const sph::PointProbes<3> probes(points, l.body.position, l.body.volume, l.kernel, l.h);
  std::vector<Vec3> values;
  std::vector<Mat3> gradients;
  for (const auto& x : l.body.position) values.push_back(quadratic(x)), gradients.push_back(quadratic_gradient(x));
  for (std::size_t p = 0; p < points.size(); ++p) {
    const double plain = (probes.sample_value<Vec3>(p, values) - quadratic(points[p])).norm();
    const double corrected =
        (probes.sample_with_gradient<Vec3, Mat3>(p, values, gradients) - quadratic(points[p])).norm();
    std::printf("probe %zu: linear fit error %.2e, with gradients %.2e\n", p, plain, corrected);
    EXPECT_GT(plain, 1e-4);  // the linear fit alone is biased by the curvature
    EXPECT_LT(corrected, test::bound(1e-12, 1e-5));
  }
}

TEST(PointProbes, UpdateFollowsParticlesInTheCurrentConfiguration) {
  Lattice l;
  const std::vector<Vec3> points{Vec3(0.4, 0.5, 0.6)};
  sph::PointProbes<3> probes(points, l.body.position, l.body.volume, l.kernel, l.h);
  for (auto& x : l.body.position) x = Real(0.8) * x + Vec3(0.05, 0, 0);  // the particles move past the point
  probes.update(l.body.position, l.body.volume);
  std::vector<Real> field;
  for (const auto& x : l.body.position) field.push_back(2 * x[0] - x[2]);
  EXPECT_NEAR(probes.sample(0, field), 2 * 0.4 - 0.6, test::bound(1e-12, 1e-5));
}

}  // namespace
