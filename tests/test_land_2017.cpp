// The Land et al. 2017 contraction model (cardio/land_2017.hpp): its analytic steady states, the
// twitch driven by the ten Tusscher-Panfilov 2006 calcium transient against a CVODE reference, the
// force-velocity sign and the step's stability at long steps.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "cardio/land_2017.hpp"
#include "libsph/reaction/cell_integrators.hpp"
#include "libsph/reaction/stimulus.hpp"
#include "libsph/reaction/ten_tusscher_panfilov_2006.hpp"
#if CARDIOSPH_HAVE_CVODE
#include "libsph/reaction/cvode_integrator.hpp"
#endif

namespace {

using cardio::Land2017;

/// The closed-form steady state at a fixed CaTRPN = c (no motion, zeta = 0): with the unbound
/// fraction XU, XW = XU k_uw / (k_wu + k_ws) = XU r_w / (1 - r_w), XS = XW k_ws / k_su and
/// B = XU (k_b / k_u) c^-n_TM, normalised so that B + XU + XW + XS = 1; T = h T_ref / r_s XS.
double analytic_steady_tension(const Land2017::Parameters& p, double c, double lambda) {
  const double k_wu = p.k_uw * (1 / p.r_w - 1) - p.k_ws, k_su = p.k_ws * p.r_w * (1 / p.r_s - 1);
  const double k_b = p.k_u * std::pow(p.TRPN50, p.n_TM) / (1 - p.r_s - (1 - p.r_s) * p.r_w);
  const double w = p.k_uw / (k_wu + p.k_ws), s = w * p.k_ws / k_su;
  const double b = k_b / p.k_u * std::min(100.0, std::pow(c, -p.n_TM / 2)) / std::pow(c, p.n_TM / 2);
  const double XU = 1 / (1 + b + w + s);
  return Land2017(p).overlap(lambda) * p.T_ref / p.r_s * s * XU;
}

TEST(Land2017, SteadyStatesMatchTheClosedForm) {
  const Land2017 model;
  const auto& p = model.parameters();
  for (double lambda : {0.9, 1.0, 1.1}) {
    const double Ca50 = p.Ca50_ref + p.beta_1 * (std::min(lambda, 1.2) - 1);
    for (double calcium : {0.3, 0.6, 1.0, 3.0, 30.0}) {
      const auto y = model.steady_state(calcium, lambda);
      const double r = std::pow(calcium / Ca50, p.n_TRPN), c = r / (1 + r);
      EXPECT_NEAR(y[Land2017::CaTRPN], c, 1e-9);
      const double expected = analytic_steady_tension(p, c, lambda);
      EXPECT_NEAR(model.tension(y, lambda), expected, 1e-8 * p.T_ref) << "Ca " << calcium << " uM, lambda " << lambda;
    }
  }
  // The design points of the model: half of T_ref where CaTRPN = TRPN50, and T_ref (less the few
  // per cent of blocked tropomyosin) at saturating calcium, both at lambda = 1.
  const double half = p.Ca50_ref * std::pow(p.TRPN50 / (1 - p.TRPN50), 1 / p.n_TRPN);
  const double T_half = model.tension(model.steady_state(half), 1), T_max = model.tension(model.steady_state(1e4), 1);
  std::printf("[ Land2017 ] steady tension at Ca = %.4f uM (CaTRPN = TRPN50): %.4f kPa; at saturation %.3f kPa (T_ref %.0f)\n",
              half, T_half, T_max, p.T_ref);
  EXPECT_NEAR(T_half, p.T_ref / 2, 1e-6 * p.T_ref);
  EXPECT_GT(T_max, 0.98 * p.T_ref);
  EXPECT_LE(T_max, p.T_ref);
}

TEST(Land2017, ShorteningLowersAndLengtheningRaisesTheTension) {
  // 5 ms of shortening or lengthening at 0.1 %/ms from full isometric activation, against the same
  // stretch history with the velocity terms left out (dlambda/dt = 0 passed): the difference is
  // the model's force-velocity relation alone.
  const Land2017 model;
  const auto rest = model.steady_state(2.0);
  double tension[2][2];
  for (int k = 0; k < 2; ++k)
    for (int moving = 0; moving < 2; ++moving) {
      auto y = rest;
      const double rate = k == 0 ? -1e-3 : 1e-3;
      double lambda = 1;
      for (int n = 0; n < 50; ++n) {
        lambda += rate * 0.1;
        model.step(y, 2.0, lambda, moving ? rate : 0.0, 0.1);
      }
      tension[k][moving] = model.tension(y, lambda);
    }
  std::printf("[ Land2017 ] 5 ms at -0.1 %%/ms: %.3f kPa (%.3f without velocity); at +0.1 %%/ms: %.3f (%.3f)\n",
              tension[0][1], tension[0][0], tension[1][1], tension[1][0]);
  EXPECT_LT(tension[0][1], 0.95 * tension[0][0]);
  EXPECT_GT(tension[1][1], 1.05 * tension[1][0]);
}

// The stiffness the solid applies within a coupling step (ActiveTension, velocity dependence) is
// the model's own response to a sudden stretch: a step of dlambda over a vanishing time changes
// T_a by k dlambda (plus the overlap factor's slope beta_0 T_a / h dlambda, left out of k; compared
// at lambda = 0.95, below the overlap's kink, with it added back).
TEST(Land2017, StretchStiffnessIsTheResponseToASuddenStretch) {
  const Land2017 model;
  for (double calcium : {0.5, 1.0, 3.0}) {
    auto y = model.steady_state(calcium, 0.95);
    const double T0 = model.tension(y, 0.95), k = model.stretch_stiffness(y, 0.95);
    const double d = 1e-6, dt = 1e-9;
    model.step(y, calcium, 0.95 + d, d / dt, dt);
    const double measured = (model.tension(y, 0.95 + d) - T0) / d;
    const double overlap_slope = model.parameters().beta_0 * T0 / model.overlap(0.95);  // dh/dlambda = beta_0 here
    std::printf("[ Land2017 ] Ca %.1f uM: k = %.1f kPa, sudden-stretch response %.1f kPa (overlap part %.1f)\n", calcium, k,
                measured, overlap_slope);
    EXPECT_NEAR(measured, k + overlap_slope, 1e-3 * k);
  }
}

TEST(Land2017, LongStepsStayBoundedAndFinite) {
  const Land2017 model;
  auto y = model.steady_state(0.1);
  for (double dt : {5.0, 50.0})
    for (double calcium : {5.0, 0.05, 100.0, 0.0}) {
      model.step(y, calcium, 0.95, -0.01, dt);
      for (std::size_t k = 0; k < Land2017::n_states; ++k) ASSERT_TRUE(std::isfinite(y[k])) << "state " << k;
      for (std::size_t k : {Land2017::CaTRPN, Land2017::B, Land2017::XW, Land2017::XS}) {
        EXPECT_GE(y[k], 0);
        EXPECT_LE(y[k], 1);
      }
      EXPECT_LE(y[Land2017::B] + y[Land2017::XW] + y[Land2017::XS], 1 + 1e-12);
    }
}

TEST(Land2017, BadParametersAreRefusedByName) {
  Land2017::Parameters p;
  p.r_s = 1.5;
  EXPECT_THROW(Land2017{p}, std::invalid_argument);
  p = {};
  p.T_ref = -1;
  try {
    Land2017 model(p);
    FAIL() << "accepted T_ref < 0";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("T_ref"), std::string::npos) << e.what();
  }
}

/// Peak, time to peak and the times from the peak to 50 % and 90 % relaxation of a twitch T(t).
struct Twitch {
  double peak = 0, time_to_peak = 0, rt50 = -1, rt90 = -1;
};
Twitch measure_twitch(const std::vector<double>& t, const std::vector<double>& T) {
  Twitch w;
  const double rest = T.front();
  std::size_t ip = 0;
  for (std::size_t i = 0; i < T.size(); ++i)
    if (T[i] > T[ip]) ip = i;
  w.peak = T[ip];
  w.time_to_peak = t[ip];
  for (auto [level, out] : {std::pair{0.5, &w.rt50}, std::pair{0.1, &w.rt90}}) {
    const double target = rest + level * (w.peak - rest);
    for (std::size_t i = ip; i + 1 < T.size(); ++i)
      if (T[i] >= target && T[i + 1] < target) {
        *out = t[i] + (T[i] - target) / (T[i] - T[i + 1]) * (t[i + 1] - t[i]) - t[ip];
        break;
      }
  }
  return w;
}

#if CARDIOSPH_HAVE_CVODE
// The isometric twitch (lambda = 1) of the ten Tusscher-Panfilov 2006 epicardial cell's calcium
// transient through the Land model, as the heart steps it (the cell's rbr_qss step and the Land
// step with the mean calcium of each step, dt = 0.1 ms, the heart's default EP step) against
// CVODE on the coupled 25-state system at rtol 1e-8.
TEST(Land2017, TwitchOfTheTenTusscherPanfilovCalciumMatchesCvode) {
  using Cell = sph::TenTusscherPanfilov2006;
  using SI = Cell::StateIndex;
  const Cell cell;
  const Land2017 land;
  const sph::StimulusProtocol stimulus{0, 1, 52, 0, 1};
  const double end = 800, dt = 0.1, sample = 0.1;
  const double rest_calcium = 1000 * cell.initial_state()[SI::Ca_i];

  // Ours.
  std::vector<double> t_ours, T_ours;
  {
    auto y = cell.initial_state();
    auto z = land.steady_state(rest_calcium);
    t_ours.push_back(0), T_ours.push_back(land.tension(z, 1));
    const long steps = std::lround(end / dt);
    for (long n = 0; n < steps; ++n) {
      const double t = n * dt, before = y[SI::Ca_i];
      sph::advance_cell(cell, y, stimulus.average(t, dt), dt, sph::ReactionScheme::rbr_qss);
      land.step(z, 1000 * 0.5 * (before + y[SI::Ca_i]), 1, 0, dt);
      t_ours.push_back(t + dt), T_ours.push_back(land.tension(z, 1));
    }
  }
  // CVODE on the coupled system.
  std::vector<double> t_ref, T_ref;
  {
    constexpr std::size_t nc = Cell::n_states, n = nc + Land2017::n_states;
    double current_stimulus = 0;
    sph::CvodeIntegrator cvode(
        n,
        [&](double, std::span<const double> y, std::span<double> dydt) {
          Cell::State c;
          Land2017::State z;
          std::copy(y.begin(), y.begin() + nc, c.begin());
          std::copy(y.begin() + nc, y.end(), z.begin());
          const auto fc = cell.rates(c, current_stimulus);
          const auto fz = land.rates(z, 1000 * c[SI::Ca_i], 1, 0);
          std::copy(fc.begin(), fc.end(), dydt.begin());
          std::copy(fz.begin(), fz.end(), dydt.begin() + nc);
        },
        {1e-8, 1e-11, 0.5});
    std::vector<double> y(n);
    const auto c0 = cell.initial_state();
    const auto z0 = land.steady_state(rest_calcium);
    std::copy(c0.begin(), c0.end(), y.begin());
    std::copy(z0.begin(), z0.end(), y.begin() + nc);
    auto tension_of = [&] {
      Land2017::State z;
      std::copy(y.begin() + nc, y.end(), z.begin());
      return land.tension(z, 1);
    };
    double t = 0;
    current_stimulus = stimulus.average(0, 0);
    cvode.reset(0, y);
    t_ref.push_back(0), T_ref.push_back(tension_of());
    const long samples = std::lround(end / sample);
    for (long i = 1; i <= samples; ++i) {
      const double t_out = i * sample;
      for (double edge : stimulus.switching_times(t, t_out)) {
        cvode.advance_to(edge, y);
        t = edge;
        current_stimulus = stimulus.average(t, 0);
        cvode.reset(t, y);
      }
      if (t < t_out) cvode.advance_to(t_out, y);
      t = t_out;
      t_ref.push_back(t), T_ref.push_back(tension_of());
    }
  }
  const Twitch ours = measure_twitch(t_ours, T_ours), ref = measure_twitch(t_ref, T_ref);
  std::printf("[ Land2017 ] TP06 twitch, ours (dt %.2f ms): peak %.3f kPa at %.1f ms, RT50 %.1f ms, RT90 %.1f ms, rest %.4f kPa\n",
              dt, ours.peak, ours.time_to_peak, ours.rt50, ours.rt90, T_ours.front());
  std::printf("[ Land2017 ] TP06 twitch, CVODE:            peak %.3f kPa at %.1f ms, RT50 %.1f ms, RT90 %.1f ms\n", ref.peak,
              ref.time_to_peak, ref.rt50, ref.rt90);
  ASSERT_GT(ref.rt90, 0) << "the reference twitch does not relax within 800 ms";
  // Bounds: 1 % of the peak, 1 ms on the times (ten steps).
  EXPECT_NEAR(ours.peak, ref.peak, 0.01 * ref.peak);
  EXPECT_NEAR(ours.time_to_peak, ref.time_to_peak, 1.0);
  EXPECT_NEAR(ours.rt50, ref.rt50, 1.0);
  EXPECT_NEAR(ours.rt90, ref.rt90, 1.0);
  // Back to rest after the beat.
  EXPECT_LT(T_ours.back() - T_ours.front(), 0.02 * ours.peak);
}
#endif

}  // namespace
