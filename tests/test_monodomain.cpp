// Monodomain stability on stiff and extreme cases: very anisotropic conduction at a fine spacing
// (step limit against the operator's spectrum, overshoot of a front), and an absurd stimulus.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "cardio/monodomain.hpp"
#include "geometry/lattice.hpp"
#include "libsph/core/numerical_failure.hpp"
#include "libsph/diffusion/diffusion_operator.hpp"
#include "libsph/diffusion/diffusion_system.hpp"

namespace {

using sph::Real;
using Vec2 = sph::Vec<2>;

/// D = 0.1 along 30 degrees and 0.01 across (ratio 10), in mm^2/ms.
sph::Mat<2> very_anisotropic() {
  const Real angle = Real(M_PI / 6);
  return sph::transversely_isotropic_tensor<2>(Real(0.1), Real(0.01), Vec2(std::cos(angle), std::sin(angle)));
}

TEST(MonodomainStability, AnisotropicStepLimitIsSafeAndNotWasteful) {
  // The computed limit 1 / max_i sum_j |a_ij| must not exceed the forward-Euler limit 2 / rho(L) of
  // the assembled operator (rho by power iteration) and should not be far below it.
  const Real dp = Real(0.02);  // 20 um: a fine cardiac spacing
  auto body = geometry::lattice_box<2>("tissue", Vec2(0, 0), Vec2(1, 1), dp);
  const auto relation = sph::build_inner_relation<2>(body.position, sph::WendlandC2<2>{}, Real(1.3) * dp);
  for (auto correction : {sph::DiffusionCorrection::moment, sph::DiffusionCorrection::none}) {
    const std::vector<sph::Mat<2>> D{very_anisotropic()};
    const auto a = sph::diffusion_pair_coefficients<2>(relation, body.volume, D, correction, {});
    const Real limit = sph::diffusion_time_step_limit<2>(relation, a);
    std::vector<Real> x(body.n_particles()), y(body.n_particles());
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(Real(12.9898) * i);  // a deterministic mixture
    double rho = 0;
    for (int it = 0; it < 300; ++it) {
      sph::apply_diffusion<2>(relation, a, x, y);
      double norm = 0, norm_x = 0;
      for (std::size_t i = 0; i < x.size(); ++i) {
        norm += double(y[i]) * y[i];
        norm_x += double(x[i]) * x[i];
      }
      rho = std::sqrt(norm / norm_x);
      for (std::size_t i = 0; i < x.size(); ++i) x[i] = static_cast<Real>(y[i] / std::sqrt(norm));
    }
    const double spectral_limit = 2 / rho;
    std::printf("correction %d: computed limit %.4g ms, 2/rho(L) = %.4g ms (ratio %.3f)\n", static_cast<int>(correction),
                double(limit), spectral_limit, double(limit) / spectral_limit);
    EXPECT_LE(limit, spectral_limit * 1.001);
    EXPECT_GE(limit, 0.3 * spectral_limit);
  }
}

TEST(MonodomainStability, AnisotropicFrontHasNoOvershootBeyondOnePercent) {
  // A -80 / +20 mV step across the diagonal diffuses (no reaction) at the full diffusion limit:
  // the values must stay within the initial range, up to 1 % of the jump.
  const Real dp = Real(0.02);
  auto body = geometry::lattice_box<2>("tissue", Vec2(0, 0), Vec2(1, 1), dp);
  const auto relation = sph::build_inner_relation<2>(body.position, sph::WendlandC2<2>{}, Real(1.3) * dp);
  sph::ScalarDiffusionSystem<2>::Settings settings;
  settings.field_name = "transmembrane_potential";
  settings.diffusion_tensor = {very_anisotropic()};
  settings.numerics.integrator = sph::DiffusionIntegrator::forward_euler;
  settings.numerics.cfl = 1;
  sph::ScalarDiffusionSystem<2> diffusion(body, relation, settings);
  auto V = body.field(diffusion.value_field());
  for (std::size_t i = 0; i < V.size(); ++i) V[i] = body.position[i][0] + body.position[i][1] < 1 ? -80 : 20;
  Real low = 0, high = 0;
  for (int step = 0; step < 2000; ++step) {
    diffusion.advance(step * diffusion.stable_time_step(), diffusion.stable_time_step());
    for (Real v : V) {
      low = std::min(low, v + 80);
      high = std::max(high, v - 20);
    }
  }
  std::printf("undershoot %.3g mV, overshoot %.3g mV over 2000 steps (jump 100 mV)\n", double(-low), double(high));
  EXPECT_GE(low, -1);
  EXPECT_LE(high, 1);
}

TEST(MonodomainStability, AbsurdStimulusIsBoundedOrFlaggedNeverNaN) {
  // 100 times the Niederer stimulus (3571 mV/ms for 2 ms) on a small tissue, each cell model with
  // the QSS schemes: the run either stays finite inside the model's valid range, or stops with a
  // NumericalFailure that names the potential and the range.
  const Real dp = Real(0.25);
  for (const auto& name : sph::cell_model_names) {
    for (auto scheme : {sph::ReactionScheme::rbr_qss, sph::ReactionScheme::rush_larsen}) {
      auto body = geometry::lattice_box<2>("tissue", Vec2(0, 0), Vec2(3, 3), dp);
      const auto relation = sph::build_inner_relation<2>(body.position, sph::WendlandC2<2>{}, Real(1.3) * dp);
      cardio::Monodomain<2>::Settings settings;
      settings.cell_model = sph::make_cell_model(name);
      settings.numerics.scheme = scheme;
      settings.numerics.time_step = Real(0.05);
      settings.diffusion_tensor = {Real(0.1) * sph::Mat<2>::Identity()};
      std::vector<std::size_t> corner;
      for (std::size_t i = 0; i < body.n_particles(); ++i)
        if ((body.position[i].array() < 1).all()) corner.push_back(i);
      settings.stimuli = {{"corner", corner, {0, 2, 100 * 35.714, 0, 1}}};
      cardio::Monodomain<2> monodomain(body, relation, settings);
      const auto range = std::visit([](const auto& m) { return m.valid_voltage(); }, settings.cell_model);
      std::string outcome;
      try {
        for (int step = 0; step < 100; ++step) monodomain.advance(step * Real(0.05), Real(0.05));
        const auto V = body.field(monodomain.potential_field());
        Real highest = -1e30;
        for (Real v : V) {
          ASSERT_TRUE(std::isfinite(v));
          EXPECT_GE(v, range.lower);
          EXPECT_LE(v, range.upper);
          highest = std::max(highest, v);
        }
        outcome = "bounded, highest V " + std::to_string(highest) + " mV after 5 ms";
      } catch (const sph::NumericalFailure& failure) {
        outcome = failure.what();
        EXPECT_NE(outcome.find("transmembrane_potential"), std::string::npos) << outcome;
        EXPECT_NE(outcome.find("valid range"), std::string::npos) << outcome;
      }
      std::printf("%s, %s: %s\n", std::string(name).c_str(), std::string(sph::to_string(scheme)).c_str(), outcome.c_str());
    }
  }
}

TEST(Monodomain, ActivationTimeOfAPlaneWaveGrowsWithDistance) {
  // A 1D-like strip stimulated at its left end: activation times increase along x, and the
  // conduction velocity of Aliev-Panfilov with D = 0.1 mm^2/ms is of the order of 0.1 mm/ms.
  const Real dp = Real(0.25);
  auto body = geometry::lattice_box<2>("strip", Vec2(0, 0), Vec2(20, 1), dp);
  const auto relation = sph::build_inner_relation<2>(body.position, sph::WendlandC2<2>{}, Real(1.3) * dp);
  cardio::Monodomain<2>::Settings settings;
  settings.cell_model = sph::AlievPanfilov{};
  settings.numerics.time_step = Real(0.1);
  settings.diffusion_tensor = {Real(0.1) * sph::Mat<2>::Identity()};
  settings.activation_threshold = -40;
  std::vector<std::size_t> left;
  for (std::size_t i = 0; i < body.n_particles(); ++i)
    if (body.position[i][0] < 1) left.push_back(i);
  settings.stimuli = {{"left end", left, {0, 2, 50, 0, 1}}};
  cardio::Monodomain<2> monodomain(body, relation, settings);
  for (int step = 0; step < 2500 && !monodomain.all_activated(); ++step) monodomain.advance(step * Real(0.1), Real(0.1));
  ASSERT_TRUE(monodomain.all_activated());
  const auto activation = body.field(monodomain.activation_field());
  auto time_at = [&](Real x) {
    double sum = 0;
    int n = 0;
    for (std::size_t i = 0; i < body.n_particles(); ++i)
      if (std::abs(body.position[i][0] - x) < dp / 2) {
        sum += activation[i];
        ++n;
      }
    return sum / n;
  };
  const double velocity = (15 - 5) / (time_at(15.125) - time_at(5.125));
  std::printf("conduction velocity %.4f mm/ms\n", velocity);
  EXPECT_LT(time_at(5.125), time_at(10.125));
  EXPECT_LT(time_at(10.125), time_at(15.125));
  // Analytic front speed of the cubic (Nagumo) term alone: sqrt(k D / 2)(1 - 2a) in model units,
  // here sqrt(8 * 0.1 * 12.9 / 2) (1 - 0.3) / 12.9 = 0.124 mm/ms; the recovery term slows it little.
  EXPECT_NEAR(velocity, 0.124, 0.124 * 0.15);
}

}  // namespace
