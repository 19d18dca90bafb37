// Cell models (production/loss form), the QSS update, the cell schemes and the CVODE reference.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "libsph/reaction/aliev_panfilov.hpp"
#include "libsph/reaction/cell_integrators.hpp"
#include "libsph/reaction/cell_simulation.hpp"
#include "libsph/reaction/fitzhugh_nagumo.hpp"
#include "libsph/reaction/reaction_system.hpp"
#include "libsph/reaction/stimulus.hpp"
#include "libsph/reaction/ten_tusscher_panfilov_2006.hpp"
#if CARDIOSPH_HAVE_CVODE
#include "libsph/reaction/cvode_integrator.hpp"
#endif

namespace {

using sph::AlievPanfilov;
using sph::FitzHughNagumo;
using sph::ReactionScheme;

static_assert(sph::ReactionModel<AlievPanfilov>);
static_assert(sph::ReactionModel<FitzHughNagumo>);

/// States along a paced action potential (forward Euler with a small step), for the form checks.
template <class M>
std::vector<typename M::State> states_along_action_potential(const M& model) {
  std::vector<typename M::State> states;
  const sph::StimulusProtocol stimulus{0, 1, 52, 0, 1};
  long step = 0;
  sph::simulate_cell(model, ReactionScheme::forward_euler, 0.01, stimulus, 400, [&](double, const auto& y) {
    if (step++ % 500 == 0) states.push_back(y);
  });
  return states;
}

template <class M>
void expect_production_loss_matches_rates(const M& model) {
  const auto states = states_along_action_potential(model);
  ASSERT_GT(states.size(), 50u);
  for (const auto& y : states)
    for (double stimulus : {0.0, 30.0}) {
      const auto f = model.rates(y, stimulus);
      for (std::size_t k = 0; k < M::n_states; ++k) {
        const auto r = model.production_loss(k, y, stimulus);
        EXPECT_GE(r.loss, 0) << "variable " << k;
        EXPECT_NEAR(r.production - r.loss * y[k], f[k], 1e-10 * (1 + std::abs(f[k]) + std::abs(r.loss * y[k])))
            << "variable " << k;
      }
    }
}

TEST(CellModels, ProductionLossFormEqualsTheRates) {
  expect_production_loss_matches_rates(AlievPanfilov{});
  expect_production_loss_matches_rates(AlievPanfilov::nash_panfilov_2004());
  expect_production_loss_matches_rates(FitzHughNagumo{});
}

// ten Tusscher-Panfilov with its functions of V in lookup tables of 0.05 mV (linear interpolation,
// error about step^2 / 8 |f''|, at most 0.3485^2 of f for the steepest exponential, exp(0.3485 V)
// of the h gate: 4e-5): every production and loss along an action potential within that 4e-5 of
// the exact ones (relative, of their size along the beat; measured 1.2e-5), and one paced beat by
// rbr_qss at 0.01 ms within 5e-6 ms of the exact model's APD90 (measured 1.6e-6) and 3e-5 mV RMS
// (measured 1.1e-5): about 3x the measures.
TEST(CellModels, TenTusscherLookupTablesFollowTheExactFunctions) {
  const sph::TenTusscherPanfilov2006 exact;
  const auto tabulated = exact.with_voltage_table(0.05);
  EXPECT_EQ(tabulated.voltage_table_step(), 0.05);
  EXPECT_THROW((void)exact.with_voltage_table(-1), std::invalid_argument);
  double worst = 0;
  for (const auto& y : states_along_action_potential(exact))
    for (std::size_t k = 0; k < sph::TenTusscherPanfilov2006::n_states; ++k) {
      const auto a = exact.production_loss(k, y, 0), b = tabulated.production_loss(k, y, 0);
      const double scale = std::abs(a.production) + std::abs(a.loss * y[k]) + 1e-12;
      worst = std::max(worst, std::abs((a.production - a.loss * y[k]) - (b.production - b.loss * y[k])) / scale);
      worst = std::max(worst, std::abs(a.loss - b.loss) / (std::abs(a.loss) + 1e-12));
    }
  const sph::StimulusProtocol stimulus{0, 1, 52, 0, 1};
  std::vector<double> t, V_exact, V_table;
  sph::simulate_cell(exact, ReactionScheme::rbr_qss, 0.01, stimulus, 500, [&](double s, const auto& y) {
    t.push_back(s);
    V_exact.push_back(y[0]);
  });
  sph::simulate_cell(tabulated, ReactionScheme::rbr_qss, 0.01, stimulus, 500, [&](double, const auto& y) { V_table.push_back(y[0]); });
  ASSERT_EQ(V_exact.size(), V_table.size());
  double sum = 0;
  for (std::size_t i = 0; i < t.size(); ++i) sum += std::pow(V_exact[i] - V_table[i], 2);
  const double rms = std::sqrt(sum / double(t.size()));
  const double apd_exact = sph::measure_action_potential(t, V_exact, 0, 500).duration();
  const double apd_table = sph::measure_action_potential(t, V_table, 0, 500).duration();
  std::printf("lookup tables (0.05 mV): largest relative difference of a rate %.2e (bound 4e-5); one beat: APD90 %.6f "
              "against %.6f ms, difference %.2e (bound 5e-6 ms), RMS V difference %.2e mV (bound 3e-5 mV)\n",
              worst, apd_table, apd_exact, std::abs(apd_table - apd_exact), rms);
  EXPECT_LT(worst, 4e-5);
  EXPECT_LT(std::abs(apd_table - apd_exact), 5e-6);
  EXPECT_LT(rms, 3e-5);
}

TEST(CellModels, RestingStatesAreSteady) {
  for (const auto& y : {AlievPanfilov{}.rates(AlievPanfilov{}.initial_state(), 0)}) {
    EXPECT_EQ(y[0], 0);
    EXPECT_EQ(y[1], 0);
  }
  const FitzHughNagumo fhn;
  const auto f = fhn.rates(fhn.initial_state(), 0);
  EXPECT_NEAR(f[0], 0, 1e-12);
  EXPECT_NEAR(f[1], 0, 1e-12);
  EXPECT_NEAR(fhn.initial_state()[0], 30 * -1.19941 - 45, 1e-3);  // v = -1.19941 (FitzHugh 1961)
}

TEST(CellModels, DimensionlessScalingMapsTheAlievPanfilovUpstroke) {
  // u = 1 is V = 20 mV; a stimulus of 1 mV/ms is du/dtau = 0.129.
  const AlievPanfilov ap;
  EXPECT_DOUBLE_EQ(ap.parameters().scaling.to_V(1), 20);
  EXPECT_DOUBLE_EQ(ap.parameters().scaling.stimulus_to_u(1), 0.129);
  // In the physical form, dV/dt = 100 / 12.9 du/dtau.
  const AlievPanfilov::State y{-30, 0.1};
  const double u = 0.5, v = 0.1;
  const double du = -8 * u * (u - 0.15) * (u - 1) - u * v;
  EXPECT_NEAR(ap.rates(y, 0)[0], 100 / 12.9 * du, 1e-12);
}

TEST(QssUpdate, IsExactForALinearEquation) {
  // dy/dt = q - p y: y(t) = q/p + (y0 - q/p) exp(-p t), at any step size.
  const sph::ProductionLoss r{3, 2};
  for (double dt : {1e-12, 1e-3, 0.5, 10.0, 1e3}) {
    const double exact = 1.5 + (4 - 1.5) * std::exp(-2 * dt);
    EXPECT_NEAR(sph::qss_update(4, r, dt), exact, 1e-14 * 4) << "dt " << dt;
  }
  // No loss: y + q dt.
  EXPECT_DOUBLE_EQ(sph::qss_update(1, {2, 0}, 0.25), 1.5);
}

TEST(Stimulus, AverageDeliversTheExactCharge) {
  const sph::StimulusProtocol s{1, 2, 10, 5, 3};  // pulses on [1,3), [6,8), [11,13)
  double charge = 0;
  for (double dt : {0.3, 0.7, 1.9}) {
    charge = 0;
    for (double t = 0; t < 20; t += dt) charge += s.average(t, dt) * dt;
    EXPECT_NEAR(charge, 60, 1e-9) << "dt " << dt;
  }
  EXPECT_EQ(s.average(2, 0), 10);
  EXPECT_EQ(s.average(3, 0), 0);
  EXPECT_EQ(s.switching_times(0, 6), (std::vector<double>{1, 3, 6}));  // (t0, t1]
  EXPECT_EQ(s.switching_times(1, 3), (std::vector<double>{3}));
}

/// A linear model with decay rates 1 and 100: its forward-Euler limit is 2 / 100.
struct TwoRates {
  static constexpr std::size_t n_states = 2;
  using State = std::array<double, 2>;
  static constexpr std::array<std::string_view, 2> state_names{"transmembrane_potential", "fast"};
  State initial_state() const { return {1, 1}; }
  sph::ProductionLoss production_loss(std::size_t k, const State&, double s) const {
    return k == 0 ? sph::ProductionLoss{s, 1} : sph::ProductionLoss{0, 100};
  }
  State rates(const State& y, double s) const { return {s - y[0], -100 * y[1]}; }
  sph::VoltageRange valid_voltage() const { return {-10, 10}; }
};
static_assert(sph::ReactionModel<TwoRates>);

TEST(CellSchemes, ExplicitEulerLimitOfALinearSystem) {
  EXPECT_NEAR(sph::explicit_euler_step_limit(TwoRates{}, TwoRates{}.initial_state()), 0.02, 1e-8);
}

TEST(CellSchemes, QssSchemesAreExactOnDecoupledLinearEquationsAndEulerIsNot) {
  for (auto scheme : {ReactionScheme::rush_larsen, ReactionScheme::rbr_qss}) {
    auto y = TwoRates{}.initial_state();
    sph::advance_cell(TwoRates{}, y, 0, 0.5, scheme);
    EXPECT_NEAR(y[0], std::exp(-0.5), 1e-14);
    EXPECT_NEAR(y[1], std::exp(-50.0), 1e-13 * std::exp(-50.0));
  }
  auto y = TwoRates{}.initial_state();
  sph::advance_cell(TwoRates{}, y, 0, 0.5, ReactionScheme::forward_euler);
  EXPECT_DOUBLE_EQ(y[1], -49);  // 1 - 100 * 0.5: the explicit step is far outside its limit
}

TEST(CellSchemes, ActionPotentialMeasuresOfATrapezoid) {
  // Rest -80 until t = 1, up to 20 at t = 2, down to -80 at t = 12: the 90 % level is -70,
  // crossed at t = 1.1 and t = 11.
  const std::vector<double> t{0, 1, 2, 12, 20}, V{-80, -80, 20, -80, -80};
  const auto ap = sph::measure_action_potential(t, V, 0, 21);
  EXPECT_DOUBLE_EQ(ap.peak, 20);
  EXPECT_NEAR(ap.upstroke, 1.1, 1e-12);
  EXPECT_NEAR(ap.repolarised, 11, 1e-12);
  EXPECT_NEAR(ap.duration(), 9.9, 1e-12);
}

// The rbr_qss step in lanes of eight (lanes.hpp) follows the scalar sweeps for the dimensionless
// models: eight cells paced at different times and strengths through an action potential. The
// arithmetic is the same; only exp and expm1 round differently (a few ulp), so the bound on V is
// 1e-9 mV after 400 ms.
template <class Model>
void expect_lanes_follow_the_scalar_sweeps(const Model& model, double amplitude) {
  static_assert(sph::HasLanesRbrQssStep<Model>);
  std::array<typename Model::State, sph::lane_count> scalar;
  scalar.fill(model.initial_state());
  std::array<sph::Lanes, Model::n_states> lanes;
  for (std::size_t k = 0; k < Model::n_states; ++k) lanes[k] = sph::Lanes::Constant(model.initial_state()[k]);
  constexpr double dt = 0.05;
  double worst = 0, peak = -1e300;
  for (int n = 0; n < 8000; ++n) {
    sph::Lanes stimulus = sph::Lanes::Zero();
    for (int l = 0; l < sph::lane_count; ++l)
      if (n * dt >= 3.0 * l && n * dt < 3.0 * l + 1) stimulus[l] = amplitude * (0.8 + 0.1 * l);
    sph::rbr_qss_step_in_lanes(model, lanes, stimulus, dt);
    for (int l = 0; l < sph::lane_count; ++l) {
      sph::advance_cell(model, scalar[l], stimulus[l], dt, sph::ReactionScheme::rbr_qss);
      worst = std::max(worst, std::abs(lanes[0][l] - scalar[l][0]));
      peak = std::max(peak, scalar[l][0]);
    }
  }
  std::printf("lanes against scalar sweeps: max |V_lane - V_scalar| = %.2e mV over 400 ms (peak V %.1f mV)\n", worst, peak);
  EXPECT_LE(worst, 1e-9);
  EXPECT_GT(peak, 0.0);  // the cells fired
}

TEST(CellSchemes, LanesFollowTheScalarSweeps) {
  expect_lanes_follow_the_scalar_sweeps(sph::AlievPanfilov::nash_panfilov_2004(), 50.0);
  expect_lanes_follow_the_scalar_sweeps(sph::FitzHughNagumo{}, 50.0);
}

TEST(ReactionSystem, FlagsAPotentialOutsideTheValidRange) {
  sph::ParticleSet<2> particles("tissue", {sph::Vec<2>(0, 0), sph::Vec<2>(1, 0)}, {1, 1});
  // An explicit step under an absurd stimulus (the QSS schemes bound V by themselves).
  sph::ReactionSystem<2, AlievPanfilov> cells(particles, AlievPanfilov{}, {ReactionScheme::forward_euler, false});
  const std::vector<sph::Real> stimulus{0, 1e5};
  try {
    cells.advance(0, 1, stimulus);
    FAIL() << "a potential of thousands of mV went unnoticed";
  } catch (const sph::NumericalFailure& failure) {
    const std::string message = failure.what();
    EXPECT_NE(message.find("particle 1"), std::string::npos) << message;
    EXPECT_NE(message.find("transmembrane_potential"), std::string::npos) << message;
    EXPECT_NE(message.find("valid range"), std::string::npos) << message;
  }
}

#if CARDIOSPH_HAVE_CVODE
TEST(Cvode, SolvesAStiffLinearSystemToItsTolerance) {
  sph::CvodeIntegrator cvode(
      2,
      [](double, std::span<const double> y, std::span<double> f) {
        f[0] = -y[0];
        f[1] = -1e4 * (y[1] - std::cos(0.0));
      },
      {1e-10, 1e-12, 0, 100000});
  std::vector<double> y{1, 0};
  cvode.reset(0, y);
  cvode.advance_to(2, y);
  EXPECT_NEAR(y[0], std::exp(-2.0), 1e-8);
  EXPECT_NEAR(y[1], 1, 1e-8);
  EXPECT_GT(cvode.steps(), 0);
}

TEST(Cvode, AlievPanfilovSchemesConvergeToTheReference) {
  // One paced action potential: the RMS voltage difference to CVODE falls with the step for both
  // QSS schemes, and APD90 at dt = 0.01 ms is within 0.5 % of the reference.
  const AlievPanfilov model;
  const sph::StimulusProtocol stimulus{0, 1, 52, 0, 1};
  std::vector<double> t_ref, V_ref;
  sph::solve_cell_with_cvode(model, stimulus, 600, 0.5, [&](double t, const auto& y) {
    t_ref.push_back(t);
    V_ref.push_back(y[0]);
  });
  const double apd_ref = sph::measure_action_potential(t_ref, V_ref, 0, 600).duration();
  ASSERT_GT(apd_ref, 100);
  for (auto scheme : {ReactionScheme::rush_larsen, ReactionScheme::rbr_qss}) {
    double previous_rms = 1e300;
    for (double dt : {0.4, 0.1, 0.01}) {
      std::vector<double> t, V;
      ASSERT_TRUE(sph::simulate_cell(model, scheme, dt, stimulus, 600, [&](double s, const auto& y) {
        t.push_back(s);
        V.push_back(y[0]);
      }));
      double sum = 0;
      for (std::size_t i = 0; i < t_ref.size(); ++i) sum += std::pow(sph::interpolate_trace(t, V, t_ref[i]) - V_ref[i], 2);
      const double rms = std::sqrt(sum / t_ref.size());
      const double apd = sph::measure_action_potential(t, V, 0, 600).duration();
      std::printf("%s dt %.3g ms: RMS %.3g mV, APD90 %.2f ms (CVODE %.2f)\n", std::string(sph::to_string(scheme)).c_str(),
                  dt, rms, apd, apd_ref);
      EXPECT_LT(rms, previous_rms);
      previous_rms = rms;
      if (dt == 0.01) {
        EXPECT_LT(std::abs(apd - apd_ref) / apd_ref, 0.005);
      }
    }
  }
}

// Quiescent cells (reaction_system.hpp): a tissue of ten Tusscher-Panfilov cells paced at 1 Hz, in
// half steps of 0.05 ms (the heart's splitting), with quiescent blocks stepping at most every 1 ms.
// quiescent_rate 0.1 mV/ms (the heart's defaults, chosen on this beat; the Niederer slab in
// test_ep_validation.cpp checks them on tissue). Against CVODE over the second beat: the RMS voltage
// error within 0.006 mV of the fixed step's (measured +0.0019 mV), the RMS error of the calcium
// transient within 0.7 % of its peak (measured 0.24 %), APD90 within 0.25 ms of CVODE's (measured
// -0.076 ms; the fixed step errs by -0.060 ms); fewer than a third of the steps (measured 25.5 %).
TEST(ReactionSystem, QuiescentCellsSkipStepsWithinTheirErrorBound) {
  using Model = sph::TenTusscherPanfilov2006;
  const Model model;
  const double period = 1000, end = 2000, dt = 0.05;
  const sph::StimulusProtocol pacing{0, 1, 52, period, 2};
  constexpr std::size_t calcium = Model::StateIndex::Ca_i;
  std::vector<double> t_ref, V_ref, Ca_ref;
  sph::solve_cell_with_cvode(model, pacing, end, 0.5, [&](double t, const auto& y) {
    t_ref.push_back(t);
    V_ref.push_back(y[0]);
    Ca_ref.push_back(y[calcium]);
  });
  const double Ca_peak = *std::max_element(Ca_ref.begin(), Ca_ref.end());
  struct Run {
    double rms = 0, calcium_rms = 0, apd = 0, taken = 0;
  };
  const auto run = [&](double quiescent_step) {
    std::vector<sph::Vec<2>> positions;
    for (int i = 0; i < 11; ++i) positions.emplace_back(i, 0);  // a full block and a partial one
    sph::ParticleSet<2> particles("tissue", positions, std::vector<sph::Real>(positions.size(), 1));
    sph::ReactionSystem<2, Model> cells(particles, model, {ReactionScheme::rbr_qss, false, quiescent_step, 0.1});
    std::vector<double> t{0}, V{double(particles.field(cells.potential_field())[10])},
        Ca{double(particles.field(cells.state_field(calcium))[10])};
    const auto steps = static_cast<long>(std::llround(end / dt));
    for (long n = 0; n < steps; ++n) {
      const std::vector<sph::Real> stimulus(positions.size(), static_cast<sph::Real>(pacing.average(n * dt, dt)));
      cells.advance(static_cast<sph::Real>(n * dt), static_cast<sph::Real>(dt), stimulus);
      t.push_back((n + 1) * dt);
      V.push_back(particles.field(cells.potential_field())[10]);
      Ca.push_back(particles.field(cells.state_field(calcium))[10]);
    }
    Run r;
    double sum = 0, calcium_sum = 0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < t_ref.size(); ++i)
      if (t_ref[i] >= period) {
        sum += std::pow(sph::interpolate_trace(t, V, t_ref[i]) - V_ref[i], 2);
        calcium_sum += std::pow(sph::interpolate_trace(t, Ca, t_ref[i]) - Ca_ref[i], 2);
        ++count;
      }
    r.rms = std::sqrt(sum / double(count));
    r.calcium_rms = std::sqrt(calcium_sum / double(count)) / Ca_peak;
    r.apd = sph::measure_action_potential(t, V, period, end).duration();
    r.taken = double(cells.block_steps()) / double(cells.n_blocks() * steps);
    return r;
  };
  const double apd_ref = sph::measure_action_potential(t_ref, V_ref, period, end).duration();
  const Run fixed = run(0), skipping = run(1);
  std::printf("second beat against CVODE (APD90 %.2f ms): every step RMS %.4f mV, Ca_i RMS %.2e of its peak, APD90 "
              "%+.3f ms; quiescent blocks at most 1 ms RMS %.4f mV, Ca_i RMS %.2e, APD90 %+.3f ms, %.1f %% of the steps taken\n",
              apd_ref, fixed.rms, fixed.calcium_rms, fixed.apd - apd_ref, skipping.rms, skipping.calcium_rms,
              skipping.apd - apd_ref, 100 * skipping.taken);
  EXPECT_EQ(fixed.taken, 1.0);
  EXPECT_LT(skipping.rms, fixed.rms + 0.006);
  EXPECT_LT(skipping.calcium_rms, 0.007);
  EXPECT_LT(std::abs(skipping.apd - apd_ref), 0.25);
  EXPECT_LT(skipping.taken, 1.0 / 3);
}
#endif

}  // namespace
