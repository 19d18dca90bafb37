// Electromechanics scenes at coarse resolution: the active myocardium cube (equilibrium of the held
// state and convergence over three resolutions), Land et al. 2015 problem 2 (apex positions against
// the published ones), the physiological beat of the heart (Land tension, closed-loop circulation:
// ejection, isovolumic phases, conserved blood; the Windkessel option), the potential-driven heart
// on the shipped biventricular mesh and on the third-party heart of ../shared/meshes, three paced
// beats, and stiff and extreme cases.

#include <gtest/gtest.h>

#include <filesystem>

#include <cmath>
#include <iostream>

#include "apps/scenes/electromechanics/em_scenes.hpp"
#include "libsph/core/numerical_failure.hpp"
#include "libsph/io/parameters.hpp"
#include "libsph/reaction/cell_models.hpp"
#include "libsph/reaction/cell_simulation.hpp"
#include "run_scene_for_test.hpp"

namespace {

using test::run_scene;
const auto at = test::result;

TEST(ElectromechanicsValidation, MyocardiumCubeSettlesInEquilibriumAndConverges) {
  std::vector<double> ux;
  for (const long resolution : {8L, 12L, 16L}) {
    const auto r = run_scene(cardiosph::make_myocardium_cube_scene(), {"resolution=" + std::to_string(resolution)},
                       "cube" + std::to_string(resolution));
    const auto u = r.results.at("corner_displacement");
    ux.push_back(u[0].get<double>());
    std::cout << "cube " << resolution << " across: corner u = (" << u[0] << ", " << u[1] << ", " << u[2]
              << "), equilibrium residual " << at(r, "equilibrium_residual") << ", J in [" << at(r, "min_jacobian") << ", "
              << at(r, "max_jacobian") << "], " << r.wall_time_s << " s\n";
    // Bound: the net nodal force of the held state is below 0.8 % of the active-stress force, 3x the
    // measured 0.24-0.27 %. The corner symmetry is a round-off check (the mirror corners move alike).
    EXPECT_LT(at(r, "equilibrium_residual"), 0.008);
    EXPECT_LT(at(r, "corner_symmetry_difference"), 1e-6);
    EXPECT_LT(u[0].get<double>(), -0.1);  // the tension shortens the cube along the fibre
  }
  // Convergence: successive differences shrink.
  const double d1 = std::abs(ux[1] - ux[0]), d2 = std::abs(ux[2] - ux[1]);
  std::cout << "corner ux differences " << d1 << " (8 -> 12), " << d2 << " (12 -> 16)\n";
  EXPECT_LT(d2, d1);
}

TEST(ElectromechanicsValidation, LandProblemTwoApexAtTheDefaultResolution) {
  const auto r = run_scene(cardiosph::make_land_lv_scene(), {}, "land_lv");
  const double endo = at(r, "apex_z_endo_mm"), epi = at(r, "apex_z_epi_mm"), mid = at(r, "apex_z_midwall_mm");
  std::cout << "land-lv problem 2: apex z endo " << endo << " (published -26.6, -26.9 to -26.4), epi " << epi
            << " (-28.3, -28.5 to -28.1), mid-wall " << mid << " (-27.3, -27.6 to -27.1); J in [" << at(r, "min_jacobian")
            << ", " << at(r, "max_jacobian") << "], " << r.wall_time_s << " s\n";
  // Bound: inside the spread of the published codes (Land et al. 2015, figs. 6-7).
  EXPECT_GE(endo, -26.9);
  EXPECT_LE(endo, -26.4);
  EXPECT_GE(epi, -28.5);
  EXPECT_LE(epi, -28.1);
  EXPECT_GE(mid, -27.6);
  EXPECT_LE(mid, -27.1);
}

// Problem 3 (inflation to 15 kPa and contraction at T_a = 60 kPa) at the scene's default dp = 1 mm
// misses the 0.5 mm that it meets at dp = 0.75 mm (ElectromechanicsLong): a regression guard at about
// 1.5x today's distance from the refined published solution (endo -12.35, epi -15.45 mm; Land et
// al. 2015), measured +0.81 and +0.49 mm; README marks the row "not met".
TEST(LandRegression, ProblemThreeApexAtTheDefaultResolution) {
  const auto r = run_scene(cardiosph::make_land_lv_scene(), {"problem=3"}, "land_lv_p3_default");
  const double endo = at(r, "apex_z_endo_mm") - -12.347, epi = at(r, "apex_z_epi_mm") - -15.452;
  std::cout << "land-lv problem 3, dp 1: apex z endo " << at(r, "apex_z_endo_mm") << " (" << endo << " mm from -12.347), epi "
            << at(r, "apex_z_epi_mm") << " (" << epi << " mm from -15.452); published bound 0.5 mm (not met at the endocardium); "
            << "guard 1.2 and 0.75 mm; " << r.wall_time_s << " s\n";
  EXPECT_LT(std::abs(endo), 1.2);
  EXPECT_LT(std::abs(epi), 0.75);
}

// The potential-driven heart (Aliev-Panfilov, Nash-Panfilov tension, no cavity load, clamped base)
// with the solid numerics it was verified with.
std::vector<std::string> potential_driven(std::vector<std::string> more) {
  std::vector<std::string> a{"cell_model=aliev_panfilov", "tension_model=nash_panfilov", "cavity_pressure=none",
                             "base_condition=clamp",      "passive_law=zhang_2021",      "bulk_modulus=100",
                             "mass_scaling=1",            "hourglass_control=penalty",   "artificial_viscosity=0",
                             "stimulus_site=lv-apex",     "acoustic_cfl=0.6"};
  a.insert(a.end(), more.begin(), more.end());
  return a;
}

void expect_sound_heart(const sph::RunReport& r) {
  EXPECT_EQ(r.status, "completed");
  EXPECT_GT(at(r, "min_jacobian"), 0.9);
  EXPECT_LT(at(r, "max_jacobian"), 1.1);
  EXPECT_TRUE(std::isfinite(at(r, "lv_ejection_fraction")));
}

TEST(ElectromechanicsValidation, HeartOnTheThirdPartyMeshActivatesAndContracts) {
  // The same scene on the shipped biventricular mesh: ThreePacedBeatsReturnToRest.
  const std::string mesh = std::string(CARDIOSPH_SHARED_MESHES) + "/biventricular_heart.stl";
  if (!std::filesystem::exists(mesh)) GTEST_SKIP() << "third-party mesh not found: " << mesh;
  const auto r = run_scene(cardiosph::make_heart_scene(),
                     potential_driven({std::string("mesh=") + CARDIOSPH_SHARED_MESHES + "/biventricular_heart.stl", "dp=3",
                                       "relaxation_steps=20", "end_time=120", "output_interval=0"}),
                     "heart_shared");
  std::cout << "shared heart dp 3: " << r.particles.at("heart") << " particles, activated " << at(r, "activated_fraction")
            << ", LV EF " << at(r, "lv_ejection_fraction") << ", RV EF " << at(r, "rv_ejection_fraction") << ", "
            << r.wall_time_s << " s\n";
  expect_sound_heart(r);
  EXPECT_GT(at(r, "activated_fraction"), 0.3);
  EXPECT_GT(at(r, "lv_ejection_fraction"), 0.0);
}

TEST(ElectromechanicsValidation, ThreePacedBeatsReturnToRest) {
  const auto r = run_scene(cardiosph::make_heart_scene(), potential_driven({"preset=coarse", "beats=3", "output_interval=0"}), "heart_beats");
  expect_sound_heart(r);
  const auto& end = r.results.at("end_of_beat");
  const double reference = at(r, "lv_reference_volume_mm3"), peak = at(r, "peak_active_tension_kPa");
  std::cout << "three beats: end-of-beat LV volume " << end.at("lv_volume_mm3") << " (reference " << reference
            << "), max displacement " << end.at("max_displacement_mm") << ", max T_a " << end.at("max_active_tension_kPa")
            << " (peak " << peak << "), mean V " << end.at("mean_potential_mV") << ", energy " << end.at("energy")
            << " (peak strain " << at(r, "peak_strain_energy") << "), LV EF " << at(r, "lv_ejection_fraction")
            << ", " << r.wall_time_s << " s\n";
  ASSERT_EQ(end.at("lv_volume_mm3").size(), 3u);
  for (std::size_t beat = 0; beat < 3; ++beat) {
    // Bounds: back within 0.5 % of the reference cavity volume, tension below 10 % of its peak,
    // mean potential within 2 mV of rest (-80 mV), each beat alike (no drift).
    EXPECT_LT(std::abs(end.at("lv_volume_mm3")[beat].get<double>() - reference), 0.005 * reference) << "beat " << beat;
    EXPECT_LT(end.at("max_active_tension_kPa")[beat].get<double>(), 0.1 * peak) << "beat " << beat;
    EXPECT_LT(std::abs(end.at("mean_potential_mV")[beat].get<double>() + 80), 2.0) << "beat " << beat;
    // Energy (kinetic + passive strain) back below 1 % of the peak strain energy of the beat.
    EXPECT_LT(end.at("energy")[beat].get<double>(), 0.01 * at(r, "peak_strain_energy")) << "beat " << beat;
  }
}

// One coarse beat of the default heart: Land tension from the ten Tusscher-Panfilov calcium, the
// closed loop of Regazzoni et al. 2022, pericardial and base springs. A calibration check: T_ref,
// the Purkinje speed, the arterial impedance and the base springs were tuned on this very beat to the
// targets it is checked against (docs/electromechanics.md, "Calibration"; the heart's report lists
// them under "calibration"), so passing says the calibration holds, not that the heart is validated.
// The conservation checks beside them (blood volume, isovolumic phases, maps, pseudo-ECG) were not
// tuned. The heart's validations against untuned data, the Frank-Starling sweep and the passive
// filling against the human EDPVR, are in test_electromechanics_long.cpp.
TEST(HeartCalibration, CoarseFirstBeatHoldsItsTargetsAndConservesBlood) {
  const auto r = run_scene(cardiosph::make_heart_scene(), {"preset=coarse", "beats=1", "output_interval=0"}, "heart_beat");
  const double edv = at(r, "lv_end_diastolic_volume_mm3"), ef = at(r, "lv_ejection_fraction");
  const double peak = at(r, "lv_peak_pressure_kPa"), activation = at(r, "total_activation_ms");
  const auto blood = r.results.at("total_blood_volume_mm3");
  const double drift = std::abs(blood[1].get<double>() - blood[0].get<double>()) / blood[0].get<double>();
  const auto isovolumic = r.results.at("isovolumic_volume_change_mm3");
  std::cout << "coarse beat: total activation " << activation << " ms (target 60-80), LV EDV " << edv << " mm^3, EF " << ef
            << " (target 0.55-0.65), peak " << peak << " kPa (target 15-17: not met on this first beat; guard 18.25 +- 0.9), EDP "
            << at(r, "lv_end_diastolic_pressure_kPa") << " kPa; RV EF " << at(r, "rv_ejection_fraction") << ", peak "
            << at(r, "rv_peak_pressure_kPa") << " kPa; isovolumic volume change " << isovolumic << " mm^3; blood volume drift "
            << drift << "; J in [" << at(r, "min_jacobian") << ", " << at(r, "max_jacobian") << "], " << r.wall_time_s << " s\n";
  EXPECT_EQ(r.status, "completed");
  // Calibration targets. The EF and the activation were tuned into their windows (measured 62.2 %
  // and 74.4 ms at mass_scaling 4; 62.1 % and 74.8 ms at 16). The first beat's LV peak overshoots
  // the healthy 15-17 kPa while the circulation settles from its starting pressures (measured
  // 18.25 kPa at mass_scaling 4, 18.13 at 16; the converged default beat, 16.5 kPa): guarded at the
  // calibrated value within 5 %, about 1.5x its change from one calibration step to the next.
  EXPECT_GT(ef, 0.55);
  EXPECT_LT(ef, 0.65);
  EXPECT_NEAR(peak, 18.25, 0.9);
  EXPECT_GE(activation, 60.0);
  EXPECT_LE(activation, 80.0);
  EXPECT_GT(at(r, "rv_ejection_fraction"), 0.2);
  // The report lists the calibrated parameters with this run's values (the defaults here).
  const auto& calibration = r.results.at("calibration");
  EXPECT_GE(calibration.size(), 10u);
  for (const auto& c : calibration) EXPECT_EQ(c.at("value").get<double>(), c.at("calibrated").get<double>()) << c.at("parameter");
  // Isovolumic phases: while both valves of a ventricle are closed its volume moves by less than
  // 1 % of the LV EDV (C_c = 20 mm^3/kPa times the pressure change, about 0.25 mL here).
  EXPECT_LT(isovolumic[0].get<double>(), 0.01 * edv);
  EXPECT_LT(isovolumic[1].get<double>(), 0.01 * edv);
  // The closed loop holds its blood to round-off: measured 1e-14 to 1e-16 of 1.5e6 mm^3; the bound,
  // 1e-12, is a round-off bound (its size grows with the number of sub-steps), not 3x the measure.
  EXPECT_LT(drift, 1e-12);
  EXPECT_GT(at(r, "min_jacobian"), 0.8);
  EXPECT_LT(at(r, "max_jacobian"), 1.2);

  // The maps: every particle completes its action potential within the beat. The median APD90 is
  // printed beside the single cell's under the heart's pulse (50 mV/ms for 2 ms) and step: measured
  // 302.4 against 286.8 ms (+5.4 %), where the slab (D = 0.095 mm^2/ms) is within 1.6 %; the coarse
  // heart's fast conduction (D = 1 mm^2/ms) couples its cells ten times more strongly. The APD
  // against the single cell is asserted in the slab and the cable (test_ep_validation.cpp).
  const auto& maps = r.results.at("maps");
  std::vector<double> t, V;
  ASSERT_TRUE(sph::simulate_cell(sph::TenTusscherPanfilov2006{}, sph::ReactionScheme::rbr_qss, 0.1, {0, 2, 50, 0, 1}, 600,
                                 [&](double s, const auto& y) {
                                   t.push_back(s);
                                   V.push_back(y[0]);
                                 }));
  const double cell = sph::measure_action_potential(t, V, 0, 600).duration();
  const double apd = maps.at("apd90_ms").at("median").get<double>();
  const auto& ecg = r.results.at("ecg");
  std::cout << "APD90 median " << apd << " ms over " << maps.at("apd90_ms").at("count") << " particles (single cell " << cell
            << " ms); pseudo-ECG: " << ecg.at("samples") << " samples, QRS " << ecg.at("qrs_duration_ms")
            << " ms, peak-to-peak " << ecg.at("peak_to_peak_mV") << "\n";
  EXPECT_EQ(maps.at("apd90_ms").at("count").get<std::size_t>(), r.particles.at("heart").get<std::size_t>());
  // The 12 leads were sampled over the beat, and each shows a deflection.
  EXPECT_GT(ecg.at("samples").get<int>(), 800);
  for (const auto& [lead, amplitude] : ecg.at("peak_to_peak_mV").items()) EXPECT_GT(amplitude.get<double>(), 0.01) << lead;
}

// The Durrer preset of the Purkinje surrogate (four endocardial sites, Durrer et al. 1970) with
// transmural cell layers: every layer is populated in both ventricles, and the coarse heart
// activates in 61.0 ms (the first 110 ms of the beat). A calibration check: the surrogate's speed was
// tuned to the 60-80 ms window of Durrer et al. 1970 (Circulation 41:899) with the apex start, and
// these sites use the same speed; guarded within 3 ms of today's value, with the window printed.
TEST(HeartCalibration, DurrerSitesActivationTime) {
  const auto r = run_scene(cardiosph::make_heart_scene(),
                     {"preset=coarse", "early_sites=durrer", "cell_heterogeneity=transmural", "end_time=260", "output_interval=0"},
                     "heart_durrer");
  ASSERT_TRUE(r.results.contains("total_activation_ms")) << "not every particle activated";
  const double activation = at(r, "total_activation_ms");
  std::cout << "Durrer sites: " << r.results.at("early_activation_sites").size() << " sites, "
            << at(r, "stimulated_particles") << " particles paced, total activation " << activation
            << " ms (Durrer et al. 1970: 60-80 ms; guard 61.0 +- 3); cell groups " << r.results.at("cell_groups") << ", "
            << r.wall_time_s << " s\n";
  EXPECT_EQ(r.results.at("early_activation_sites").size(), 4u);
  EXPECT_NEAR(activation, 61.0, 3.0);
  for (const char* group : {"endo lv", "mid lv", "epi lv", "endo rv", "mid rv", "epi rv"})
    EXPECT_GT(r.results.at("cell_groups").at(group).at("particles").get<int>(), 0) << group;
}

// The open-loop option: the filled LV ejects into a three-element Windkessel, whose pressure rises
// above its start.
TEST(ElectromechanicsValidation, WindkesselLoadedHeartEjectsAgainstARisingPressure) {
  const auto r = run_scene(cardiosph::make_heart_scene(),
                     {"preset=coarse", "circulation_model=windkessel", "end_time=450", "output_interval=0"}, "heart_windkessel");
  std::cout << "windkessel: LV EDV " << at(r, "lv_end_diastolic_volume_mm3") << " (unloaded " << at(r, "lv_reference_volume_mm3")
            << "), ESV " << at(r, "lv_end_systolic_volume_mm3") << ", peak pressure " << at(r, "lv_peak_pressure_kPa") << " kPa, "
            << r.wall_time_s << " s\n";
  EXPECT_EQ(r.status, "completed");
  EXPECT_GT(at(r, "lv_end_diastolic_volume_mm3"), 1.1 * at(r, "lv_reference_volume_mm3"));  // filled by the preload
  EXPECT_LT(at(r, "lv_end_systolic_volume_mm3"), 0.9 * at(r, "lv_end_diastolic_volume_mm3"));
  EXPECT_GT(at(r, "lv_peak_pressure_kPa"), 10.7);  // above the Windkessel's starting 10.7 kPa
}

// A tension ten times too large, a very stiff bulk modulus, and valves that never open (arterial
// pressures of 150 and 60 kPa, above what the ventricles reach isovolumically; at 60 kPa the LV
// reached 49 kPa and opened its valve; run to 450 ms, 300 ms into the beat, past the peak tension): each run either completes with finite pressures and J > 0 or
// stops with the numerical-failure diagnostic, never with NaN results.
TEST(ElectromechanicsValidation, StiffAndExtremeHeartEitherCompletesOrStopsWithADiagnostic) {
  const std::vector<std::vector<std::string>> cases{
      {"preset=coarse", "land_reference_tension=6000", "end_time=350", "output_interval=0"},
      {"preset=coarse", "bulk_modulus=10000", "end_time=250", "output_interval=0"},
      {"preset=coarse", "circulation_initial_systemic_arterial_pressure=150", "circulation_initial_pulmonary_arterial_pressure=60",
       "end_time=450", "output_interval=0"},
  };
  for (const auto& c : cases) {
    try {
      const auto r = run_scene(cardiosph::make_heart_scene(), c, "heart_extreme");
      std::cout << c[1] << ": completed, J in [" << at(r, "min_jacobian") << ", " << at(r, "max_jacobian") << "], LV EF "
                << at(r, "lv_ejection_fraction") << ", LV peak " << at(r, "lv_peak_pressure_kPa") << " kPa, " << r.wall_time_s
                << " s\n";
      EXPECT_GT(at(r, "min_jacobian"), 0);
      EXPECT_TRUE(std::isfinite(at(r, "lv_ejection_fraction")));
      EXPECT_TRUE(std::isfinite(at(r, "lv_peak_pressure_kPa")));
      EXPECT_TRUE(std::isfinite(at(r, "peak_kinetic_energy")));
      if (c[1].find("arterial") != std::string::npos) EXPECT_LT(at(r, "lv_ejection_fraction"), 0.05) << "the aortic valve opened";
    } catch (const sph::NumericalFailure& failure) {
      std::cout << c[1] << ": stopped: " << failure.what() << '\n';
      EXPECT_NE(std::string(failure.what()).find("numerical failure"), std::string::npos);
    }
  }
}

}  // namespace
