#pragma once
// Pacing protocols of the tissue scenes, and the per-beat records at measuring points from which
// they are read: the APD and diastolic interval of every beat, the conduction velocity between two
// points, the APD change over the last two beats of a train (how steady the prepacing left it), and
// the APD and CV restitution curves of an S1-S2 protocol.
//
// Protocols (onsets of the pulses; each pulse lasts the scene's stimulus duration):
//   train:        pacing_count pulses every pacing_period, from 0;
//   s1s2:         s1_count S1 pulses every pacing_period, then one S2 s2_coupling after the last S1;
//   restitution:  for each coupling interval CI of restitution_couplings, a block of s1_count S1 pulses
//                 every pacing_period followed by an S2 at CI after the block's last S1; the next
//                 block starts one pacing_period after the S2. The S2 beats give APD(DI) and CV(DI).

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "cardio/monodomain.hpp"
#include "libsph/io/parameters.hpp"
#include "libsph/io/run_report.hpp"
#include "libsph/reaction/stimulus.hpp"

namespace cardiosph {

struct PacingParameters {
  std::string protocol = "train";  ///< train, s1s2 or restitution
  double period = 1000;            ///< [ms] between S1 pulses
  long count = 1;                  ///< pulses of a train
  long s1_count = 4;               ///< S1 pulses before each S2
  double s2_coupling = 300;        ///< [ms] S2 after the last S1 (s1s2)
  std::string couplings = "600,450,400,375,350,340,330,320";  ///< [ms] S2 coupling intervals (restitution)
};

/// Declares pacing, pacing_period, pacing_count, s1_count, s2_coupling and restitution_couplings.
void declare_parameters(sph::Parameters& p, PacingParameters& pacing);

/// The protocol's pulses as a stimulus protocol of the given duration and strength, and the S2 onsets.
struct PacingPlan {
  sph::StimulusProtocol stimulus;
  std::vector<double> s2_onsets;  ///< empty for a train
  double end_time = 0;            ///< one pacing_period after the last pulse
};
/// Throws sph::ParameterError naming the parameter for an impossible protocol (a coupling interval
/// not shorter than the period or not longer than the pulse, an unreadable list).
PacingPlan pacing_plan(const PacingParameters& p, double duration, double strength);

/// Per-beat records at a few particles: activation, APD, diastolic interval. Call record() after
/// every step (cheap: it reads a handful of particles of the maps).
template <int Dim>
class BeatRecorder {
 public:
  struct Point {
    std::string name;
    std::size_t particle;
  };
  struct Beat {
    double activation, apd, diastolic_interval;
  };
  /// `cv_from` and `cv_to`: indices into points between which the CV is taken (distance over the
  /// difference of their activation times in the same beat).
  BeatRecorder(const cardio::Monodomain<Dim>& monodomain, std::vector<Point> points, std::size_t cv_from, std::size_t cv_to);
  void record();
  const std::vector<Beat>& beats(std::size_t point) const { return beats_[point]; }
  /// beats.csv (every beat at every point), restitution.csv and restitution.png (APD and CV of the S2
  /// beats against their DI) when there are S2 onsets, and the summary under results["beats"].
  void finish(const std::filesystem::path& folder, const PacingPlan& plan, double period, sph::RunReport& report) const;
  /// Saves or loads the beats recorded so far (checkpoints).
  void checkpoint(sph::StateArchive& archive) {
    for (std::size_t p = 0; p < beats_.size(); ++p) archive.io("beats" + std::to_string(p), beats_[p]);
    archive.io("counted", counted_);
  }

 private:
  const cardio::Monodomain<Dim>& monodomain_;
  std::vector<Point> points_;
  std::size_t cv_from_, cv_to_;
  double distance_;
  std::vector<std::vector<Beat>> beats_;
  std::vector<sph::Real> counted_;
};

}  // namespace cardiosph
