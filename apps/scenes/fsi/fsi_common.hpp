#pragma once
// What the FSI scenes share: an elastic body coupled to the fluid, and the amplitude and frequency
// of an oscillating signal.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "apps/scenes/fsi/fsi_scenes.hpp"
#include "libsph/fsi/solid_fluid_coupling.hpp"
#include "libsph/io/run_harness.hpp"

namespace cardiosph {

/// An elastic body in a fluid: its particles, inner relation, TLSPH solid and coupling.
struct FsiBody {
  sph::ParticleSet<2> particles;
  sph::InnerRelation<2> relation;
  std::unique_ptr<sph::ElasticSolid<2>> solid;
  std::unique_ptr<sph::SolidFluidCoupling<2>> coupling;

  /// Adds the body to a fluid run: its particles written every `output_interval`, the coupling in
  /// the slots of the fluid's step (SolidFluidCoupling::fill), and the solid's and coupling's state
  /// to the checkpoints.
  void add_to(sph::RunHarness& run, sph::Stage& fluid_step, sph::Real output_interval);
  /// Saves or loads the solid's and the coupling's changing members (their fields are the particles').
  void checkpoint(sph::StateArchive& archive) {
    solid->checkpoint(archive);
    coupling->checkpoint(archive);
  }
};

struct FsiBodySpec {
  double spacing = 0;                 ///< solid dp
  double density = 0, young_modulus = 0, poisson_ratio = 0;
  double damping_rate = 0;
  sph::Vec<2> gravity = sph::Vec<2>::Zero();
  std::function<bool(const sph::Vec<2>&)> clamped;  ///< particles held at their reference position
  /// The clamp's flat faces, where it has them (a point on the face and the normal towards the free
  /// part): with FsiSolidNumerics::clamp = "reflection" each clamped particle behind a face is held
  /// by odd reflection across it. Empty: the clamp is not flat and "reflection" is refused.
  struct ClampFace {
    sph::Vec<2> point, normal;
  };
  std::vector<ClampFace> clamp_faces;
};

/// Builds the Saint Venant-Kirchhoff body on `particles` (reference normals given), clamps, and
/// couples it to the fluid. A body thinner than one fluid spacing is refused as a ParameterError
/// naming `thickness_parameter`.
std::unique_ptr<FsiBody> make_fsi_body(sph::ParticleSet<2> particles, const std::vector<sph::Vec<2>>& normals,
                                       const FsiBodySpec& spec,
                                       const FsiSolidNumerics& numerics, sph::WeaklyCompressibleFluid<2>& fluid,
                                       const std::string& thickness_parameter);

/// Of the samples (t_k, y_k) with t_k >= t_start: the mean and half the range (max + min) / 2 and
/// (max - min) / 2 (the "mean +- amplitude" of Turek & Hron 2006), the dominant frequency (the peak
/// of the Fourier transform, which noise at other frequencies does not shift) and the amplitude of
/// that harmonic alone.
/// Also, per whole period of the dominant frequency (consecutive windows of 1 / frequency from the
/// window's end backwards), the period's own mean and half range, averaged over the periods: the
/// statistic of Turek & Hron 2006, who take mean and amplitude "from the last period", made robust
/// to the particle-scale noise whose extremes set the half range over many periods.
struct Oscillation {
  double mean = 0, amplitude = 0, frequency = 0, harmonic_amplitude = 0;
  double period_mean = 0, period_amplitude = 0;
  std::size_t cycles = 0;  ///< whole periods of the dominant frequency in the window
};
Oscillation analyse_oscillation(const std::vector<double>& t, const std::vector<double>& y, double t_start);

/// Relative error |measured - reference| / |reference|.
inline double relative_error(double measured, double reference) {
  return std::abs(measured - reference) / std::abs(reference);
}

}  // namespace cardiosph
