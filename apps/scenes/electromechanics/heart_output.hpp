#pragma once
// What `cardiosph heart` (apps/scenes/electromechanics/heart.cpp) records and reports: the cavity
// and observer time series, the beats against the circulation, the activation map and the
// electrodes of the pseudo-ECG.

#include <array>
#include <filesystem>
#include <vector>

#include "apps/scenes/electromechanics/heart_model.hpp"
#include "cardio/beat_metrics.hpp"
#include "cardio/circulation_coupling.hpp"
#include "cardio/pseudo_ecg.hpp"
#include "libsph/core/distribution.hpp"
#include "libsph/core/point_probes.hpp"
#include "libsph/io/run_harness.hpp"

namespace cardiosph {

/// What the heart records while it beats: cavities.csv (volumes, pressures, energies, J range,
/// peak T_a, mean V), observers.csv (V, T_a and displacement at three material points) and the
/// end-of-beat states, with the extremes that the report needs.
class HeartRecorder {
 public:
  HeartRecorder(HeartModel& heart, sph::RunHarness& run, sph::TimeStepper& stepper, const HeartParameters& p)
      : heart_(heart),
        volume_min_(heart.cavities->size(), std::numeric_limits<double>::infinity()),
        volume_max_(heart.cavities->size(), 0),
        peak_pressure_(heart.cavities->size(), 0),
        probes_(observer_points(), heart.whole_X, heart.whole_volume, heart.kernel, heart.h) {
    std::vector<std::string> cavity_columns;
    for (std::size_t c = 0; c < heart.cavities->size(); ++c)
      for (const char* q : {"_volume", "_pressure"}) cavity_columns.push_back(heart.cavities->name(c) + q);
    for (const char* column : {"kinetic", "strain", "min_J", "max_J", "max_T_a", "mean_V", "mechanics_dt", "max_k_a"}) cavity_columns.push_back(column);
    run.add_time_series("cavities.csv", cavity_columns, Real(p.sample_interval), [this](const sph::StepInfo& s) { return cavity_row(s); });
    std::vector<std::string> observer_columns;
    for (const auto& name : observer_names_)
      for (const char* q : {"_V", "_T_a", "_displacement"}) observer_columns.push_back(name + q);
    run.add_time_series("observers.csv", observer_columns, Real(p.sample_interval), [this](const sph::StepInfo&) { return observer_row(); });
    stepper.add_event("end of beat", {Real(p.cycle_length), true, false, true, Real(beat_origin(p))},
                      [this](const sph::StepInfo&) { end_of_beat(); });
    run.add_state("recorder", [this](sph::StateArchive& a) {
      a.io("volume_min", volume_min_);
      a.io("volume_max", volume_max_);
      a.io("peak_pressure", peak_pressure_);
      for (auto [name, value] : {std::pair{"min_J", &min_J_}, {"max_J", &max_J_}, {"peak_tension", &peak_tension_},
                                 {"peak_kinetic", &peak_kinetic_}, {"peak_strain", &peak_strain_},
                                 {"peak_displacement", &peak_displacement_},
                                 {"smallest_step", &smallest_step_}, {"peak_active_stiffness", &peak_active_stiffness_}})
        a.io(name, *value);
      std::string end_of_beat = end_of_beat_.dump();
      a.io("end_of_beat", end_of_beat);
      if (a.loading()) end_of_beat_ = nlohmann::json::parse(end_of_beat);
    });
  }

  void report(sph::RunReport& r) const {
    for (std::size_t c = 0; c < heart_.cavities->size(); ++c) {
      const std::string name = heart_.cavities->name(c);
      r.results[name + "_reference_volume_mm3"] = heart_.cavities->surface(c).reference_volume;
      r.results[name + "_end_diastolic_volume_mm3"] = volume_max_[c];
      r.results[name + "_end_systolic_volume_mm3"] = volume_min_[c];
      r.results[name + "_peak_pressure_kPa"] = peak_pressure_[c];
      r.results[name + "_ejection_fraction"] = volume_max_[c] > 0 ? (volume_max_[c] - volume_min_[c]) / volume_max_[c] : 0.0;
    }
    r.results["min_jacobian"] = min_J_;
    r.results["max_jacobian"] = max_J_;
    r.results["peak_active_tension_kPa"] = peak_tension_;
    r.results["peak_kinetic_energy"] = peak_kinetic_;
    r.results["peak_displacement_mm"] = peak_displacement_;
    r.results["peak_strain_energy"] = peak_strain_;
    // What the inertia (scaled by mass_scaling) costs a quasi-static beat: peak kinetic over peak
    // strain energy.
    r.results["kinetic_to_strain_energy_ratio"] = peak_strain_ > 0 ? peak_kinetic_ / peak_strain_ : 0.0;
    r.results["end_of_beat"] = end_of_beat_;
    // What sizes the explicit mechanics step (cavities.csv: mechanics_dt, max_k_a): the solid's
    // largest tangent modulus, in systole the crossbridge stiffness k_a of the Land model.
    r.results["smallest_sampled_mechanics_time_step_ms"] = smallest_step_;
    r.results["peak_active_stiffness_kPa"] = peak_active_stiffness_;
  }

 private:
  /// The particle nearest to the stimulus centre, and the LV and RV endocardial particles farthest
  /// from it (found on the whole heart; the probes sample the gathered fields).
  std::vector<Vec3> observer_points() {
    const auto& x = heart_.whole_X;
    const auto labels = heart_.labels;
    std::size_t nearest = 0;
    for (std::size_t i = 1; i < x.size(); ++i)
      if ((x[i] - heart_.stimulus_centre).squaredNorm() < (x[nearest] - heart_.stimulus_centre).squaredNorm()) nearest = i;
    std::vector<Vec3> points{x[nearest]};
    observer_names_ = {"stimulus"};
    for (auto [name, l] : {std::pair{"lv_far", cardio::label_lv_endo}, std::pair{"rv_far", cardio::label_rv_endo}}) {
      std::optional<std::size_t> far;
      for (std::size_t i = 0; i < x.size(); ++i)
        if (labels[i] == l && (!far || (x[i] - heart_.stimulus_centre).norm() > (x[*far] - heart_.stimulus_centre).norm())) far = i;
      if (far) points.push_back(x[*far]), observer_names_.push_back(name);
    }
    return points;
  }
  // End-diastolic volume: the largest sampled; end-systolic: the smallest sampled after it.
  std::vector<double> cavity_row(const sph::StepInfo& s) {
    const auto e = heart_.solid->energies();  // leaves F at the current positions
    std::vector<double> row;
    for (std::size_t c = 0; c < heart_.cavities->size(); ++c) {
      const double v = heart_.cavities->volume(c);
      if (v > volume_max_[c]) volume_max_[c] = v, volume_min_[c] = v;
      volume_min_[c] = std::min(volume_min_[c], v);
      const double pressure = heart_.cavities->pressure(c).at(s.time);
      row.insert(row.end(), {v, pressure});
      peak_pressure_[c] = std::max(peak_pressure_[c], pressure);
    }
    const double max_T = heart_.max_tension();
    const double dt = heart_.solid->stable_time_step();
    const auto& k_a = heart_.tension->stiffness();
    const auto owned_k_a = std::span<const Real>(k_a).first(k_a.empty() ? 0 : heart_.body->n_owned());
    const double max_k_a =
        k_a.empty() ? 0.0 : double(sph::global_max(*heart_.body, *std::max_element(owned_k_a.begin(), owned_k_a.end())));
    row.insert(row.end(), {e.kinetic, e.strain, double(e.min_jacobian), double(e.max_jacobian), max_T, heart_.mean_potential(),
                           dt, max_k_a});
    smallest_step_ = std::min(smallest_step_, dt);
    peak_active_stiffness_ = std::max(peak_active_stiffness_, max_k_a);
    min_J_ = std::min<double>(min_J_, e.min_jacobian);
    max_J_ = std::max<double>(max_J_, e.max_jacobian);
    peak_tension_ = std::max(peak_tension_, max_T);
    peak_kinetic_ = std::max(peak_kinetic_, e.kinetic);
    peak_strain_ = std::max(peak_strain_, e.strain);
    peak_displacement_ = std::max(peak_displacement_, heart_.max_displacement());
    return row;
  }
  std::vector<double> observer_row() const {
    std::vector<Real> whole_V, whole_T;
    const auto V = sph::gather_all(*heart_.body, std::span<const Real>(heart_.body->field(heart_.monodomain->potential_field())), whole_V);
    const auto T = sph::gather_all(*heart_.body, std::span<const Real>(heart_.tension->tension()), whole_T);
    const auto x = material_point_positions<3>(probes_, *heart_.solid);
    std::vector<double> row;
    for (std::size_t p = 0; p < probes_.size(); ++p)
      row.insert(row.end(), {probes_.sample(p, V), probes_.sample(p, T), double((x[p] - probes_.point(p)).norm())});
    return row;
  }
  void end_of_beat() {
    end_of_beat_["energy"].push_back(heart_.solid->energies().total());  // also leaves F at the current positions
    end_of_beat_["lv_volume_mm3"].push_back(heart_.cavities->size() == 0 ? 0.0 : heart_.cavities->volume(0));
    end_of_beat_["max_displacement_mm"].push_back(heart_.max_displacement());
    end_of_beat_["max_active_tension_kPa"].push_back(heart_.max_tension());
    end_of_beat_["mean_potential_mV"].push_back(heart_.mean_potential());
  }

  HeartModel& heart_;
  std::vector<std::string> observer_names_;
  std::vector<double> volume_min_, volume_max_, peak_pressure_;
  double min_J_ = 1, max_J_ = 1, peak_tension_ = 0, peak_kinetic_ = 0, peak_strain_ = 0, peak_displacement_ = 0;
  double smallest_step_ = std::numeric_limits<double>::infinity(), peak_active_stiffness_ = 0;
  nlohmann::json end_of_beat_ = {{"energy", nlohmann::json::array()},
                                 {"lv_volume_mm3", nlohmann::json::array()},
                                 {"max_displacement_mm", nlohmann::json::array()},
                                 {"max_active_tension_kPa", nlohmann::json::array()},
                                 {"mean_potential_mV", nlohmann::json::array()}};
  const sph::PointProbes<3> probes_;  // in the reference configuration: material points
};

/// The measures of each beat against the circulation (cavity_pressure = circulation), an observer
/// after every coupled step: the PV measures of both ventricles at each beat's end
/// (cardio/beat_metrics.hpp), the largest volume change in the isovolumic phases, circulation.csv,
/// and the end of the run once both stroke volumes changed by less than beat_tolerance from the
/// beat before.
class HeartBeats {
 public:
  HeartBeats(cardio::CirculationCoupling& coupling, sph::TimeStepper& stepper, sph::RunHarness& run, const HeartParameters& p,
             bool quiet);
  void report(sph::RunReport& r) const;
  /// pv_loop.png: pressure against volume of both ventricles over every beat (from circulation.csv).
  void plot(const std::filesystem::path& folder) const;

 private:
  void after_step(const sph::StepInfo& s, sph::TimeStepper& stepper);
  void checkpoint(sph::StateArchive& a);

  cardio::CirculationCoupling& coupling_;
  const HeartParameters& p_;
  const bool quiet_;
  cardio::BeatRecorder recorders_[2];
  std::vector<std::array<cardio::BeatMeasures, 2>> beats_;
  long converged_at_ = -1;
  bool was_closed_[2] = {false, false};
  double closed_volume_[2] = {0, 0}, isovolumic_change_[2] = {0, 0};
};

/// The errors of this run (its results.beats, written by HeartBeats::report) against the reference
/// run's beats (reference_beats()), on the last beat both ran: the LV and RV ejection fractions in
/// percentage points, peak and end-diastolic pressures in kPa; `reference` names the run and beat.
void compare_with_reference(sph::RunReport& r, const nlohmann::json& reference_beats, const std::filesystem::path& run);

/// activation_map.csv (reference x, y, z, first activation time after the first stimulus at
/// `origin`, -1 where not activated, and with the maps the latest APD) and activation_map.png, the
/// particles coloured by their activation time; `activation` and `apd` (empty without maps) are
/// the whole heart's, by global id.
void write_activation_map(const std::filesystem::path& folder, const HeartModel& heart, std::span<const Real> activation,
                          std::span<const Real> apd, double origin);

/// The electrodes of the pseudo-ECG: the 12-lead set placed by the heart's frame (its centre, the
/// base-to-apex direction -base_normal and the LV-to-RV endocardial centroids), or the given ones.
std::vector<cardio::Electrode> heart_electrodes(const HeartModel& heart, const cardio::HeartGeometry& g, const EcgParameters& p);

}  // namespace cardiosph
