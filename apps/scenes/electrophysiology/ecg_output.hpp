#pragma once
// The pseudo-ECG of a scene (cardio/pseudo_ecg.hpp) as parameters, a CSV time series (ecg.csv:
// time and one column per lead, or per electrode), a picture (ecg.png, one panel per column) and a
// summary in report.json (peak-to-peak amplitude per column, time spent per sample).

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cardio/pseudo_ecg.hpp"
#include "libsph/io/parameters.hpp"
#include "libsph/io/run_harness.hpp"

namespace cardiosph {

struct EcgParameters {
  std::string mode = "none";  ///< twelve_lead, electrodes or none
  std::string electrodes;     ///< "name:x,y,z;name:x,y,z" [mm], for mode = electrodes
  double chest_radius = 100;  ///< [mm] precordial electrodes from the heart centre (twelve_lead)
  double limb_distance = 300;  ///< [mm] limb electrodes from the heart centre (twelve_lead)
  double bath_conductivity = 0.2;  ///< sigma_b [S/m]
  double surface_to_volume = 140;  ///< chi [1/mm], with C_m turning D into the conductivity
  double capacitance = 0.01;       ///< C_m [uF/mm^2]
  double interval = 1;             ///< [ms] between samples
};

/// Declares ecg (with the modes given: twelve_lead only where the scene has a heart frame),
/// ecg_electrodes, ecg_chest_radius, ecg_limb_distance, ecg_bath_conductivity, ecg_surface_to_volume,
/// ecg_capacitance and ecg_interval. Scenes that have chi and C_m of their own declare those instead
/// and copy them in.
void declare_parameters(sph::Parameters& p, EcgParameters& ecg, std::vector<std::string> modes, bool tissue_parameters = true);

/// "name:x,y,z;..." into electrodes; throws sph::ParameterError naming 'ecg_electrodes' and the entry.
std::vector<cardio::Electrode> parse_electrodes(const std::string& text);

/// Samples a pseudo-ECG into ecg.csv during a run and draws ecg.png after it.
class EcgRecorder {
 public:
  /// What the recorder reads at each sample: the potential, the conduction tensors (one, or one per
  /// particle), the current positions and the deformation gradients (empty for a fixed tissue).
  struct Source {
    std::function<std::span<const sph::Real>()> potential;
    std::function<std::span<const sph::Mat<3>>()> conduction;
    std::function<std::span<const sph::Vec<3>>()> positions;
    std::function<std::span<const sph::Mat<3>>()> deformation;
  };
  /// electrodes: parsed or placed by the scene; `twelve_lead` combines them into the 12 leads.
  EcgRecorder(const EcgParameters& p, std::vector<cardio::Electrode> electrodes, bool twelve_lead,
              const sph::NeighbourList<3>& relation, std::span<const sph::Vec<3>> reference_positions,
              std::span<const sph::Real> volumes, double particle_spacing, Source source, sph::RunHarness& run,
              const sph::ParticleSet<3>* distributed = nullptr);
  /// One beat of the ECG: its stimulus time and length, and how long after the stimulus the QRS is
  /// sought.
  struct Beat {
    double start = 0, length = 0, qrs_window = 150;
  };
  /// ecg.png, and the summary under results["ecg"]. With a beat, its intervals from the RMS over the
  /// columns: the QRS from the first to the last sample above 10 % of the RMS peak within qrs_window
  /// (qrs_duration_ms); the T wave as the RMS peak after the QRS (t_peak_ms, after the stimulus), and
  /// the QT interval from the QRS onset to the last sample above 10 % of that peak (qt_interval_ms).
  void finish(const std::filesystem::path& folder, sph::RunReport& report, std::optional<Beat> beat = {}) const;

 private:
  cardio::PseudoEcg ecg_;
  std::vector<cardio::Lead> leads_;
  std::vector<std::string> columns_;
  std::vector<double> lowest_, highest_;
  std::vector<double> time_, rms_;
  Source source_;
  double seconds_ = 0;
  std::size_t samples_ = 0;
};

}  // namespace cardiosph
