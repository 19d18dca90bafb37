#pragma once
// The parameters of `cardiosph heart` (apps/scenes/electromechanics/heart.cpp): their defaults,
// declarations and checks, the SPHinXsys preset and the table of the calibrated ones.

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "apps/scenes/electrophysiology/cell_variation.hpp"
#include "apps/scenes/electrophysiology/ecg_output.hpp"
#include "apps/scenes/geometry/heart_geometry_parameters.hpp"
#include "apps/scenes/solid/solid_run.hpp"
#include "cardio/active_tension.hpp"
#include "cardio/cavity_pressure.hpp"
#include "cardio/circulation.hpp"
#include "cardio/electromechanics.hpp"
#include "cardio/monodomain.hpp"

namespace cardiosph {

using sph::Real;

enum class CellModel { aliev_panfilov, aliev_panfilov_dimensionless, ten_tusscher_panfilov };
enum class StimulusSite { lv_apex, point, box, surface, nodes, endocardium };
enum class Preset { coarse, standard, fine, sphinxsys };
enum class BaseCondition { springs, clamp };
enum class PassiveLaw { holzapfel_ogden_2009, holzapfel_ogden_2009_transverse, zhang_2021 };

/// The heart's pseudo-ECG: the 12 leads by default.
inline EcgParameters twelve_lead_ecg() {
  EcgParameters e;
  e.mode = "twelve_lead";
  return e;
}

struct HeartParameters {
  HeartGeometryParameters geometry;
  Preset preset = Preset::standard;
  // Electrophysiology.
  CellModel cell_model = CellModel::ten_tusscher_panfilov;
  double diffusivity_fibre = 0, diffusivity_cross = 0;  ///< 0: the cell model's default
  double stimulus_strength = 50, stimulus_duration = 2, stimulus_radius = 5;
  /// stimulus_site = endocardium: speed [mm/ms] of the Purkinje surrogate that paces each endocardial
  /// particle at its distance from the LV apex over this speed: an effective speed, calibrated so that
  /// the coarse heart activates in 60-80 ms (Durrer et al. 1970), below the 2-4 m/s of Purkinje fibres
  /// because the straight distance is shorter than the paths of the network.
  double purkinje_velocity = 1.1;
  StimulusSite stimulus_site = StimulusSite::endocardium;
  std::string stimulus_surface = "lv_endo";
  std::filesystem::path stimulus_nodes;
  /// stimulus_site = endocardium: where the surrogate starts (lv_apex, durrer, or early_site_list).
  std::string early_sites = "lv_apex";
  std::string early_site_list;        ///< "x,y,z@t;..." [mm, ms] for early_sites = list
  double endocardial_conduction = 1;  ///< factor on D of the endocardial particles (a fast layer)
  Eigen::Vector3d stimulus_point = Eigen::Vector3d::Zero();
  Eigen::Vector3d stimulus_box_min = Eigen::Vector3d::Zero(), stimulus_box_max = Eigen::Vector3d::Zero();
  long beats = 6;              ///< at most; fewer once the stroke volumes agree within beat_tolerance
  double beat_tolerance = 0.02;  ///< relative change of both stroke volumes between two beats (0: run every beat)
  double cycle_length = 800;
  double end_time = 0;  ///< 0: preload + beats x cycle length
  /// The monodomain's numerics: a 0.1 ms splitting step (the coupling step) and clipped negative
  /// diffusion coefficients on the heart's thin, irregular walls (docs/electromechanics.md).
  cardio::MonodomainNumerics monodomain{sph::ReactionScheme::rbr_qss, Real(0.1),
                                        {sph::DiffusionCorrection::moment, sph::DiffusionIntegrator::forward_euler,
                                         Real(0.9), true}};
  cardio::ElectromechanicsSettings coupling;
  double apd_percent = 90;  ///< action potential maps (cardio/ep_maps.hpp); 0: none
  CellVariationParameters cells;
  EcgParameters ecg = twelve_lead_ecg();
  // Active tension.
  cardio::TensionModel tension_model = cardio::TensionModel::land_2017;
  double land_reference_tension = 600;  ///< T_ref [kPa] (calibrated, docs/electromechanics.md)
  bool land_velocity_dependence = true;
  double k_a = 0.01;
  double tension_threshold = 1;  ///< V_th - V_r [mV]
  bool tension_allow_negative = false;
  cardio::ActiveTensionSettings tension_rates;  ///< eps_0, eps_inf and xi (k_a and V_th are set above)
  // Mechanics.
  /// Without the sheet terms of the full law, which resist the transmural stretch of a thickening
  /// wall (docs/electromechanics.md, "Solid numerics of the beat").
  PassiveLaw passive_law = PassiveLaw::holzapfel_ogden_2009_transverse;
  double density = 1.06;
  /// Near incompressibility under tensions of tens of kPa: |J - 1| of a few per cent (at 100 kPa,
  /// the value of the potential-driven heart, the Land tension compresses the wall by 20 %).
  double bulk_modulus = 1000;
  double damping_rate = 0.02;
  double clamp_depth = 0;  ///< 0: the particles labelled base; > 0: every particle this close to the base plane
  BaseCondition base_condition = BaseCondition::springs;
  double pericardium_stiffness = 0.2;  ///< [kPa/mm] normal springs on the epicardium
  double base_stiffness = 100;         ///< [kPa/mm] springs on the base, every direction
  cardio::CavityPressureSettings cavity_pressure{cardio::CavityPressureMode::circulation, 1.2, 0.4, 100};
  double preload_time = 150;  ///< [ms] before the first beat (circulation): the ramp to the preload, then rest
  cardio::CirculationSettings circulation;
  double sample_interval = 2;
  SolidSceneNumerics numerics;
  /// A run of the same heart to compare with (its report.json, or the folder holding it): the
  /// report's errors are this run's beat measures against the reference's on the last beat both ran.
  std::filesystem::path reference_run;
};

/// The defaults of the heart scene (the shipped biventricular mesh, the beat's solid numerics and
/// circulation).
HeartParameters heart_defaults();
/// Declares every parameter of the heart scene on p_.
void declare_heart_parameters(sph::Parameters& p, HeartParameters& p_);
/// Throws sph::ParameterError for inconsistent parameters (before anything is written).
void check_heart_parameters(const HeartParameters& p_);

/// The parameters of the default beat that were calibrated, the target each was tuned to and the
/// run it was tuned on (docs/electromechanics.md, "Calibration and where the beat stands"). A check
/// of these targets is a calibration check, not a validation: the tests that assert them are named
/// and labelled so (HeartCalibration, label regression), and the heart's validations use other data.
/// The report lists each with the value of this run, so a changed calibration is visible.
struct CalibratedParameter {
  const char* key;
  double calibrated;
  const char* target;
  const char* tuned_on;
  double (*value)(const HeartParameters&);
};

const std::vector<CalibratedParameter>& calibrated_parameters();

/// The beats (results.beats of report.json) of a reference run, `run` the report or its folder;
/// sph::ParameterError naming the file when it is missing, unreadable or holds no beat.
nlohmann::json reference_beats(const std::filesystem::path& run);

/// The time of the first stimulus: after the preload phase when the circulation drives the cavities.
inline double beat_origin(const HeartParameters& p) {
  return p.cavity_pressure.mode == cardio::CavityPressureMode::circulation ? p.preload_time : 0.0;
}

/// Spacing of each preset on the shipped biventricular heart (the research resolution is "fine").
inline double preset_spacing(Preset preset) {
  switch (preset) {
    case Preset::coarse: return 3.0;
    case Preset::fine: return 1.0;
    case Preset::standard:
    case Preset::sphinxsys: return 2.0;
  }
  return 2.0;
}

}  // namespace cardiosph
