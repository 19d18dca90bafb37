// FSI scenes at coarse resolution against their references (docs/fsi.md has the full tables).
#include <gtest/gtest.h>

#include <cstdio>

#include "apps/scenes/fsi/fsi_scenes.hpp"
#include "libsph/core/numerical_failure.hpp"
#include "run_scene_for_test.hpp"

namespace {

using test::run_scene;

double result(const sph::RunReport& r, const std::string& key) { return r.results.at(key).get<double>(); }
double error(const sph::RunReport& r, const std::string& key) { return r.errors.at(key).get<double>(); }

// Flow past the cylinder of Schaefer & Turek 1996 (case 2D-2) at 10 particles across it, to t = 60:
// the Strouhal number within 5 % of 0.300 (measured 0.304); the mean drag coefficient between 2.9
// and 3.4 (measured 3.18; the benchmark's c_D oscillates just below its maximum 3.22-3.24).
TEST(FsiValidation, CylinderFlowStrouhalAndDrag) {
  auto p = cardiosph::cylinder_flow_defaults();
  p.end_time = 60;
  const auto r = run_scene(*cardiosph::make_channel_flow_scene("cylinder-flow", p), "cylinder");
  std::printf("cylinder-flow D/dp = 10, t = 60: St %.4f (0.295-0.305), mean c_D %.3f, c_L harmonic amplitude %.3f; %.1f s\n",
              result(r, "strouhal"), result(r, "drag_coefficient_mean"), result(r, "lift_coefficient_harmonic_amplitude"),
              r.wall_time_s);
  EXPECT_EQ(r.status, "completed");
  EXPECT_LT(error(r, "strouhal_relative"), 0.05);
  EXPECT_GT(result(r, "drag_coefficient_mean"), 2.9);
  EXPECT_LT(result(r, "drag_coefficient_mean"), 3.4);
}

// Turek & Hron FSI2 in the SPHinXsys setup (dp 0.1, bar at twice the fluid's resolution) to t = 100,
// analysed over [70, 100]: the bar flaps with a tip y amplitude within 25 % of 0.806 D and a frequency
// within 20 % of 0.2 U / D (measured here 0.922 and 0.175; over [100, 200] of the full run 0.921 and 0.176: the bar of four
// particles across is too soft in bending, docs/fsi.md).
TEST(FsiValidation, TurekHronFsi2Flaps) {
  auto p = cardiosph::turek_hron_defaults();
  p.end_time = 100;
  p.analysis_start = 0.7;
  const auto r = run_scene(*cardiosph::make_channel_flow_scene("turek-hron-fsi2", p), "fsi2");
  std::printf("turek-hron-fsi2 dp 0.1, t = 100: tip y amplitude %.3f (0.806), frequency %.3f (0.2), x mean %.3f "
              "(-0.146); %.1f s\n",
              result(r, "tip_y_amplitude"), result(r, "tip_y_frequency"), result(r, "tip_x_mean"), r.wall_time_s);
  EXPECT_EQ(r.status, "completed");
  EXPECT_LT(error(r, "tip_amplitude_relative"), 0.25);
  EXPECT_LT(error(r, "tip_frequency_relative"), 0.2);
}

// The water column on the clamped plate at 4 solid particles across the plate and the fluid 4 times
// coarser, to t = 0.2: the plate sags, and its mid-span deflection lies within a factor 1.8 of the
// thin-plate value (measured 1.10 here, but 1.76 at the default fluid ratio 2 and t = 0.5: the TLSPH
// plate of four particles across is 70 % too soft in bending on its own, under the same load without
// fluid, so the coarse figure is a cancellation of errors, not agreement. SPHinXsys's own case at its
// resolution is 44 % too deep. The 2 % the benchmark asks for is not reached: docs/fsi.md).
TEST(FsiValidation, HydrostaticPlateSags) {
  cardiosph::HydrostaticPlateParameters p;
  p.fluid_ratio = 4;
  p.end_time = 0.2;
  const auto r = run_scene(*cardiosph::make_hydrostatic_plate_scene(p), "plate");
  std::printf("hydrostatic-plate 4 across, fluid ratio 4, t = 0.2: deflection %.4e against %.4e (%.1f %%); %.1f s\n",
              result(r, "mid_span_deflection"), result(r, "reference_deflection"), 100 * error(r, "deflection_relative"),
              r.wall_time_s);
  EXPECT_EQ(r.status, "completed");
  EXPECT_LT(result(r, "mid_span_deflection"), 0);
  EXPECT_LT(error(r, "deflection_relative"), 0.8);
}

// The dam break through the elastic gate (Antoci et al. 2007) at SPHinXsys's resolution (2 fluid and
// 4 solid particles across the gate), to t = 150 ms, past the gate's widest opening: against
// SPHinXsys's run of the same setup, the largest |dx| of the free corner within 10 % (measured 5.2 %),
// its largest dy within 25 % (measured 15 %), and the RMS difference of dx over the curve within
// 10 % of SPHinXsys's largest |dx|.
TEST(FsiValidation, ElasticGateOpensAsSphinxsys) {
  cardiosph::ElasticGateParameters p;
  p.end_time = 150;
  const auto r = run_scene(*cardiosph::make_elastic_gate_scene(p), "gate");
  std::printf("elastic-gate t = 150 ms: max |dx| %.2f mm (SPHinXsys 45.13, %.1f %%), max dy %.2f mm (18.81, %.1f %%), "
              "RMS dx difference %.1f %%; %.1f s\n",
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
