#include "apps/scenes/electromechanics/heart_output.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <sstream>

#include "apps/plot.hpp"
#include "libsph/io/atomic_file.hpp"
#include "libsph/io/parameters.hpp"

namespace cardiosph {
namespace {

nlohmann::json measures_json(const cardio::BeatMeasures& m) {
  return {{"edv_mm3", m.edv}, {"esv_mm3", m.esv}, {"stroke_volume_mm3", m.stroke_volume}, {"ejection_fraction", m.ejection_fraction},
          {"edp_kPa", m.edp}, {"peak_pressure_kPa", m.peak_pressure}, {"dpdt_max_kPa_per_ms", m.dpdt_max},
          {"dpdt_min_kPa_per_ms", m.dpdt_min}};
}

double relative_change(const cardio::BeatMeasures& a, const cardio::BeatMeasures& b) {
  return std::abs(b.stroke_volume - a.stroke_volume) / std::max(std::abs(b.stroke_volume), 1e-12);
}

}  // namespace

HeartBeats::HeartBeats(cardio::CirculationCoupling& coupling, sph::TimeStepper& stepper, sph::RunHarness& run,
                       const HeartParameters& p, bool quiet)
    : coupling_(coupling), p_(p), quiet_(quiet) {
  stepper.add_step_callback([this, &stepper](const sph::StepInfo& s) { after_step(s, stepper); });
  run.add_state("circulation", [this](sph::StateArchive& a) { checkpoint(a); });
  auto columns = coupling_.circulation().columns();
  columns.erase(columns.begin());  // its own time: the run's time is the first column
  run.add_time_series("circulation.csv", columns, Real(p.sample_interval / 4), [this](const sph::StepInfo&) {
    auto row = coupling_.circulation().row();
    row.erase(row.begin());
    return row;
  });
}

void HeartBeats::checkpoint(sph::StateArchive& a) {
  coupling_.checkpoint(a);
  for (int k = 0; k < 2; ++k) {
    auto recorder = a.part("recorder" + std::to_string(k));
    recorders_[k].checkpoint(recorder);
  }
  a.io("beats", beats_);
  a.io("converged_at", converged_at_);
  a.io("was_closed", was_closed_);
  a.io("closed_volume", closed_volume_);
  a.io("isovolumic_change", isovolumic_change_);
}

void HeartBeats::after_step(const sph::StepInfo& s, sph::TimeStepper& stepper) {
  if (!coupling_.advanced()) return;
  const auto& circulation = coupling_.circulation();
  const double t = s.time, tolerance = 1e-9 * p_.cycle_length;
  using cardio::Ventricle;
  const double v[2] = {circulation.ventricle_3d_volume(Ventricle::left), circulation.ventricle_3d_volume(Ventricle::right)};
  recorders_[0].add(t, v[0], circulation.pressure(Ventricle::left));
  recorders_[1].add(t, v[1], circulation.pressure(Ventricle::right));
  // Isovolumic phases: the largest change of a cavity's volume while both of its valves are closed.
  using V = cardio::Valve;
  const bool closed[2] = {!circulation.valve_open(V::mitral) && !circulation.valve_open(V::aortic),
                          !circulation.valve_open(V::tricuspid) && !circulation.valve_open(V::pulmonary)};
  for (int k = 0; k < 2; ++k) {
    if (closed[k] && was_closed_[k]) isovolumic_change_[k] = std::max(isovolumic_change_[k], std::abs(v[k] - closed_volume_[k]));
    if (closed[k] && !was_closed_[k]) closed_volume_[k] = v[k];
    was_closed_[k] = closed[k];
  }
  const double beat_end = coupling_.start_time() + double(beats_.size() + 1) * p_.cycle_length;
  if (t < beat_end - tolerance) return;
  beats_.push_back({recorders_[0].finish(), recorders_[1].finish()});
  const auto& b = beats_.back();
  if (!quiet_)
    std::cout << "beat " << beats_.size() << ": LV EDV " << b[0].edv / 1000 << " mL, EF " << 100 * b[0].ejection_fraction
              << " %, peak " << b[0].peak_pressure << " kPa; RV EF " << 100 * b[1].ejection_fraction << " %, peak "
              << b[1].peak_pressure << " kPa\n" << std::flush;
  if (beats_.size() >= 2 && converged_at_ < 0 && p_.beat_tolerance > 0) {
    const auto& a = beats_[beats_.size() - 2];
    if (relative_change(a[0], b[0]) < p_.beat_tolerance && relative_change(a[1], b[1]) < p_.beat_tolerance) {
      converged_at_ = long(beats_.size());
      stepper.stop_after_this_step();
    }
  }
}

void HeartBeats::report(sph::RunReport& r) const {
  nlohmann::json beats = nlohmann::json::array();
  for (const auto& beat : beats_) {
    nlohmann::json b;
    for (int v = 0; v < 2; ++v) b[v == 0 ? "lv" : "rv"] = measures_json(beat[v]);
    beats.push_back(b);
  }
  r.results["beats"] = beats;
  r.results["beats_run"] = beats_.size();
  r.results["beats_to_converge"] = converged_at_;
  r.results["beat_tolerance"] = p_.beat_tolerance;
  if (beats_.size() >= 2) {
    const auto& a = beats_[beats_.size() - 2];
    const auto& b = beats_.back();
    r.results["stroke_volume_change_last_beat"] = std::max(relative_change(a[0], b[0]), relative_change(a[1], b[1]));
  }
  r.results["total_blood_volume_mm3"] = {coupling_.initial_blood_volume(), coupling_.circulation().total_blood_volume()};
  r.results["unsettled_valve_steps"] = coupling_.circulation().unsettled_valve_steps();
  r.results["isovolumic_volume_change_mm3"] = {isovolumic_change_[0], isovolumic_change_[1]};
  if (beats_.empty()) return;
  // The last beat under the names of the whole-run measures, and its place in the healthy ranges.
  const auto& last = beats_.back();
  for (int v = 0; v < 2; ++v) {
    const std::string name = v == 0 ? "lv" : "rv";
    r.results[name + "_end_diastolic_volume_mm3"] = last[v].edv;
    r.results[name + "_end_systolic_volume_mm3"] = last[v].esv;
    r.results[name + "_stroke_volume_mm3"] = last[v].stroke_volume;
    r.results[name + "_ejection_fraction"] = last[v].ejection_fraction;
    r.results[name + "_peak_pressure_kPa"] = last[v].peak_pressure;
    r.results[name + "_end_diastolic_pressure_kPa"] = last[v].edp;
    r.results[name + "_dpdt_max_kPa_per_ms"] = last[v].dpdt_max;
    r.results[name + "_dpdt_min_kPa_per_ms"] = last[v].dpdt_min;
  }
  // Healthy adult targets: LV EF 55-65 % (inside the normal 52-74 % of Lang et al. 2015,
  // J. Am. Soc. Echocardiogr. 28:1), LV peak systolic pressure 15-17 kPa (110-130 mmHg), LV
  // end-diastolic pressure 1-1.6 kPa (8-12 mmHg) and RV peak systolic pressure 3-4 kPa (22-30
  // mmHg), the textbook values of a resting adult.
  nlohmann::json ranges = nlohmann::json::array();
  auto range = [&](const char* what, double value, double low, double high) {
    ranges.push_back({{"quantity", what}, {"value", value}, {"low", low}, {"high", high}, {"inside", value >= low && value <= high}});
  };
  range("lv_ejection_fraction", last[0].ejection_fraction, 0.55, 0.65);
  range("lv_peak_pressure_kPa", last[0].peak_pressure, 15, 17);
  range("lv_end_diastolic_pressure_kPa", last[0].edp, 1, 1.6);
  range("rv_peak_pressure_kPa", last[1].peak_pressure, 3, 4);
  r.results["healthy_ranges"] = ranges;
}

void compare_with_reference(sph::RunReport& r, const nlohmann::json& reference_beats, const std::filesystem::path& run) {
  if (!r.results.contains("beats")) return;
  const auto& beats = r.results.at("beats");
  if (!beats.is_array() || beats.empty()) return;
  const std::size_t k = std::min(beats.size(), reference_beats.size()) - 1;
  for (const char* v : {"lv", "rv"}) {
    const auto& a = beats[k][v];
    const auto& b = reference_beats[k][v];
    const std::string name(v);
    r.errors[name + "_ejection_fraction_pp"] =
        100 * std::abs(a["ejection_fraction"].get<double>() - b["ejection_fraction"].get<double>());
    r.errors[name + "_peak_pressure_kPa"] = std::abs(a["peak_pressure_kPa"].get<double>() - b["peak_pressure_kPa"].get<double>());
    r.errors[name + "_end_diastolic_pressure_kPa"] = std::abs(a["edp_kPa"].get<double>() - b["edp_kPa"].get<double>());
  }
  r.reference = "the run of " + run.string() + ", beat " + std::to_string(k + 1);
}

void HeartBeats::plot(const std::filesystem::path& folder) const {
  const auto columns = coupling_.circulation().columns();
  auto column = [&](const std::string& name) {
    const auto it = std::find(columns.begin(), columns.end(), name);
    return int(it - columns.begin()) + 1;  // 1-based; the run's time replaces the circulation's
  };
  CsvPlot pv{"circulation.csv", "pv_loop.png", "pressure-volume loops", "cavity volume [mm^3]", "cavity pressure [kPa]",
                {{column("v3d_lv"), column("p_lv"), "LV", ""}, {column("v3d_rv"), column("p_rv"), "RV", ""}}};
  pv.logarithmic = false;
  pv.style = "lines";
  plot_csv(folder, pv);
}

void write_activation_map(const std::filesystem::path& folder, const HeartModel& heart, std::span<const Real> activation,
                          std::span<const Real> apd, double origin) {
  const auto* maps = heart.monodomain->maps();
  const auto& X = heart.whole_X;
  std::ostringstream csv;
  csv << "x,y,z,activation_time" << (maps ? "," + maps->apd_name() : "") << '\n';
  for (std::size_t i = 0; i < heart.n(); ++i) {
    csv << X[i][0] << ',' << X[i][1] << ',' << X[i][2] << ',' << (activation[i] >= 0 ? double(activation[i]) - origin : -1.0);
    if (maps) csv << ',' << apd[i];
    csv << '\n';
  }
  sph::write_file_atomically(folder / "activation_map.csv", csv.str());
  if (std::none_of(activation.begin(), activation.end(), [](Real a) { return a >= 0; })) return;  // nothing to draw
  plot_scatter(folder, {"activation_map.csv", "activation_map.png", "first activation (mesh coordinates)",
                        "activation time after the first stimulus [ms]", 4, 60, 30});
}

std::vector<cardio::Electrode> heart_electrodes(const HeartModel& heart, const cardio::HeartGeometry& g, const EcgParameters& p) {
  if (p.mode != "twelve_lead") return parse_electrodes(p.electrodes);
  Vec3 centre = Vec3::Zero(), lv = Vec3::Zero(), rv = Vec3::Zero();
  std::size_t n_lv = 0, n_rv = 0;
  const auto& X = heart.whole_X;
  for (std::size_t i = 0; i < heart.n(); ++i) {
    centre += X[i];
    if (heart.labels[i] == cardio::label_lv_endo) lv += X[i], ++n_lv;
    if (heart.labels[i] == cardio::label_rv_endo) rv += X[i], ++n_rv;
  }
  if (n_lv == 0 || n_rv == 0)
    throw sph::ParameterError("parameter 'ecg' = twelve_lead places the electrodes by the LV and RV endocardia, and this "
                              "heart has no particle labelled " + std::string(n_lv == 0 ? "LV" : "RV") +
                              " endocardium (use ecg = electrodes)");
  centre /= Real(heart.n());
  return cardio::twelve_lead_electrodes(centre, -g.base_normal.cast<Real>(), rv / Real(n_rv) - lv / Real(n_lv),
                                        p.chest_radius, p.limb_distance);
}
}  // namespace cardiosph
