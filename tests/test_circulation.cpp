// The 0D circulation (cardio/circulation.hpp): the closed loop of Regazzoni et al. 2022 with 0D
// ventricles (blood volume conserved to round-off, a periodic beat in the healthy ranges), the
// isovolumic phases of a coupled ventricle (V_b held, V_3D moving by C_c times the pressure change),
// the three-element Windkessel against its closed-form solution for a constant ejection flow,
// stability at a 10 ms step with the stiff coupled cavity, the refusal of bad settings, and the
// coupling to 3D cavities (cardio/circulation_coupling.hpp): preload, start and volume penalty.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "cardio/beat_metrics.hpp"
#include "cardio/circulation.hpp"
#include "cardio/circulation_coupling.hpp"
#include "tests/tetrahedral_cavity.hpp"
#include "libsph/io/parameters.hpp"

namespace {

using cardio::Circulation;
using cardio::CirculationModel;
using cardio::CirculationSettings;
using cardio::Valve;
using cardio::Ventricle;
using cardio::VentricleMode;
constexpr double mmHg = cardio::circulation_units::mmHg, mL = cardio::circulation_units::mL;

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Extremes of one beat.
struct Beat {
  double p_lv_max = -1e300, v_lv_max = -1e300, v_lv_min = 1e300;
  double p_ao_max = -1e300, p_ao_min = 1e300;
  double p_rv_max = -1e300, v_rv_max = -1e300, v_rv_min = 1e300;
  double p_pa_max = -1e300, p_pa_min = 1e300;
  void record(const Circulation& c) {
    p_lv_max = std::max(p_lv_max, c.pressure(Ventricle::left));
    v_lv_max = std::max(v_lv_max, c.ventricle_blood_volume(Ventricle::left));
    v_lv_min = std::min(v_lv_min, c.ventricle_blood_volume(Ventricle::left));
    p_ao_max = std::max(p_ao_max, c.arterial_pressure(Ventricle::left));
    p_ao_min = std::min(p_ao_min, c.arterial_pressure(Ventricle::left));
    p_rv_max = std::max(p_rv_max, c.pressure(Ventricle::right));
    v_rv_max = std::max(v_rv_max, c.ventricle_blood_volume(Ventricle::right));
    v_rv_min = std::min(v_rv_min, c.ventricle_blood_volume(Ventricle::right));
    p_pa_max = std::max(p_pa_max, c.arterial_pressure(Ventricle::right));
    p_pa_min = std::min(p_pa_min, c.arterial_pressure(Ventricle::right));
  }
};

TEST(Circulation, ClosedLoopWithElastanceVentriclesConservesBloodAndBeatsInHealthyRanges) {
  const CirculationSettings s;  // closed loop, both ventricles 0D, Regazzoni et al. defaults
  Circulation c(s);
  const double V_total = c.total_blood_volume();
  const double dt = 0.1, T = s.heart_period;
  const int beats = 10, steps_per_beat = static_cast<int>(std::lround(T / dt));
  double worst_drift = 0, t = 0;
  Beat previous, last;
  for (int beat = 0; beat < beats; ++beat) {
    Beat current;
    for (int k = 0; k < steps_per_beat; ++k) {
      c.advance(t, dt);
      t += dt;
      worst_drift = std::max(worst_drift, std::abs(c.total_blood_volume() - V_total) / V_total);
      current.record(c);
    }
    previous = last;
    last = current;
  }
  const double SV = last.v_lv_max - last.v_lv_min, EF = SV / last.v_lv_max, SV_rv = last.v_rv_max - last.v_rv_min;
  std::printf("closed loop, %d beats of %.0f ms: total blood volume %.6f mL, largest relative drift %.2e\n", beats, T,
              V_total / mL, worst_drift);
  std::printf("  LV: p_max %.1f mmHg, EDV %.1f mL, ESV %.1f mL, SV %.1f mL, EF %.1f %%; aorta %.1f/%.1f mmHg\n",
              last.p_lv_max / mmHg, last.v_lv_max / mL, last.v_lv_min / mL, SV / mL, 100 * EF, last.p_ao_max / mmHg,
              last.p_ao_min / mmHg);
  std::printf("  RV: p_max %.1f mmHg, EDV %.1f mL, SV %.1f mL; pulmonary artery %.1f/%.1f mmHg; CO %.2f L/min\n",
              last.p_rv_max / mmHg, last.v_rv_max / mL, SV_rv / mL, last.p_pa_max / mmHg, last.p_pa_min / mmHg,
              SV / mL * 60000 / T / 1000);
  std::printf("  periodicity: LV EDV of the last two beats %.3f and %.3f mL; unsettled valve sub-steps %ld\n",
              previous.v_lv_max / mL, last.v_lv_max / mL, c.unsettled_valve_steps());

  EXPECT_LT(worst_drift, 1e-12);
  // Periodic: the last two beats agree to 1 % in EDV and peak pressure.
  EXPECT_NEAR(last.v_lv_max, previous.v_lv_max, 0.01 * last.v_lv_max);
  EXPECT_NEAR(last.p_lv_max, previous.p_lv_max, 0.01 * last.p_lv_max);
  // Healthy adult ranges at rest (bounds of this test): LV peak 90-150 mmHg, aortic systolic 90-150
  // and diastolic 50-95 mmHg, EF 40-75 %, SV 40-110 mL; the two ventricles eject the same volume per
  // beat in the periodic state. The right side is bounded looser, RV peak and pulmonary systolic
  // 15-50 mmHg: the default pulmonary resistances R_AR_PUL = R_VEN_PUL = 0.1625 mmHg s/mL of the
  // reference code drop about 30 mmHg at 5.5 L/min, so its pulmonary artery sits near 40/35 mmHg,
  // above the healthy 15-30/4-12 mmHg.
  EXPECT_GT(last.p_lv_max, 90 * mmHg);
  EXPECT_LT(last.p_lv_max, 150 * mmHg);
  EXPECT_GT(last.p_ao_max, 90 * mmHg);
  EXPECT_LT(last.p_ao_max, 150 * mmHg);
  EXPECT_GT(last.p_ao_min, 50 * mmHg);
  EXPECT_LT(last.p_ao_min, 95 * mmHg);
  EXPECT_GT(EF, 0.40);
  EXPECT_LT(EF, 0.75);
  EXPECT_GT(SV, 40 * mL);
  EXPECT_LT(SV, 110 * mL);
  EXPECT_GT(last.p_rv_max, 15 * mmHg);
  EXPECT_LT(last.p_rv_max, 50 * mmHg);
  EXPECT_GT(last.p_pa_max, 15 * mmHg);
  EXPECT_LT(last.p_pa_max, 50 * mmHg);
  EXPECT_NEAR(SV_rv, SV, 0.02 * SV);

  // One row per column, valve states 0/1.
  const auto names = c.columns();
  const auto row = c.row();
  ASSERT_EQ(names.size(), row.size());
  for (const char* name : {"time", "p_lv", "v_lv", "p_ar_sys", "q_av", "q_ven_pul", "valve_av_open", "v_total"})
    EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << name;
  const auto at = [&](const std::string& name) { return row[std::find(names.begin(), names.end(), name) - names.begin()]; };
  EXPECT_TRUE(at("valve_mv_open") == 0 || at("valve_mv_open") == 1);
  EXPECT_EQ(at("v_total"), c.total_blood_volume());
}

// A prescribed 3D volume V_3D(t) of the coupled LV against the LV Windkessel (filling 1.2 kPa,
// aorta from 80 mmHg): slow contraction (isovolumic until the aortic valve opens), ejection, slow
// relaxation (isovolumic until the mitral valve opens), filling.
double prescribed_lv_volume(double t) {
  const double V = 120 * mL;
  const double rates[][2] = {{60, -4}, {300, -250}, {420, 4}, {600, 300}};  // {end [ms], dV/dt [mm^3/ms]}
  double volume = V, start = 0;
  for (const auto& [end, rate] : rates) {
    volume += rate * (std::min(t, end) - start);
    if (t <= end) break;
    start = end;
  }
  return volume;
}

TEST(Circulation, CoupledVentricleHoldsItsBloodWhileBothValvesAreClosed) {
  CirculationSettings s;
  s.model = CirculationModel::windkessel;
  s.lv_mode = VentricleMode::coupled;
  Circulation c(s);
  const double p_fill = s.lv_windkessel.filling_pressure, C_c = s.cavity_compliance, R_closed = s.valve_closed_resistance;
  c.initialise(0, prescribed_lv_volume(0), 0, p_fill, 0);
  const double dt = 0.1;
  // An isovolumic interval: both LV valves closed over whole coupling steps.
  struct Interval {
    double t0 = 0, t1 = 0, V_b0 = 0, V3d0 = 0, V3d1 = 0, p0 = 0, p1 = 0, leak_bound = 0, worst_V_b = 0, worst_V3d = 0;
  };
  std::vector<Interval> intervals;
  bool closed = false, aortic_opened = false, mitral_reopened = false;
  double t = 0;
  for (int k = 0; k < 6000; ++k) {
    const bool closed_before = !c.valve_open(Valve::mitral) && !c.valve_open(Valve::aortic);
    const double V_b_before = c.ventricle_blood_volume(Ventricle::left), V3d_before = c.ventricle_3d_volume(Ventricle::left),
                 p_before = c.pressure(Ventricle::left);
    c.advance(t, dt, prescribed_lv_volume(t + dt), 0);
    t += dt;
    const bool closed_after = !c.valve_open(Valve::mitral) && !c.valve_open(Valve::aortic);
    aortic_opened = aortic_opened || c.valve_open(Valve::aortic);
    mitral_reopened = mitral_reopened || (aortic_opened && c.valve_open(Valve::mitral));
    if (!(closed_before && closed_after)) {
      closed = false;
      continue;
    }
    if (!closed) {
      intervals.push_back({t - dt, t, V_b_before, V3d_before, V3d_before, p_before, p_before, 0, 0, 0});
      closed = true;
    }
    auto& iv = intervals.back();
    const double p = c.pressure(Ventricle::left), p_ao = c.arterial_pressure(Ventricle::left);
    // Leakage over the step through the closed mitral (p_fill - p) and aortic (p - p_C) valves.
    iv.leak_bound += dt * (std::abs(p_fill - p) + std::abs(p - p_ao)) / R_closed;
    const double dV_b = c.ventricle_blood_volume(Ventricle::left) - iv.V_b0;
    const double dV3d = c.ventricle_3d_volume(Ventricle::left) - iv.V3d0;
    // p = p_ref + (V_b - V_3D)/C_c, so Delta V_3D + C_c Delta p = Delta V_b: the leakage alone.
    iv.worst_V_b = std::max(iv.worst_V_b, std::abs(dV_b));
    iv.worst_V3d = std::max(iv.worst_V3d, std::abs(dV3d + C_c * (p - iv.p0)));
    iv.t1 = t;
    iv.p1 = p;
    iv.V3d1 = c.ventricle_3d_volume(Ventricle::left);
  }
  // The isovolumic contraction from t = 0 and the isovolumic relaxation after t = 300 ms, each
  // longer than 20 ms (closed intervals of a few steps around valve events are checked as well).
  int long_intervals = 0;
  for (const auto& iv : intervals) {
    const double bound = 1.01 * iv.leak_bound + 1e-9 * iv.V_b0;  // leakage plus round-off
    std::printf("both LV valves closed %.1f-%.1f ms: p %.2f -> %.2f kPa, V_3D moved %.2f mm^3 (-C_c dp = %.2f mm^3), "
                "|dV_b| <= %.2e, |dV_3D + C_c dp| <= %.2e mm^3, leakage bound %.2e mm^3\n",
                iv.t0, iv.t1, iv.p0, iv.p1, iv.V3d1 - iv.V3d0, -C_c * (iv.p1 - iv.p0), iv.worst_V_b, iv.worst_V3d,
                iv.leak_bound);
    EXPECT_LE(iv.worst_V_b, bound);
    EXPECT_LE(iv.worst_V3d, bound);
    if (iv.t1 - iv.t0 > 20) {
      ++long_intervals;
      EXPECT_GT(std::abs(iv.p1 - iv.p0), 8) << "an isovolumic phase spans most of the pressure range";
    }
  }
  EXPECT_EQ(long_intervals, 2);
  // Between them the LV ejects through the aortic valve and then fills through the mitral valve.
  EXPECT_TRUE(aortic_opened);
  EXPECT_TRUE(mitral_reopened);
}

// Windkessel driven by a constant ejection flow Q from t = 0 (aortic valve open throughout):
//   p_C(t) = p_dist + Q R + (p_C(0) - p_dist - Q R) exp(-t / (R C)),  p_ao = p_C + Z Q.
double windkessel_error(double max_step, double& p_end, double& p_exact_end) {
  CirculationSettings s;
  s.model = CirculationModel::windkessel;
  s.lv_mode = VentricleMode::coupled;
  // A nearly incompressible cavity and a tight mitral valve, so that the aortic flow equals the
  // ejection Q to about 1e-8 (the cavity compliance takes C_c dp/dt of it, the closed mitral valve
  // leaks (p - p_fill) / R_closed back to the filling reservoir).
  s.cavity_compliance = 0.01;
  s.valve_closed_resistance = 1e9;
  s.max_step = max_step;
  const auto& w = s.lv_windkessel;
  const double Q = 250, V0 = 130 * mL, p_C0 = s.initial_systemic_arterial_pressure;
  Circulation c(s);
  // The LV starts at the pressure that drives Q through the open valve and Z.
  c.initialise(0, V0, 0, p_C0 + (s.aortic_resistance + w.characteristic_impedance) * Q, 0);
  const double dt = 1, tau = w.resistance * w.compliance, p_inf = w.distal_pressure + Q * w.resistance;
  double worst = 0, t = 0;
  for (int k = 0; k < 300; ++k) {
    c.advance(t, dt, V0 - Q * (t + dt), 0);
    t += dt;
    const double exact = p_inf + (p_C0 - p_inf) * std::exp(-t / tau) + w.characteristic_impedance * Q;
    worst = std::max(worst, std::abs(c.arterial_pressure(Ventricle::left) - exact));
    p_end = c.arterial_pressure(Ventricle::left);
    p_exact_end = exact;
    EXPECT_TRUE(c.valve_open(Valve::aortic)) << "t = " << t;
  }
  return worst;
}

TEST(Circulation, WindkesselFollowsTheClosedFormForAConstantEjectionFlow) {
  double p_end = 0, p_exact = 0, p_end_fine = 0, p_exact_fine = 0;
  const double error = windkessel_error(0.1, p_end, p_exact);
  const double error_fine = windkessel_error(0.05, p_end_fine, p_exact_fine);
  std::printf("Windkessel, Q = 250 mm^3/ms for 300 ms: p_ao %.4f kPa (closed form %.4f) at 300 ms; largest error "
              "%.2e kPa at h = 0.1 ms, %.2e kPa at h = 0.05 ms (ratio %.2f)\n",
              p_end, p_exact, error, error_fine, error / error_fine);
  // Bound 1e-3 kPa (0.0075 mmHg) on a rise of about 4 kPa; backward Euler is first order.
  EXPECT_LT(error, 1e-3);
  EXPECT_GT(error / error_fine, 1.8);
  EXPECT_LT(error / error_fine, 2.2);
}

TEST(Circulation, LargeStepsWithAStiffCoupledVentricleStayFiniteAndConserveVolume) {
  CirculationSettings s;  // closed loop
  s.lv_mode = VentricleMode::coupled;
  s.max_step = 10;  // no sub-steps: dt / (R_min C_c) = 10 / 0.02 = 500
  Circulation c(s);
  // Mock 3D volume: the LV elastance chamber's activation empties 60 mL of 120 mL.
  auto V3d = [&s](double time) { return 120 * mL - 60 * mL * s.lv.activation(time, s.heart_period); };
  c.initialise(0, V3d(0), 0, 1.0, 0);
  const double V_total = c.total_blood_volume(), dt = 10;
  double worst_drift = 0, p_max = 0, t = 0;
  for (int k = 0; k < 3 * 80; ++k) {
    c.advance(t, dt, V3d(t + dt), 0);
    t += dt;
    for (double v : c.row()) ASSERT_TRUE(std::isfinite(v)) << "t = " << t;
    worst_drift = std::max(worst_drift, std::abs(c.total_blood_volume() - V_total) / V_total);
    p_max = std::max(p_max, c.pressure(Ventricle::left));
  }
  std::printf("closed loop, coupled LV, dt = 10 ms (3 beats): largest relative volume drift %.2e, LV p_max %.1f mmHg\n",
              worst_drift, p_max / mmHg);
  EXPECT_LT(worst_drift, 1e-12);
  EXPECT_LT(p_max, 300 * mmHg);

  // A 3D volume that overflows the cavity pressure: stopped, naming the compartment and the time.
  try {
    c.advance(t, dt, 1e308, 0);
    ADD_FAILURE() << "no error for a non-finite state";
  } catch (const std::runtime_error& e) {
    // The first compartment found non-finite (the whole loop is overflowed by then) and the time.
    EXPECT_TRUE(contains(e.what(), "is not finite at t = 2410 ms")) << e.what();
  }
}

TEST(Circulation, BadSettingsAreRefusedNamingTheSetting) {
  auto message = [](CirculationSettings s) -> std::string {
    try {
      Circulation c(s);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  CirculationSettings s;
  s.systemic_arterial.compliance = -1;
  EXPECT_TRUE(contains(message(s), "circulation_systemic_arterial_compliance")) << message(s);
  s = {};
  s.aortic_resistance = 0;
  EXPECT_TRUE(contains(message(s), "circulation_aortic_resistance")) << message(s);
  s = {};
  s.lv_windkessel.resistance = 0;
  EXPECT_TRUE(contains(message(s), "circulation_lv_windkessel_resistance")) << message(s);
  s = {};
  s.valve_closed_resistance = 1e-4;  // below the open resistances
  EXPECT_TRUE(contains(message(s), "circulation_valve_closed_resistance")) << message(s);
  s = {};
  s.la.contraction_duration = 700;  // 700 + 136 ms > 800 ms
  EXPECT_TRUE(contains(message(s), "circulation_la_contraction_duration")) << message(s);
  s = {};
  s.cavity_compliance = 0;
  EXPECT_TRUE(contains(message(s), "circulation_cavity_compliance")) << message(s);

  // The parameters refuse them before anything runs.
  CirculationSettings declared;
  sph::Parameters p;
  cardio::declare_parameters(p, declared);
  for (const char* key : {"circulation_systemic_venous_compliance", "circulation_mitral_resistance",
                          "circulation_cavity_compliance", "circulation_pulmonary_arterial_inductance"}) {
    try {
      p.set(key, key == std::string("circulation_mitral_resistance") ? "0" : "-5", "--set");
      ADD_FAILURE() << key << " accepted";
    } catch (const sph::ParameterError& e) {
      EXPECT_TRUE(contains(e.what(), key)) << e.what();
    }
  }
  p.set("circulation_model", "windkessel", "--set");
  p.set("circulation_lv_mode", "coupled", "--set");
  EXPECT_EQ(declared.model, CirculationModel::windkessel);
  EXPECT_EQ(declared.lv_mode, VentricleMode::coupled);
  EXPECT_NO_THROW(p.check());

  // A coupled ventricle needs its initial 3D volume and pressure first.
  Circulation coupled(declared);
  EXPECT_THROW(coupled.advance(0, 0.1, 120 * mL, 0), std::logic_error);
  coupled.initialise(0, 120 * mL, 0, 1, 0);
  EXPECT_THROW(coupled.advance(0, 0.1), std::invalid_argument);  // no 3D volume given
  EXPECT_THROW(coupled.advance(5, 0.1, 120 * mL, 0), std::invalid_argument);  // not at the current time
  EXPECT_NO_THROW(coupled.advance(0, 0.1, 120 * mL, 0));
}

}  // namespace

// The PV measures of one beat (cardio/beat_metrics.hpp) on a synthetic rectangular loop sampled
// every 0.1 ms: filling 120 -> 150 mL at 1 kPa, isovolumic rise to 15 kPa over 50 ms, ejection to
// 60 mL at 15 kPa, isovolumic fall over 70 ms. dP/dt over the 2 ms window is the ramps' slope.
TEST(Circulation, BeatMeasuresOfARectangularLoop) {
  cardio::BeatRecorder beat;
  double t = 0;
  auto segment = [&](double duration, double v0, double v1, double p0, double p1) {
    const int n = int(std::lround(duration / 0.1));
    for (int k = 1; k <= n; ++k) {
      const double f = double(k) / n;
      t += 0.1;
      beat.add(t, v0 + f * (v1 - v0), p0 + f * (p1 - p0));
    }
  };
  beat.add(0, 120 * mL, 1);
  segment(300, 120 * mL, 150 * mL, 1, 1);
  segment(50, 150 * mL, 150 * mL, 1, 15);
  segment(250, 150 * mL, 60 * mL, 15, 15);
  segment(70, 60 * mL, 60 * mL, 15, 1);
  const auto m = beat.finish();
  std::printf("[ Beat     ] EDV %.1f mL, ESV %.1f mL, EF %.4f, EDP %.2f kPa, peak %.2f kPa, dP/dt %.4f / %.4f kPa/ms\n",
              m.edv / mL, m.esv / mL, m.ejection_fraction, m.edp, m.peak_pressure, m.dpdt_max, m.dpdt_min);
  EXPECT_DOUBLE_EQ(m.edv, 150 * mL);
  EXPECT_DOUBLE_EQ(m.esv, 60 * mL);
  EXPECT_NEAR(m.ejection_fraction, 0.6, 1e-12);
  EXPECT_NEAR(m.edp, 1, 1e-12);
  EXPECT_NEAR(m.peak_pressure, 15, 1e-12);
  EXPECT_NEAR(m.dpdt_max, 14.0 / 50, 1e-9);
  EXPECT_NEAR(m.dpdt_min, -14.0 / 70, 1e-9);
}

// The circulation coupled to two 3D cavities (cardio/circulation_coupling.hpp): the preload ramp,
// the start with V_b = V_3D at the preload pressures, the coupled steps and the volume penalty the
// cavities take, in the stage that add_circulation_coupling declares.
namespace coupling {

using tetrahedral_cavity::Block;
using tetrahedral_cavity::corners;
using tetrahedral_cavity::tetrahedron;
using Vec3 = sph::Vec<3>;

std::vector<cardio::CavitySurface> lv_and_rv(const Block& b) {
  return {tetrahedron(b.body, corners(b.body), cardio::label_lv_endo),
          tetrahedron(b.body, corners(b.body, Vec3(1, 1, 1)), cardio::label_rv_endo)};
}

const cardio::CavityPressureSettings preload{cardio::CavityPressureMode::circulation, 1.2, 0.4, 5};

TEST(CirculationCoupling, RefusesCavitiesWithoutBothEndocardia) {
  Block b;
  cardio::Cavities lv_only(b.solid, {tetrahedron(b.body, corners(b.body), cardio::label_lv_endo)}, preload);
  try {
    cardio::CirculationCoupling(CirculationSettings{}, 800, preload, 10, lv_only);
    FAIL() << "no RV endocardium accepted";
  } catch (const sph::ParameterError& e) {
    EXPECT_TRUE(contains(e.what(), "no RV endocardium")) << e.what();
  }
}

TEST(CirculationCoupling, PreloadRampsThenTheCirculationStartsAndLoadsTheCavitiesThroughThePenalty) {
  Block b;
  cardio::Cavities cavities(b.solid, lv_and_rv(b), preload);
  cardio::CirculationCoupling coupling(CirculationSettings{}, 800, preload, 10, cavities);
  EXPECT_FALSE(coupling.started());
  EXPECT_EQ(coupling.circulation().settings().lv_mode, VentricleMode::coupled);
  EXPECT_EQ(coupling.circulation().ventricle_3d_volume(Ventricle::left), cavities.volume(coupling.lv()));
  sph::TimeStepper stepper(0, 12);
  stepper.add_stage(sph::make_stage("tissue", [] { return sph::Real(3); }, [](sph::Real, sph::Real) {}));
  cardio::add_circulation_coupling(stepper, coupling, cavities);
  std::vector<double> lv_pressure;
  std::vector<bool> started, advanced;
  stepper.add_step_callback([&](const sph::StepInfo& s) {
    lv_pressure.push_back(cavities.pressure(coupling.lv()).at(s.time));
    started.push_back(coupling.started());
    advanced.push_back(coupling.advanced());
    if (s.time == 2.5) EXPECT_NEAR(cavities.pressure(coupling.rv()).at(s.time), 0.4 * 2.5 / 5, 1e-15);
  });
  stepper.run();
  // Steps end at 2.5, 5, 7.5, 10 (the start, an event) and 12.
  ASSERT_EQ(lv_pressure.size(), 5u);
  EXPECT_NEAR(lv_pressure[0], 1.2 * 2.5 / 5, 1e-15);
  EXPECT_EQ(lv_pressure[2], 1.2);
  EXPECT_EQ(started, (std::vector<bool>{false, false, false, true, true}));
  EXPECT_EQ(advanced, (std::vector<bool>{false, false, false, false, true}));
  EXPECT_NEAR(coupling.circulation().time(), 2, 1e-12);  // its time 0 is the start
  EXPECT_NEAR(coupling.initial_blood_volume(), coupling.circulation().total_blood_volume(), 1e-9 * coupling.initial_blood_volume());
  // Each cavity takes p = p_ref + (V_b - V) / C_c of its ventricle.
  for (const auto& [c, v] : {std::pair{coupling.lv(), Ventricle::left}, std::pair{coupling.rv(), Ventricle::right}}) {
    const auto& penalty = cavities.penalty(c);
    ASSERT_TRUE(penalty.has_value());
    const double V = cavities.volume(c);
    EXPECT_EQ(penalty->reference_pressure + (penalty->blood_volume - V) / penalty->compliance,
              coupling.circulation().pressure_at_volume(v, V));
    EXPECT_EQ(cavities.pressure(c).at(12), coupling.circulation().pressure(v));
  }
}

TEST(CirculationCoupling, StartsAtOnceWithoutPreloadAtTheCavityPressures) {
  Block b;
  cardio::Cavities cavities(b.solid, lv_and_rv(b), preload);
  const cardio::CirculationCoupling coupling(CirculationSettings{}, 800, preload, 0, cavities);
  EXPECT_TRUE(coupling.started());
  EXPECT_NEAR(coupling.circulation().pressure(Ventricle::left), 1.2, 1e-12);
  EXPECT_NEAR(coupling.circulation().pressure(Ventricle::right), 0.4, 1e-12);
  EXPECT_TRUE(cavities.penalty(coupling.lv()).has_value());
}

}  // namespace coupling
