// The diffusion operator: exact on quadratic fields with the moment correction (2D and 3D,
// anisotropic D), conservative, stable at its computed time-step limit, and it rejects tensors
// that are not symmetric positive definite.
#include <gtest/gtest.h>

#include <cstdio>

#include "geometry/lattice.hpp"
#include "libsph/core/neighbour_relation.hpp"
#include "libsph/core/numerical_failure.hpp"
#include "libsph/diffusion/diffusion_operator.hpp"
#include "libsph/diffusion/diffusion_system.hpp"
#include "tests/precision.hpp"

namespace {

using sph::Real;

template <int Dim>
sph::Mat<Dim> anisotropic_tensor() {
  sph::Vec<Dim> f = sph::Vec<Dim>::Ones().normalized();
  f[0] *= 2;
  return sph::transversely_isotropic_tensor<Dim>(10, 1, f.normalized());
}

// Applies the operator to C = 1/2 x^T Q x + g . x + c on a jittered lattice (not needed: a plain
// lattice already has a non-isotropic fourth moment) and compares with D : Q away from the walls.
template <int Dim>
Real quadratic_error(sph::DiffusionCorrection correction) {
  const int n = Dim == 2 ? 30 : 16;
  const Real dp = 1.0 / n;
  auto body = geometry::lattice_box<Dim>("box", sph::Vec<Dim>::Zero(), sph::Vec<Dim>::Ones(), dp);
  const auto relation = sph::build_inner_relation<Dim>(body.position, sph::WendlandC2<Dim>{}, 1.3 * dp);
  const sph::Mat<Dim> D = anisotropic_tensor<Dim>();
  sph::Mat<Dim> Q = sph::Mat<Dim>::Identity();
  Q(0, 1) = Q(1, 0) = 0.7;
  Q(Dim - 1, Dim - 1) = -2.5;
  const sph::Vec<Dim> g = sph::Vec<Dim>::LinSpaced(0.3, 1.1);
  std::vector<Real> C(body.n_particles()), rate(body.n_particles());
  for (std::size_t i = 0; i < C.size(); ++i) {
    const auto& x = body.position[i];
    C[i] = 0.5 * x.dot(Q * x) + g.dot(x) + 2;
  }
  std::vector<sph::Mat<Dim>> B;
  const std::vector<sph::Mat<Dim>> tensors{D};
  const auto a = sph::diffusion_pair_coefficients<Dim>(relation, body.volume, tensors, correction, B);
  sph::apply_diffusion<Dim>(relation, a, C, rate);
  const Real expected = (D.cwiseProduct(Q)).sum();
  Real worst = 0;
  for (std::size_t i = 0; i < C.size(); ++i) {
    const auto& x = body.position[i];
    // Only where i and all of its neighbours have full support (2 x 2.6 dp from the walls).
    if ((x.array() < 5.5 * dp).any() || (x.array() > 1 - 5.5 * dp).any()) continue;
    worst = std::max(worst, std::abs(rate[i] - expected) / std::abs(expected));
  }
  return worst;
}

TEST(DiffusionOperator, MomentCorrectionIsExactOnQuadratics2D) {
  const Real moment = quadratic_error<2>(sph::DiffusionCorrection::moment);
  const Real none = quadratic_error<2>(sph::DiffusionCorrection::none);
  std::printf("2D relative error of div(D grad C) on a quadratic: moment %.2e (bound %.0e), none %.2e\n", moment,
              test::bound(1e-9, 5e-3), none);
  EXPECT_LT(moment, test::bound(1e-9, 5e-3));
  EXPECT_GT(none, 1e-3);  // the uncorrected weighting feels the lattice's anisotropic fourth moment
}

TEST(DiffusionOperator, MomentCorrectionIsExactOnQuadratics3D) {
  const Real moment = quadratic_error<3>(sph::DiffusionCorrection::moment);
  std::printf("3D relative error of div(D grad C) on a quadratic: moment %.2e (bound %.0e)\n", moment, test::bound(1e-9, 5e-3));
  EXPECT_LT(moment, test::bound(1e-9, 5e-3));
}

TEST(DiffusionOperator, ConservesTheTotalAndIsStableAtItsLimit) {
  const Real dp = 1.0 / 40;
  auto body = geometry::lattice_box<2>("box", sph::Vec<2>::Zero(), sph::Vec<2>::Ones(), dp);
  const auto relation = sph::build_inner_relation<2>(body.position, sph::WendlandC2<2>{}, 1.3 * dp);
  for (auto correction : {sph::DiffusionCorrection::none, sph::DiffusionCorrection::gradient, sph::DiffusionCorrection::moment}) {
    auto particles = geometry::lattice_box<2>("box", sph::Vec<2>::Zero(), sph::Vec<2>::Ones(), dp);
    sph::ScalarDiffusionSystem<2>::Settings settings;
    settings.diffusion_tensor = {anisotropic_tensor<2>()};
    settings.numerics.correction = correction;
    settings.numerics.integrator = sph::DiffusionIntegrator::forward_euler;
    settings.numerics.cfl = 1.0;  // exactly at the computed limit
    sph::ScalarDiffusionSystem<2> diffusion(particles, relation, settings);
    auto C = particles.field(diffusion.value_field());
    // A checkerboard excites the highest-frequency mode, the first to blow up beyond the limit.
    for (std::size_t i = 0; i < C.size(); ++i) C[i] = ((i + i / 40) % 2) ? 1.0 : 0.0;
    Real total0 = 0, total1 = 0, peak = 0;
    for (std::size_t i = 0; i < C.size(); ++i) total0 += C[i] * particles.volume[i];
    for (int step = 0; step < 400; ++step) diffusion.advance(step, diffusion.stable_time_step());
    for (std::size_t i = 0; i < C.size(); ++i) {
      total1 += C[i] * particles.volume[i];
      peak = std::max(peak, std::abs(C[i]));
    }
    EXPECT_NEAR(total1, total0, test::bound(1e-12, 1e-5)) << "correction " << static_cast<int>(correction);
    EXPECT_LT(peak, 1.5) << "correction " << static_cast<int>(correction);
  }
}

TEST(DiffusionOperator, BlowUpIsDetectedAndNamed) {
  const Real dp = 1.0 / 20;
  auto body = geometry::lattice_box<2>("slab", sph::Vec<2>::Zero(), sph::Vec<2>::Ones(), dp);
  const auto relation = sph::build_inner_relation<2>(body.position, sph::WendlandC2<2>{}, 1.3 * dp);
  sph::ScalarDiffusionSystem<2>::Settings settings;
  settings.diffusion_tensor = {sph::Mat<2>::Identity()};
  settings.numerics.integrator = sph::DiffusionIntegrator::forward_euler;
  sph::ScalarDiffusionSystem<2> diffusion(body, relation, settings);
  auto C = body.field(diffusion.value_field());
  for (std::size_t i = 0; i < C.size(); ++i) C[i] = (i % 2) ? 1.0 : 0.0;
  // Ten times the stable step: the checkerboard grows until it overflows to infinity.
  try {
    for (int step = 0; step < 2000; ++step) diffusion.advance(step, 10 * diffusion.stable_time_step());
    FAIL() << "the blow-up was not detected";
  } catch (const sph::NumericalFailure& failure) {
    const std::string message = failure.what();
    EXPECT_NE(message.find("body 'slab'"), std::string::npos) << message;
    EXPECT_NE(message.find("concentration is not finite"), std::string::npos) << message;
  }
}

TEST(DiffusionTensor, RejectsTensorsThatAreNotPositiveDefinite) {
  EXPECT_NO_THROW(sph::check_diffusion_tensor<2>(anisotropic_tensor<2>(), "test"));
  EXPECT_THROW(sph::check_diffusion_tensor<2>(sph::transversely_isotropic_tensor<2>(1, 0, sph::Vec<2>(1, 0)), "t"),
               std::invalid_argument);
  sph::Mat<3> indefinite = sph::Mat<3>::Identity();
  indefinite(2, 2) = -0.1;
  EXPECT_THROW(sph::check_diffusion_tensor<3>(indefinite, "t"), std::invalid_argument);
  sph::Mat<2> unsymmetric = sph::Mat<2>::Identity();
  unsymmetric(0, 1) = 0.5;
  EXPECT_THROW(sph::check_diffusion_tensor<2>(unsymmetric, "t"), std::invalid_argument);
}

}  // namespace
