// FSI scenes at coarse resolution against their references (docs/fsi.md has the full tables), and
// the regression guards (FsiRegression) of those that miss their reference today: each guard bounds
// the error at about 1.5 times today's and prints the published bound beside the measured value.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "apps/scenes/fsi/fsi_scenes.hpp"
#include "apps/scenes/solid/solid_scenes.hpp"
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
// [70, 100]. The code misses the benchmark: the tip flaps with a y amplitude 14 % above 0.806 D and
// a frequency 12 % below 0.2 U / D (measured 0.916, the mean of the periods' half ranges as Turek &
// Hron take it per period, and 0.175; the half range over the whole window was 0.927, and 0.921
// over [100, 200] of the full run). The bar's bending explains part of the frequency error (the
// quadratic F gives -7 %) and none of the amplitude's (docs/fsi.md). The 5 % asked of the amplitude
// and the frequency is not met; the guard is 1.5 times the errors measured when it was set.
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

// The Turek-Hron FSI2 bar on its own (L = 3.5, H = 0.2, rho = 10, E = 1400, nu = 0.4, 4 particles
// across) in its second bending mode, the mode FSI2 oscillates in: the oscillating-beam scene with
// mode = 2. At that scene's solid numerics (quadratic F, Gauss points, clamp by reflection) the
// period lies within 5 % of the thin plate's, 2 pi / omega with omega^2 = E H^2 k^4 / (12 rho
// (1 - nu^2) L^4), k L = 4.6941 (measured +2.6 %; shear and rotary inertia lengthen the thin-plate
// period by about 1.3 % at L / H = 17.5). The FSI2 scene's own solid numerics (kernel-corrected F,
// nodal, clamp fixed) make the bar's period 22 % too long (docs/fsi.md): that is most of FSI2's
// frequency error.
TEST(FsiValidation, TurekHronBarAloneSecondBendingMode) {
  cardiosph::OscillatingBeamParameters p;
  p.mode = 2;
  p.length = 3.5;
  p.thickness = 0.2;
  p.resolution = 4;
  p.clamp_length = 0.2;
  p.density = 10;
  p.young_modulus = 1400;
  p.poisson_ratio = 0.4;
  p.velocity_factor = 0.01;
  p.end_time = 10;
  const auto r = run_scene(*cardiosph::make_oscillating_beam_scene(p), "fsi2_bar");
  const double period = result(r, "period_s"), reference = result(r, "reference_period_s");
  std::printf("FSI2 bar alone, second mode, 4 across: period %.4f (thin plate %.4f), error %+.4f (bound 0.05), %g half periods, %.1f s\n",
              period, reference, period / reference - 1, result(r, "half_periods_measured"), r.wall_time_s);
  EXPECT_LT(error(r, "period_relative"), 0.05);
  EXPECT_GE(result(r, "half_periods_measured"), 3);
}

// The clamped plate on its own: the hydrostatic-plate scene with a water film of one fluid layer
// and gravity raised to 155 m/s^2, so that the plate's own weight carries (nearly all of) the load of
// the 2 m column, q = g (rho_f H + rho_s t) (the reference takes the film into account). At the
// scene's default solid numerics (4 particles across the plate, quadratic F, Gauss points, clamp by
// reflection, inertia scaled by 100) the mean mid-span sag over [0.03, 0.15] s lies within 1 % of
// the clamped Timoshenko beam in plane strain, w = q L^4 / (384 D) + q L^2 / (8 kappa G t)
// (measured +0.03 %; +0.4 % at 8 across). The thin-plate value alone is 3.6 % shallower: a continuum
// solid shears. (The kernel-corrected F with a fixed clamp sagged 64 % too deep here, docs/fsi.md.)
TEST(FsiValidation, PlateAloneBendsAsATimoshenkoBeam) {
  cardiosph::HydrostaticPlateParameters p;
  p.water_height = 0.025;
  p.gravity = 155;
  p.fluid_density = 1;
  p.end_time = 0.15;
  const auto r = run_scene(*cardiosph::make_hydrostatic_plate_scene(p), "plate_alone");
  const double w = result(r, "mid_span_deflection");
  std::printf("plate alone, 4 across: sag %.4e, Timoshenko %.4e (%+.2f %%, bound 1 %%), thin plate %.4e (%+.2f %%); %.1f s\n", w,
              result(r, "reference_deflection"), 100 * (w / result(r, "reference_deflection") - 1),
              result(r, "thin_plate_deflection"), 100 * (w / result(r, "thin_plate_deflection") - 1), r.wall_time_s);
  EXPECT_EQ(r.status, "completed");
  EXPECT_LT(error(r, "deflection_relative"), 0.01);
}

// The water column on the clamped plate (Fourey et al. 2017) at the scene's default: 4 solid
// particles across the plate, the fluid twice as coarse, to t = 0.5, the deflection averaged over
// [0.1, 0.5] (the column rings in its acoustic mode, about 45 ms, with an amplitude larger than the
// sag: the mean over many periods is the measure). Against the clamped plate with Timoshenko's
// shear within 2 % (measured +0.8 %). Fourey et al.'s value is the thin plate's, -6.86e-5, which a
// continuum solid does not converge to (the plate alone converges to the sheared value, the test
// above): the deflection is 4.5 % deeper than it, printed beside. SPHinXsys's own case at its
// resolution is 44 % too deep.
TEST(FsiValidation, HydrostaticPlateDeflectionAtTheDefault) {
  cardiosph::HydrostaticPlateParameters p;
  const auto r = run_scene(*cardiosph::make_hydrostatic_plate_scene(p), "plate");
  const double w = result(r, "mid_span_deflection"), reference = result(r, "reference_deflection");
  std::printf("hydrostatic-plate 4 across, fluid ratio 2, t = 0.5: deflection %.4e against %.4e (with shear), error %+.3f "
              "(bound 0.02); against the thin plate %.4e %+.3f (the benchmark's 2 %% on the thin plate: not met, see "
              "above); %.1f s\n",
              w, reference, w / reference - 1, result(r, "thin_plate_deflection"),
              w / result(r, "thin_plate_deflection") - 1, r.wall_time_s);
  EXPECT_EQ(r.status, "completed");
  EXPECT_LT(error(r, "deflection_relative"), 0.02);
}

// The dam break through the elastic gate (Antoci et al. 2007) at SPHinXsys's resolution (2 fluid and
// 4 solid particles across the gate), to t = 370 ms, over the whole measured record (the widest
// opening: the experiment's at 160 ms, SPHinXsys's at 135 ms).
// Against the experiment (digitised points every 40 ms to 360 ms; the scene names the source; no
// scatter was published, the two public digitisations agree within 0.5 mm): the largest |dx| at the
// measured times within 5 % of the largest measured (measured +1.1 %), the largest dy within 30 %
// (measured +22 %: the gate rises too far, as in SPHinXsys's run, +10 %), the RMS difference of dx
// over the record within 10 % of the measured peak (measured 8.2 %; over the opening alone, the
// first four points, 10.6 %: the model opens faster than the experiment).
// Against SPHinXsys's run of the same setup: the largest |dx| within 10 % (measured 5.7 %), the
// largest dy within 25 % (measured 17 %), the RMS dx difference within 10 % (measured 5.6 %).
TEST(FsiValidation, ElasticGateOpensAsTheExperiment) {
  cardiosph::ElasticGateParameters p;
  p.end_time = 370;
  const auto r = run_scene(*cardiosph::make_elastic_gate_scene(p), "gate");
  std::printf("elastic-gate t = 370 ms against the experiment: largest |dx| at its times %.2f mm (46.39, %+.1f %%, bound 5 %%), "
              "largest dy %.2f mm (17.09, %.1f %%, bound 30 %%), RMS dx difference %.1f %% (bound 10 %%), RMS dy %.1f %%\n",
              result(r, "tip_max_abs_dx_at_experiment_times"), 100 * error(r, "experiment_max_dx_relative"),
              result(r, "tip_max_dy_at_experiment_times"), 100 * error(r, "experiment_max_dy_relative"),
              100 * error(r, "experiment_dx_rms_relative"), 100 * error(r, "experiment_dy_rms_relative"));
  std::printf("elastic-gate against SPHinXsys: max |dx| %.2f mm (45.13, %.1f %%, bound 10 %%), max dy %.2f mm (18.81, %.1f %%, "
              "bound 25 %%), RMS dx difference %.1f %% (bound 10 %%); %.1f s\n",
              result(r, "tip_max_abs_dx"), 100 * error(r, "tip_max_dx_relative"), result(r, "tip_max_dy"),
              100 * error(r, "tip_max_dy_relative"), 100 * error(r, "tip_dx_rms_relative"), r.wall_time_s);
  EXPECT_EQ(r.status, "completed");
  EXPECT_LT(error(r, "experiment_max_dx_relative"), 0.05);
  EXPECT_LT(error(r, "experiment_max_dy_relative"), 0.30);
  EXPECT_LT(error(r, "experiment_dx_rms_relative"), 0.10);
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
