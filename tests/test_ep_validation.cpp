// Validation of the electrophysiology (label: validation): cell schemes against CVODE, the 2D
// depolarization case against a converged run, and the Niederer slab against the published spread.
// Bounds are stated in each test and the measured values printed.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>

#include "apps/scenes/electrophysiology/ep_scenes.hpp"
#include "libsph/reaction/cell_models.hpp"
#include "run_scene_for_test.hpp"

namespace {

using test::run_scene;

#if CARDIOSPH_HAVE_CVODE
// One paced beat of each model, every scheme on the step ladder 0.01 ms x 2^k up to 163.84 ms.
//  - Accuracy: the QSS schemes at 0.01 ms are within 0.05 % of the CVODE APD90 (measured 0.005 %
//    to 0.017 % over the models and both schemes) and within an RMS voltage difference of 0.025 mV
//    with the splitting scheme (measured 0.0034 to 0.0076 mV) and 0.25 mV with Rush-Larsen
//    (measured 0.0088 to 0.081 mV, the largest on ten Tusscher-Panfilov).
//  - Stiffness: at the first rung at least 20 times the forward-Euler limit (from the Jacobian
//    along the reference), the QSS schemes stay bounded; the splitting scheme stays bounded at
//    every rung. For the stiff ten Tusscher-Panfilov model, APD90 there is within 2.5e-5 of CVODE
//    with the splitting scheme (measured 8e-6) and 1.3e-3 with Rush-Larsen (measured 4.3e-4).
//    For the two-variable models the explicit limit is set by the action potential itself (AP
//    upstroke and plateau for Aliev-Panfilov: 3.8 ms; 20 times that is a third of the APD), so
//    their APD90 at 20 times the limit is beyond any first-order splitting: printed, not asserted.
TEST(EpValidation, CellSchemesAgainstCvode) {
  cardiosph::CellParameters p;
  p.end_time = 1000;
  p.resolution = 15;
  const auto r = run_scene(*cardiosph::make_cell_scene(p), "cell");
  for (const auto& name_view : sph::cell_model_names) {
    const std::string name(name_view);
    const auto& m = r.results.at(name);
    const double apd = m.at("cvode_apd90_ms").get<double>(), limit = m.at("forward_euler_step_limit_ms").get<double>();
    const auto& steps = m.at("time_steps_ms");
    std::size_t stiff_rung = 0;
    while (stiff_rung < steps.size() && steps[stiff_rung].get<double>() < 20 * limit) ++stiff_rung;
    ASSERT_LT(stiff_rung, steps.size()) << name << ": the ladder does not reach 20 times the explicit limit";
    for (const char* scheme : {"rbr_qss", "rush_larsen"}) {
      const auto& s = m.at(scheme);
      const double error0 = s.at("apd90_error_ms")[0].get<double>(), rms0 = s.at("rms_mV")[0].get<double>();
      const bool stiff_stable = s.at("stable")[stiff_rung].get<bool>();
      const auto& stiff_error = s.at("apd90_error_ms")[stiff_rung];
      const double stiff_relative = stiff_error.is_number() ? stiff_error.get<double>() / apd : INFINITY;
      const bool splitting = std::string(scheme) == "rbr_qss";
      const double rms_bound = splitting ? 0.025 : 0.25, stiff_bound = splitting ? 2.5e-5 : 1.3e-3;
      std::printf("%s %s: APD90 %.2f ms (CVODE), at 0.01 ms error %.4f%% and RMS %.3g mV (bounds 0.05%%, %g mV); "
                  "explicit limit %.3g ms, at %.3g ms (%.0fx): %s, APD90 error %.4f%%%s\n",
                  name.c_str(), scheme, apd, 100 * error0 / apd, rms0, rms_bound, limit, steps[stiff_rung].get<double>(),
                  steps[stiff_rung].get<double>() / limit, stiff_stable ? "bounded" : "UNBOUNDED", 100 * stiff_relative,
                  name == "ten_tusscher_panfilov_2006" ? (splitting ? " (bound 0.0025%)" : " (bound 0.13%)") : " (printed, not asserted)");
      EXPECT_LT(std::abs(error0) / apd, 5e-4) << name << " " << scheme;
      EXPECT_LT(rms0, rms_bound) << name << " " << scheme;
      EXPECT_TRUE(stiff_stable) << name << " " << scheme;
      if (name == "ten_tusscher_panfilov_2006") {
        EXPECT_LT(std::abs(stiff_relative), stiff_bound) << scheme;
      }
    }
    for (std::size_t k = 0; k < steps.size(); ++k)
      EXPECT_TRUE(m.at("rbr_qss").at("stable")[k].get<bool>()) << name << " rbr_qss at " << steps[k].get<double>() << " ms";
  }
}
#endif

// SPHinXsys depolarization case at its resolution (dp = 0.02): the observer's upstroke time and
// V(1) against the converged reference of this code (measured 0.65 % and 0.0025; bounds 2 % and
// 0.0075), and the plateau against the SPHinXsys regression value 0.975, given to three decimals
// (measured 0.97516; bound 5e-4, three times the difference and the rounding of the value).
TEST(EpValidation, DepolarizationObserver) {
  const auto r = run_scene(*cardiosph::make_depolarization_scene(), "depolarization");
  const double up = r.results.at("observer_upstroke_time").get<double>();
  const double at_1 = r.results.at("observer_potential_at_1").get<double>();
  const double plateau = r.results.at("observer_plateau").get<double>();
  const double up_error = r.errors.at("upstroke_time_relative").get<double>();
  const double at_1_error = r.errors.at("potential_at_1_abs").get<double>();
  std::printf("depolarization dp 0.02: upstroke %.4f (error %.2f%%, bound 2%%), V(1) %.4f (error %.4f, bound 0.0075), plateau "
              "%.5f (SPHinXsys 0.975, difference %+.1e, bound 5e-4)\n",
              up, 100 * up_error, at_1, at_1_error, plateau, plateau - 0.975);
  EXPECT_LT(up_error, 0.02);
  EXPECT_LT(at_1_error, 0.0075);
  EXPECT_NEAR(plateau, 0.975, 5e-4);
}

// Niederer et al. 2011 slab at dx = 0.5 mm, dt = 0.05 ms (the scene's default): every point
// activated, P1 next to the stimulus first, and the far corner P8 within the published spread at
// this resolution, the mean +- one standard deviation over the 11 codes, 117.86 +- 36.11 ms. The
// spread was published at dt = 0.01 ms; this code's P8 moves by 0.8 ms between the two steps
// (126.5 ms at 0.05, 127.3 ms at 0.01: docs/electrophysiology.md, the dt table), 2 % of the standard
// deviation, so the step does not decide where P8 lies in the spread. The spread (+-31 %) is wider
// than three times the measured distance from the mean (8.7 ms), and is the bound. (The APD map
// against the single cell is checked on the cable below, which repolarises in a fifth of the slab's
// time.)
TEST(EpValidation, NiedererSlabCoarse) {
  const auto r = run_scene(*cardiosph::make_niederer_slab_scene(), "niederer");
  const auto& a = r.results.at("activation_ms");
  const std::array<const char*, 9> points{"P1", "P2", "P3", "P4", "P5", "P6", "P7", "P8", "P9"};
  std::printf("niederer-slab dx 0.5: ");
  for (const char* point : points) std::printf("%s %.1f ", point, a.at(point).get<double>());
  const double p8 = a.at("P8").get<double>();
  std::printf("ms; P8 %+.1f ms from the published mean (bound: one standard deviation, 36.11 ms)\n", p8 - 117.86);
  for (const char* point : points) EXPECT_GT(a.at(point).get<double>(), 0) << point;
  EXPECT_LT(a.at("P1").get<double>(), 3);
  EXPECT_LT(a.at("P9").get<double>(), a.at("P8").get<double>());
  EXPECT_GT(p8, 117.86 - 36.11);
  EXPECT_LT(p8, 117.86 + 36.11);
  // Quiescent cells stepping every 1 ms (the heart's default) until the front wakes them: every
  // activation time within 0.1 ms of the every-step run's (measured up to 0.05 ms, P2).
  const auto q = run_scene(cardiosph::make_niederer_slab_scene(), {"reaction_quiescent_step=1"}, "niederer_quiescent");
  const auto& b = q.results.at("activation_ms");
  double largest = 0;
  for (const char* point : points) largest = std::max(largest, std::abs(b.at(point).get<double>() - a.at(point).get<double>()));
  std::printf("quiescent cells at most 1 ms: activation times within %.3f ms of every step's (bound 0.1 ms), %.0f %% of "
              "the reaction steps taken\n",
              largest, 100 * q.results.at("reaction_steps_taken").get<double>());
  EXPECT_LT(largest, 0.1);
  EXPECT_LT(q.results.at("reaction_steps_taken").get<double>(), 0.6);
}

// The cable (10 x 0.5 x 0.5 mm, dx 0.25 mm) under two S1-S2 blocks (two S1 at 600 ms, S2 at 450
// and 350 ms): both S2 captured, APD and CV fall with the diastolic interval (restitution), and
// the APD of each S2 beat at the middle lies within 3 % of the single cell's under the same pulses
// (measured 0.97 %). The APD90 map: every particle has repolarised by the end, and the map's median
// (the last beat, the S2 at 350 ms) lies within 3 % of the single cell's last beat (measured +1.0 %).
TEST(EpValidation, CableRestitutionAgainstTheSingleCell) {
  cardiosph::CableParameters parameters;
  parameters.pacing.period = 600;
  parameters.pacing.s1_count = 2;
  parameters.pacing.couplings = "450,350";
  const auto r = run_scene(*cardiosph::make_cable_scene(parameters), "cable");
  const auto& curve = r.results.at("beats").at("restitution");
  ASSERT_EQ(curve.size(), 2u);
  for (const auto& row : curve) {
    ASSERT_TRUE(row.at("captured").get<bool>());
    std::printf("S2 at %.0f ms: DI %.1f ms, APD90 %.1f ms, CV %.3f mm/ms\n", row.at("coupling_ms").get<double>(),
                row.at("diastolic_interval_ms").get<double>(), row.at("apd_ms").get<double>(),
                row.at("cv_mm_per_ms").get<double>());
  }
  EXPECT_GT(curve[0].at("diastolic_interval_ms").get<double>(), curve[1].at("diastolic_interval_ms").get<double>());
  EXPECT_GT(curve[0].at("apd_ms").get<double>(), curve[1].at("apd_ms").get<double>());
  EXPECT_GT(curve[0].at("cv_mm_per_ms").get<double>(), curve[1].at("cv_mm_per_ms").get<double>());
  const double error = r.errors.at("restitution_apd_max_relative").get<double>();
  std::printf("largest APD difference from the single cell: %.2f %%\n", 100 * error);
  EXPECT_LT(error, 0.03);
  const auto& apd = r.results.at("maps").at("apd90_ms");
  const double cell_last = r.results.at("single_cell").back().at("apd_ms").get<double>();
  std::printf("APD90 map: median %.1f ms (range %.1f-%.1f over %d particles), single cell's last beat %.1f ms\n",
              apd.at("median").get<double>(), apd.at("min").get<double>(), apd.at("max").get<double>(),
              apd.at("count").get<int>(), cell_last);
  EXPECT_EQ(apd.at("count").get<int>(), 160);
  EXPECT_NEAR(apd.at("median").get<double>(), cell_last, 0.03 * cell_last);
}

}  // namespace
