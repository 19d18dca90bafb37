// FSI scenes at coarse resolution against their references (docs/fsi.md has the full tables), and
// the regression guards (FsiRegression) of those that miss their reference today: each guard bounds
// the error at about 1.5 times today's and prints the published bound beside the measured value.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "apps/scenes/fsi/fsi_scenes.hpp"
#include "libsph/core/numerical_failure.hpp"
#include "run_scene_for_test.hpp"

namespace {

using test::run_scene;

double result(const sph::RunReport& r, const std::string& key) { return r.results.at(key).get<double>(); }
double error(const sph::RunReport& r, const std::string& key) { return r.errors.at(key).get<double>(); }

// Flow past the cylinder of Schaefer & Turek 1996 (case 2D-2) at 10 particles across it, to t = 60
// (the default runs to t = 100, twice the cost): the Strouhal number within 4 % of 0.300 (measured
// +1.4 %; the benchmark's 0.295-0.305 is +-1.7 %). The mean drag coefficient misses the benchmark
// here: the scene's c_D mean is the midrange of the sampled force over [30, 60], 2.92, 9.5 % below
// the benchmark's 3.22-3.24 (the force record is noisy, and its extremes set the midrange: at the
// default t = 100 the same statistic gives 3.22). Guard: |c_D / 3.23 - 1| below 0.14.
TEST(FsiRegression, CylinderFlowStrouhalAndDrag) {
  auto p = cardiosph::cylinder_flow_defaults();
  p.end_time = 60;
  const auto r = run_scene(*cardiosph::make_channel_flow_scene("cylinder-flow", p), "cylinder");
  const double cd = result(r, "drag_coefficient_mean");
  std::printf("cylinder-flow D/dp = 10, t = 60: St %.4f (%+.4f; published 0.295-0.305, bound 0.04), mean c_D %.3f (%+.3f from "
              "3.23; published 3.22-3.24: not met; guard 0.14), c_L harmonic amplitude %.3f; %.1f s\n",
              result(r, "strouhal"), result(r, "strouhal") / 0.3 - 1, cd, cd / 3.23 - 1,
              result(r, "lift_coefficient_harmonic_amplitude"), r.wall_time_s);
  EXPECT_EQ(r.status, "completed");
  EXPECT_LT(error(r, "strouhal_relative"), 0.04);
  EXPECT_LT(std::abs(cd / 3.23 - 1), 0.14);
}

// Turek & Hron 2006 FSI2 in the SPHinXsys setup (dp 0.1, bar at twice the fluid's resolution), the
// scene's default except its length: to t = 100 (the default 200 takes 78 s), analysed over
// [70, 100]. The code misses the benchmark: the bar of four particles across is too soft in bending
// (docs/fsi.md), so the tip flaps with a y amplitude 15 % above 0.806 D and a frequency 12 % below
// 0.2 U / D (measured 0.927 and 0.175; over [100, 200] of the full run 0.921 and 0.176). The 5 %
// asked of the amplitude and the frequency is not met; the guard is 1.5 times today's errors.
TEST(FsiRegression, TurekHronFsi2AmplitudeAndFrequency) {
  auto p = cardiosph::turek_hron_defaults();
  p.end_time = 100;
  p.analysis_start = 0.7;
  const auto r = run_scene(*cardiosph::make_channel_flow_scene("turek-hron-fsi2", p), "fsi2");
  std::printf("turek-hron-fsi2 dp 0.1, t = 100: tip y amplitude %.3f (0.806), error %+.3f (bound asked 0.05: not met; "
              "guard 0.22); frequency %.3f (0.2), error %+.3f (bound asked 0.05: not met; guard 0.19); x mean %.3f "
              "(-0.146 +- 0.124); %.1f s\n",
              result(r, "tip_y_amplitude"), result(r, "tip_y_amplitude") / 0.806 - 1, result(r, "tip_y_frequency"),
              result(r, "tip_y_frequency") / 0.2 - 1, result(r, "tip_x_mean"), r.wall_time_s);
  EXPECT_EQ(r.status, "completed");
  EXPECT_LT(error(r, "tip_amplitude_relative"), 0.22);
  EXPECT_LT(error(r, "tip_frequency_relative"), 0.19);
}

// The water column on the clamped plate (Fourey et al. 2017) at the scene's default: 4 solid
// particles across the plate, the fluid twice as coarse, to t = 0.5, the deflection averaged over
// [0.3, 0.5]. The code misses the thin-plate value: the mid-span deflection is 84 % too deep
// (-1.26e-4 against -6.86e-5). The TLSPH plate of four particles across is 70 % too soft in bending
// on its own, under the same load without fluid (docs/fsi.md), and the plate still oscillates about
// its sag at t = 0.5, so the mean depends on the window (76 % in an earlier measurement). SPHinXsys's
// own case at its resolution is 44 % too deep. The benchmark's 2 % is not met; the guard is 1.5
// times today's error. (With the fluid four times coarser and to t = 0.2 the error was 10 %, a
// cancellation of errors: this test ran that setup before.)
TEST(FsiRegression, HydrostaticPlateDeflectionAtTheDefault) {
  cardiosph::HydrostaticPlateParameters p;
  const auto r = run_scene(*cardiosph::make_hydrostatic_plate_scene(p), "plate");
  const double w = result(r, "mid_span_deflection"), reference = result(r, "reference_deflection");
  std::printf("hydrostatic-plate 4 across, fluid ratio 2, t = 0.5: deflection %.4e against %.4e, error %+.3f (the "
              "benchmark's bound 0.02: not met; guard 1.26); %.1f s\n",
              w, reference, w / reference - 1, r.wall_time_s);
  EXPECT_EQ(r.status, "completed");
  EXPECT_LT(w, 0);
  EXPECT_LT(error(r, "deflection_relative"), 1.26);
}

// The dam break through the elastic gate (Antoci et al. 2007) at SPHinXsys's resolution (2 fluid and
// 4 solid particles across the gate), to t = 150 ms, past the gate's widest opening: against
// SPHinXsys's run of the same setup, the largest |dx| of the free corner within 10 % (measured 6.0 %),
// its largest dy within 25 % (measured 17 %), and the RMS difference of dx over the curve within
// 10 % of SPHinXsys's largest |dx| (measured 5.7 %).
TEST(FsiValidation, ElasticGateOpensAsSphinxsys) {
  cardiosph::ElasticGateParameters p;
  p.end_time = 150;
  const auto r = run_scene(*cardiosph::make_elastic_gate_scene(p), "gate");
  std::printf("elastic-gate t = 150 ms: max |dx| %.2f mm (SPHinXsys 45.13, %.1f %%, bound 10 %%), max dy %.2f mm (18.81, %.1f %%, "
              "bound 25 %%), RMS dx difference %.1f %% (bound 10 %%); %.1f s\n",
              result(r, "tip_max_abs_dx"), 100 * error(r, "tip_max_dx_relative"), result(r, "tip_max_dy"),
              100 * error(r, "tip_max_dy_relative"), 100 * error(r, "tip_dx_rms_relative"), r.wall_time_s);
  EXPECT_EQ(r.status, "completed");
  EXPECT_LT(error(r, "tip_max_dx_relative"), 0.10);
  EXPECT_LT(error(r, "tip_max_dy_relative"), 0.25);
  EXPECT_LT(error(r, "tip_dx_rms_relative"), 0.10);
}

// A plate 1000 times stiffer (its solid sub-cycles about 30 times more) and one 100 times softer
// (deflection of millimetres) complete a short run or stop with a numerical-failure diagnostic.
TEST(FsiValidation, StiffAndSoftPlatesCompleteOrStopWithADiagnostic) {
  for (double factor : {1000.0, 0.01}) {
    cardiosph::HydrostaticPlateParameters p;
    p.fluid_ratio = 4;
    p.young_modulus *= factor;
    p.end_time = factor > 1 ? 0.002 : 0.05;
    try {
      const auto r = run_scene(*cardiosph::make_hydrostatic_plate_scene(p), factor > 1 ? "stiff" : "soft");
      std::printf("plate E x %g: completed, deflection %.3e, %g solid steps\n", factor, result(r, "mid_span_deflection"),
                  result(r, "solid_steps"));
      EXPECT_LT(result(r, "mid_span_deflection"), 0);
    } catch (const sph::NumericalFailure& e) {
      std::printf("plate E x %g: stopped: %s\n", factor, e.what());
      EXPECT_NE(std::string(e.what()).find("time"), std::string::npos);
    }
  }
}

}  // namespace
