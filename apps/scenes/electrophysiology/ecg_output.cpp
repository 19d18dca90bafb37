#include "apps/scenes/electrophysiology/ecg_output.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <sstream>

#include <nlohmann/json.hpp>

#include "apps/plot.hpp"

namespace cardiosph {

void declare_parameters(sph::Parameters& p, EcgParameters& ecg, std::vector<std::string> modes, bool tissue_parameters) {
  const bool twelve = std::find(modes.begin(), modes.end(), "twelve_lead") != modes.end();
  modes.push_back("electrodes");
  modes.push_back("none");
  p.add_choice("ecg", ecg.mode, modes,
               std::string("pseudo-ECG written to ecg.csv and ecg.png: ") +
                   (twelve ? "the standard 12 leads from electrodes placed around the heart (twelve_lead), " : "") +
                   "the potentials at ecg_electrodes, or none");
  p.add_text("ecg_electrodes", ecg.electrodes, "electrodes for ecg = electrodes, as name:x,y,z;name:x,y,z in mm (mesh coordinates)");
  if (twelve) {
    p.add("ecg_chest_radius", ecg.chest_radius, "mm", "distance of the precordial electrodes V1-V6 from the heart centre",
          sph::Range::positive());
    p.add("ecg_limb_distance", ecg.limb_distance, "mm", "distance of the limb electrodes RA, LA, LL from the heart centre",
          sph::Range::positive());
  }
  p.add("ecg_bath_conductivity", ecg.bath_conductivity, "S/m", "conductivity of the volume conductor around the tissue",
        sph::Range::positive());
  if (tissue_parameters) {
    p.add("ecg_surface_to_volume", ecg.surface_to_volume, "1/mm",
          "membrane surface-to-volume ratio chi; chi C_m D is the tissue conductivity of the pseudo-ECG",
          sph::Range::positive());
    p.add("ecg_capacitance", ecg.capacitance, "uF/mm^2", "membrane capacitance C_m of the pseudo-ECG", sph::Range::positive());
  }
  p.add("ecg_interval", ecg.interval, "ms", "time between pseudo-ECG samples", sph::Range::positive());
}

std::vector<cardio::Electrode> parse_electrodes(const std::string& text) {
  std::vector<cardio::Electrode> electrodes;
  std::istringstream entries(text);
  std::string entry;
  while (std::getline(entries, entry, ';')) {
    if (entry.find_first_not_of(" \t") == std::string::npos) continue;
    const auto colon = entry.find(':');
    auto fail = [&](const std::string& why) {
      return sph::ParameterError("parameter 'ecg_electrodes': entry '" + entry + "' " + why + " (expected name:x,y,z)");
    };
    if (colon == std::string::npos || colon == 0) throw fail("has no name");
    cardio::Electrode e;
    e.name = entry.substr(0, colon);
    std::istringstream coordinates(entry.substr(colon + 1));
    std::string c;
    int k = 0;
    while (std::getline(coordinates, c, ',')) {
      if (k == 3) throw fail("has more than three coordinates");
      std::size_t used = 0;
      try {
        e.position[k] = sph::Real(std::stod(c, &used));
      } catch (const std::exception&) {
        throw fail("has a coordinate that is not a number");
      }
      if (c.find_first_not_of(" \t", used) != std::string::npos || !std::isfinite(e.position[k]))
        throw fail("has a coordinate that is not a finite number");
      ++k;
    }
    if (k != 3) throw fail("has fewer than three coordinates");
    for (const auto& other : electrodes)
      if (other.name == e.name) throw fail("repeats the name '" + e.name + "'");
    electrodes.push_back(e);
  }
  if (electrodes.empty()) throw sph::ParameterError("parameter 'ecg_electrodes' names no electrode (ecg = electrodes)");
  return electrodes;
}

EcgRecorder::EcgRecorder(const EcgParameters& p, std::vector<cardio::Electrode> electrodes, bool twelve_lead,
                         const sph::NeighbourList<3>& relation, std::span<const sph::Vec<3>> reference_positions,
                         std::span<const sph::Real> volumes, double particle_spacing, Source source, sph::RunHarness& run,
                         const sph::ParticleSet<3>* distributed)
    : ecg_([&]() -> cardio::PseudoEcg {
        try {
          return {std::move(electrodes), relation, reference_positions, volumes,
                  p.surface_to_volume * p.capacitance / p.bath_conductivity, 2 * particle_spacing, distributed};
        } catch (const std::invalid_argument& e) {
          throw sph::ParameterError(std::string(e.what()) + (twelve_lead ? " (raise ecg_chest_radius)" : " (ecg_electrodes)"));
        }
      }()),
      source_(std::move(source)) {
  if (twelve_lead) {
    leads_ = cardio::twelve_leads(ecg_.electrodes());
    for (const auto& lead : leads_) columns_.push_back(lead.name);
  } else {
    for (const auto& e : ecg_.electrodes()) columns_.push_back(e.name);
  }
  lowest_.assign(columns_.size(), std::numeric_limits<double>::infinity());
  highest_.assign(columns_.size(), -std::numeric_limits<double>::infinity());
  run.add_time_series("ecg.csv", columns_, sph::Real(p.interval), [this](const sph::StepInfo& step) {
    const auto start = std::chrono::steady_clock::now();
    const auto phi = ecg_.potentials(source_.potential(), source_.conduction(), source_.positions(),
                                     source_.deformation ? source_.deformation() : std::span<const sph::Mat<3>>());
    auto row = leads_.empty() ? phi : cardio::lead_values(leads_, phi);
    double squares = 0;
    for (std::size_t c = 0; c < row.size(); ++c) {
      lowest_[c] = std::min(lowest_[c], row[c]);
      highest_[c] = std::max(highest_[c], row[c]);
      squares += row[c] * row[c];
    }
    time_.push_back(step.time);
    rms_.push_back(std::sqrt(squares / double(row.size())));
    seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ++samples_;
    return row;
  });
  run.add_state("ecg", [this](sph::StateArchive& a) {
    a.io("lowest", lowest_);
    a.io("highest", highest_);
    a.io("time", time_);
    a.io("rms", rms_);
    a.io("seconds", seconds_);
    a.io("samples", samples_);
  });
}

void EcgRecorder::finish(const std::filesystem::path& folder, sph::RunReport& report, std::optional<Beat> beat) const {
  CsvPlot plot{"ecg.csv", "ecg.png", "pseudo-ECG", "time [ms]", "potential [mV]", {}, false, "lines",
               columns_.size() > 3 ? 3 : 1};
  for (std::size_t c = 0; c < columns_.size(); ++c) plot.series.push_back({1, int(c) + 2, columns_[c], ""});
  plot_csv(folder, plot);
  auto& s = report.results["ecg"];
  for (std::size_t c = 0; c < columns_.size(); ++c)
    s["peak_to_peak_mV"][columns_[c]] = samples_ > 0 ? highest_[c] - lowest_[c] : 0.0;
  for (const auto& e : ecg_.electrodes()) s["electrodes_mm"][e.name] = {e.position[0], e.position[1], e.position[2]};
  s["samples"] = samples_;
  s["seconds"] = seconds_;
  if (samples_ > 0) s["seconds_per_sample"] = seconds_ / double(samples_);
  if (!beat) return;
  // The RMS above `fraction` of its peak within [from, to): first and last such sample times.
  auto above = [&](double from, double to, double fraction) {
    double peak = 0, peak_time = -1, first = -1, last = -1;
    for (std::size_t k = 0; k < time_.size(); ++k)
      if (time_[k] >= from && time_[k] < to && rms_[k] > peak) peak = rms_[k], peak_time = time_[k];
    for (std::size_t k = 0; k < time_.size(); ++k)
      if (time_[k] >= from && time_[k] < to && peak > 0 && rms_[k] > fraction * peak) {
        if (first < 0) first = time_[k];
        last = time_[k];
      }
    return std::array<double, 3>{first, last, peak_time};
  };
  const auto qrs = above(beat->start, beat->start + beat->qrs_window, 0.1);
  if (qrs[0] < 0) return;
  s["qrs_duration_ms"] = qrs[1] - qrs[0];
  const auto t = above(qrs[1] + 1e-9, beat->start + beat->length, 0.1);
  if (t[0] < 0) return;
  s["t_peak_ms"] = t[2] - beat->start;
  s["qt_interval_ms"] = t[1] - qrs[0];
}

}  // namespace cardiosph
