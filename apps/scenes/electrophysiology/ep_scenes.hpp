#pragma once
// Electrophysiology scenes: parameter structs with their defaults, and the factories.

#include <memory>
#include <string>

#include "apps/scenes/electrophysiology/cell_variation.hpp"
#include "apps/scenes/electrophysiology/ecg_output.hpp"
#include "apps/scenes/electrophysiology/ep_run.hpp"
#include "apps/scenes/electrophysiology/pacing.hpp"
#include "apps/scenes/scene.hpp"

namespace cardiosph {

/// `cell`: single cells, paced, every scheme at several steps against the CVODE reference.
struct CellParameters {
  std::string model = "all";      ///< a cell model name, or all
  long resolution = 8;            ///< rungs of the step ladder: smallest_time_step times 1, 2, 4, ...
  double end_time = 2000;         ///< [ms]; APD90 is measured on the last paced beat
  double period = 1000;           ///< pacing cycle length [ms]
  double stimulus_strength = 52;  ///< applied dV/dt during a pulse [mV/ms]
  double stimulus_duration = 1;   ///< [ms]
  double smallest_time_step = 0.01;  ///< [ms]
  double sample_interval = 0.5;   ///< where the voltage error is measured [ms]
  double cvode_tolerance = 1e-8;  ///< relative tolerance of the reference (absolute: 1e-3 of it)
  /// [mV] ten Tusscher-Panfilov also by rbr_qss with its functions of V in lookup tables of this
  /// step (the row rbr_qss_table); 0: not
  double lookup_table = 0.05;
};

/// `depolarization`: 2D Aliev-Panfilov excitation from a corner bump (dimensionless units).
struct DepolarizationParameters {
  long resolution = 50;  ///< particles across the unit square (dp = 0.02)
  double end_time = 16;
  double diffusivity = 1;
  double k = 8, a = 0.15, b = 0, mu1 = 0.2, mu2 = 0.3, epsilon0 = 0.04;
  EpSceneNumerics numerics{{1.3, "wendland_c2", 0}, {sph::ReactionScheme::rbr_qss, sph::Real(0.01)}};
};

/// `spiral-wave`: 2D Aliev-Panfilov spiral from an S1-S2 cross-field stimulus (mm, ms, mV).
struct SpiralWaveParameters {
  long resolution = 128;          ///< particles across the domain
  double end_time = 5000;         ///< [ms]
  std::string domain = "square";  ///< square or disc
  double size = 100;              ///< side of the square or diameter of the disc [mm]
  double diffusivity_longitudinal = 0.1;  ///< along the fibres (x) [mm^2/ms]
  double diffusivity_transverse = 0.1;    ///< across [mm^2/ms]
  double stimulus_strength = 50;  ///< [mV/ms]
  double stimulus_duration = 2;   ///< [ms]
  double s2_time = 0;             ///< onset of the S2 stimulus [ms]; 0: when the S1 wave back passes the middle
  EpSceneNumerics numerics{{1.3, "wendland_c2", 20}, {sph::ReactionScheme::rbr_qss, sph::Real(0.5)}};
};

/// `niederer-slab`: the N-version benchmark slab of Niederer et al. 2011 (mm, ms, mV).
struct NiedererSlabParameters {
  long resolution = 6;      ///< particles across the 3 mm side: dx = 3 / resolution (6: 0.5, 15: 0.2, 30: 0.1 mm)
  double end_time = 250;    ///< the run stops earlier once every particle has been activated [ms]
  bool stop_when_activated = true;
  PacingParameters pacing;
  TissueProperties tissue;
  double stimulus_current = 50;     ///< [uA/mm^3] (50,000 uA/cm^3)
  double stimulus_duration = 2;     ///< [ms]
  double stimulus_size = 1.5;       ///< side of the stimulated corner cube [mm]
  double lookup_table = 0;          ///< [mV] the cells' functions of V tabulated (0: exact)
  EpSceneNumerics numerics{{1.3, "wendland_c2", 0}, {sph::ReactionScheme::rbr_qss, sph::Real(0.05)}, 90};
};

/// `cable`: a strand of ten Tusscher-Panfilov cells under a pacing protocol (mm, ms, mV).
struct CableParameters {
  double length = 10, width = 0.5;  ///< [mm]
  long resolution = 2;              ///< particles across the width (dx = 0.25 mm)
  double end_time = 0;              ///< [ms]; 0: the protocol's
  TissueProperties tissue;
  double stimulus_current = 50;     ///< [uA/mm^3]
  double stimulus_duration = 2;     ///< [ms]
  double stimulus_length = 1;       ///< [mm] stimulated from x = 0
  PacingParameters pacing{"restitution"};
  CellVariationParameters cells;
  EcgParameters ecg;
  EpSceneNumerics numerics{{1.3, "wendland_c2", 0}, {sph::ReactionScheme::rbr_qss, sph::Real(0.05)}, 90};
};

std::unique_ptr<Scene> make_cable_scene(CableParameters p = {});
std::unique_ptr<Scene> make_cell_scene(CellParameters p = {});
std::unique_ptr<Scene> make_depolarization_scene(DepolarizationParameters p = {});
std::unique_ptr<Scene> make_spiral_wave_scene(SpiralWaveParameters p = {});
std::unique_ptr<Scene> make_niederer_slab_scene(NiedererSlabParameters p = {});

}  // namespace cardiosph
