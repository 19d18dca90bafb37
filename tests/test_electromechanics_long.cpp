// Electromechanics runs of minutes (label: long; in the full suite, `ctest -L long`): Land et al.
// 2015 problem 3 at the resolution of its bound (problem 2 at the default resolution stays in the
// validation suite); the heart's Frank-Starling response and passive filling against human data;
// the coarse heart converged, a calibration check at the resolution CI affords.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>

#include "apps/scenes/electromechanics/em_scenes.hpp"
#include "libsph/io/parameters.hpp"
#include "run_scene_for_test.hpp"

namespace {

using test::run_scene;
const auto at = test::result;

// Problem 3 (inflation to 15 kPa and contraction at T_a = 60 kPa) at dp = 0.75 mm with the benchmark's
// prolate-spheroidal fibre field: both apex positions within 0.5 mm of the refined published solution
// (endo -12.35, epi -15.45 mm). Measured -12.01 and -14.97 mm (+0.34, +0.48); at dp = 1 mm +0.81 and
// +0.49; with the LDRB fibres, whose direction near the apex points through the wall, +1.6 and +2.9.
TEST(ElectromechanicsLong, LandProblemThreeApexWithinHalfAMillimetre) {
  const auto r = run_scene(cardiosph::make_land_lv_scene(), {"problem=3", "dp=0.75"}, "land_lv_p3");
  const double endo = at(r, "apex_z_endo_mm"), epi = at(r, "apex_z_epi_mm");
  std::cout << "land-lv problem 3, dp 0.75: apex z endo " << endo << " (published -12.347), epi " << epi
            << " (-15.452); bound 0.5 mm; J in [" << at(r, "min_jacobian") << ", " << at(r, "max_jacobian") << "], "
            << r.wall_time_s << " s\n";
  EXPECT_LT(std::abs(endo - -12.347), 0.5);
  EXPECT_LT(std::abs(epi - -15.452), 0.5);
}

// The Frank-Starling response, a validation of the heart against data that no calibration used
// (the calibration tuned T_ref, the Purkinje speed, the impedance and the springs at one preload;
// docs/electromechanics.md). The coarse heart's first beat at three preloads (LV 0.8, 1.2 and 1.6
// kPa, the RV at a third of it, the arterial pressures as they start): the end-diastolic volume
// follows the preload, and the stroke volume must grow with it as in healthy humans. Nixon et al.
// 1982 (Circulation 65:698) varied the preload of 12 young men by head-down tilt and lower-body
// negative pressure at nearly constant heart rate and arterial pressure: SV = 0.36 EDV^1.1 over the
// group, EDV +23 % with SV +35 % (tilt) and EDV -28 % with SV -33 % (negative pressure), i.e. an
// elasticity d ln SV / d ln EDV of 1.1, 1.45 and 1.22. Bound: the elasticity of the fit through the
// three beats within that published spread widened by half its width each side, [0.93, 1.63] (the
// three are estimates over the group, whose individual slopes scatter more: r = 0.92 for their
// linear fit). Measured 1.48, 0.03 above the group's 1.45 (EDV 66.7, 69.1, 72.4 mL; SV 40.8, 43.0,
// 46.0 mL; 1.47 at mass_scaling 4); the linear slope dSV/dEDV 0.92 against their regression's 0.6.
TEST(HeartLong, FrankStarlingStrokeVolumeGrowsWithPreloadAsInHumans) {
  const double preload[3] = {0.8, 1.2, 1.6};
  double edv[3], sv[3];
  for (int k = 0; k < 3; ++k) {
    const std::string lv = std::to_string(preload[k]), rv = std::to_string(preload[k] / 3);
    const auto r = run_scene(cardiosph::make_heart_scene(),
                       {"preset=coarse", "beats=1", "end_time=650", "output_interval=0", "ecg=none", "lv_pressure=" + lv,
                        "rv_pressure=" + rv},
                       "heart_starling_" + std::to_string(k));
    edv[k] = at(r, "lv_end_diastolic_volume_mm3");
    sv[k] = edv[k] - at(r, "lv_end_systolic_volume_mm3");
    std::cout << "preload " << preload[k] << " kPa: LV EDV " << edv[k] << " mm^3, SV " << sv[k] << " mm^3, EF " << sv[k] / edv[k]
              << ", peak " << at(r, "lv_peak_pressure_kPa") << " kPa, J in [" << at(r, "min_jacobian") << ", "
              << at(r, "max_jacobian") << "], " << r.wall_time_s << " s\n";
    EXPECT_EQ(r.status, "completed");
  }
  // Least-squares slope of ln SV against ln EDV.
  double mx = 0, my = 0;
  for (int k = 0; k < 3; ++k) mx += std::log(edv[k]) / 3, my += std::log(sv[k]) / 3;
  double sxy = 0, sxx = 0;
  for (int k = 0; k < 3; ++k) {
    sxy += (std::log(edv[k]) - mx) * (std::log(sv[k]) - my);
    sxx += (std::log(edv[k]) - mx) * (std::log(edv[k]) - mx);
  }
  const double elasticity = sxy / sxx;
  std::cout << "Frank-Starling: d ln SV / d ln EDV = " << elasticity
            << " (Nixon et al. 1982: 1.1 to 1.45; bound [0.93, 1.63]); linear slope dSV/dEDV "
            << (sv[2] - sv[0]) / (edv[2] - edv[0]) << " (their regression: 0.6)\n";
  EXPECT_LT(edv[0], edv[1]);
  EXPECT_LT(edv[1], edv[2]);
  EXPECT_GE(elasticity, 0.93);
  EXPECT_LE(elasticity, 1.63);
}

// Passive filling of the unloaded coarse heart against the end-diastolic pressure-volume relation of
// human ventricles, data that no calibration of the heart used (its passive constants are Holzapfel &
// Ogden 2009's, fitted to tissue shear tests). Klotz et al. 2006 (Am. J. Physiol. Heart Circ. Physiol.
// 291:H403) found the EDPVRs of ex-vivo human hearts to collapse onto one curve once the volume is
// normalised between the unloaded volume V_0 and the volume at 30 mmHg, V_30:
//   P = A_n V_n^B_n,  V_n = (V - V_0) / (V_30 - V_0),  A_n = 27.78 mmHg, B_n = 2.76.
// The LV is inflated (the beat's preload ramp over 200 ms, held 100 ms, no stimulus; the RV at a
// third of the pressure) to 9, 15 and 30 mmHg; V_n at 9 and 15 mmHg is compared with the curve's
// (p / A_n)^(1 / B_n) = 0.665 and 0.800. Not met today: the wall is stiffer than the human curve at
// low pressure (measured V_n 0.505 and 0.700, 0.511 and 0.699 at mass_scaling 4; 0.30 against 0.50
// at 4 mmHg, still creeping after the hold, so left out), nearly linear where the human curve is
// exponential; without the pericardial springs V_n rises by 0.03-0.05. A regression guard at 1.5x
// the largest difference when it was set (0.154; 0.160 now); the
// comparison becomes a validation once the passive response meets the curve.
TEST(HeartRegression, PassiveFillingAgainstTheHumanEdpvr) {
  constexpr double mmHg = 0.133322, A_n = 27.78, B_n = 2.76;
  const double pressure_mmHg[3] = {9, 15, 30};
  double volume[3], unloaded = 0;
  for (int k = 0; k < 3; ++k) {
    const double lv = pressure_mmHg[k] * mmHg;
    const auto r = run_scene(cardiosph::make_heart_scene(),
                       {"preset=coarse", "preload_time=300", "pressure_ramp_time=200", "end_time=300", "output_interval=0",
                        "ecg=none", "lv_pressure=" + std::to_string(lv), "rv_pressure=" + std::to_string(lv / 3)},
                       "heart_edpvr_" + std::to_string(k));
    volume[k] = at(r, "lv_end_diastolic_volume_mm3");
    unloaded = at(r, "lv_reference_volume_mm3");
    std::cout << "LV at " << pressure_mmHg[k] << " mmHg: " << volume[k] << " mm^3 (unloaded " << unloaded << "), J in ["
              << at(r, "min_jacobian") << ", " << at(r, "max_jacobian") << "], " << r.wall_time_s << " s\n";
    EXPECT_EQ(r.status, "completed");
  }
  double worst = 0;
  for (int k = 0; k < 2; ++k) {
    const double normalised = (volume[k] - unloaded) / (volume[2] - unloaded);
    const double human = std::pow(pressure_mmHg[k] / A_n, 1 / B_n);
    worst = std::max(worst, std::abs(normalised - human));
    std::cout << "  " << pressure_mmHg[k] << " mmHg: V_n " << normalised << ", Klotz et al. 2006 " << human << " (difference "
              << normalised - human << ")\n";
  }
  std::cout << "largest |V_n - Klotz| " << worst << " (the human curve: not met; guard 0.23)\n";
  EXPECT_LT(worst, 0.23);
}

// The coarse heart beating until its stroke volumes settle: the run that README's default beat
// (dp 2 mm, 15 min, not in the suite) stands for at a resolution CI can afford. A calibration check:
// the last beat inside the four healthy ranges the defaults were tuned to (on the coarse first
// beat; docs/electromechanics.md, "Calibration"). Measured at mass_scaling 16: converged in 4 beats
// (the stroke volumes changed by 1.05 % from beat 3), LV EF 61.5 %, LV peak 16.45 kPa, LV EDP 1.18
// kPa, RV peak 3.35 kPa; blood kept to 1e-14; J in [0.880, 1.049] (at 4: 16.50 kPa, 1.25 kPa,
// 3.37 kPa, J in [0.860, 1.086]).
TEST(HeartCalibration, CoarseHeartConvergesInsideTheHealthyRanges) {
  const auto r = run_scene(cardiosph::make_heart_scene(), {"preset=coarse", "output_interval=0", "ecg=none"}, "heart_converged");
  const auto blood = r.results.at("total_blood_volume_mm3");
  const double drift = std::abs(blood[1].get<double>() - blood[0].get<double>()) / blood[0].get<double>();
  std::cout << "coarse heart: converged in " << r.results.at("beats_to_converge") << " beats (last change "
            << at(r, "stroke_volume_change_last_beat") << "), LV EF " << at(r, "lv_ejection_fraction") << ", LV peak "
            << at(r, "lv_peak_pressure_kPa") << " kPa, LV EDP " << at(r, "lv_end_diastolic_pressure_kPa") << " kPa, RV EF "
            << at(r, "rv_ejection_fraction") << ", RV peak " << at(r, "rv_peak_pressure_kPa") << " kPa; blood drift " << drift
            << "; J in [" << at(r, "min_jacobian") << ", " << at(r, "max_jacobian") << "], " << r.wall_time_s << " s\n";
  EXPECT_EQ(r.status, "completed");
  const long beats = r.results.at("beats_to_converge").get<long>();
  EXPECT_GE(beats, 2);
  EXPECT_LE(beats, 6);
  for (const auto& range : r.results.at("healthy_ranges"))
    EXPECT_TRUE(range.at("inside").get<bool>()) << range.at("quantity") << " " << range.at("value") << " outside ["
                                                << range.at("low") << ", " << range.at("high") << "]";
  EXPECT_LT(drift, 1e-12);
  EXPECT_GT(at(r, "min_jacobian"), 0.8);
  EXPECT_LT(at(r, "max_jacobian"), 1.2);
}

}  // namespace
