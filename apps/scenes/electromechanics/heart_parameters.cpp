#include "apps/scenes/electromechanics/heart_parameters.hpp"

#include "apps/scenes/electrophysiology/ep_run.hpp"
#include "cardio/early_activation.hpp"
#include "geometry/tet_mesh.hpp"
#include "libsph/io/parameters.hpp"

#include <fstream>

#include <nlohmann/json.hpp>

namespace cardiosph {
namespace {

/// The SPHinXsys heart case (test_3d_heart_electromechanics, ../shared/PARITY.md) in this scene's
/// parameters: its mesh (without the translation, so the boxes are in mesh coordinates: theirs
/// plus (53.5, 70, 32.5) mm), dp 2 mm with h = 1.15 dp, Aliev-Panfilov in its own units with
/// isotropic D = 0.8 and a splitting step of 0.5 h^2 / (3 D) = 1.102, their tension law
/// (100 k_a V with k_a = 1e-4 MPa = 10 kPa per unit of V, eps 0.1 to 1 switching at V = 0.8
/// with xi = 100), K = 495.8 kPa, the base clamped 4 mm deep, the stimulus box raised to V = 0.92
/// (here by a pulse of 0.92 per unit time for one time unit), its solid scheme (no hourglass
/// control, its pair viscosity 0.25, the acoustic step of the small-strain modulus), and end time 100.
std::vector<std::pair<std::string, std::string>> sphinxsys_preset() {
  return {{"mesh", shared_mesh("biventricular_heart.stl").string()},
          {"dp", "2"},
          {"smoothing_length_ratio", "1.15"},
          {"kernel", "wendland_c2"},
          {"cell_model", "aliev_panfilov_dimensionless"},
          {"tension_model", "nash_panfilov"},
          {"passive_law", "zhang_2021"},
          {"cavity_pressure", "none"},
          {"base_condition", "clamp"},
          {"beats", "1"},
          {"diffusivity_fibre", "0.8"},
          {"diffusivity_cross", "0.8"},
          {"ep_time_step", "1.102"},
          {"stimulus_site", "box"},
          {"stimulus_box_min", "23.5,68,29.5"},
          {"stimulus_box_max", "38.5,70,35.5"},
          {"stimulus_strength", "0.92"},
          {"stimulus_duration", "1"},
          {"cycle_length", "100"},
          {"k_a", "10"},
          {"tension_threshold", "0.8"},
          {"tension_rate_rest", "0.1"},
          {"tension_rate_active", "1"},
          {"tension_steepness", "100"},
          {"bulk_modulus", "495.8"},
          {"clamp_depth", "4"},
          {"acoustic_cfl", "0.6"},
          {"hourglass_coefficient", "0"},
          {"hourglass_control", "penalty"},
          {"mass_scaling", "1"},
          {"artificial_viscosity", "0.25"},
          {"tangent_time_step", "false"},
          {"output_interval", "0"}};
}

}  // namespace

HeartParameters heart_defaults() {
  HeartParameters p;
  p.geometry.settings.mesh = shipped_mesh("biventricular.stl");
  p.geometry.settings.spacing = 0;
  p.geometry.dp_from_preset = true;
  p.geometry.settings.relaxation_steps = 60;
  p.numerics.discretisation.output_interval = 20;
  // The beat's solid numerics (docs/electromechanics.md, "A physiological beat"): inertia scaled by
  // 16 (the beat is slow against the wall's acoustic time; its ejection fractions within 0.1
  // percentage point of those at 4, "What sizes the mechanics step"), the conservative hourglass control and
  // the pair viscosity, which damp the particle-scale modes that physiological tension excites,
  // and a step of 0.45 of the acoustic limit (at 0.6 the transversely isotropic wall inverted).
  p.numerics.solid.mass_scaling = 16;
  // The cells' functions of V from lookup tables of 0.05 mV: the beat within 1e-4 ms of APD90,
  // 14 % less time for the cells (docs/electrophysiology.md, "Lookup tables").
  p.cells.lookup_table = 0.05;
  // Quiescent cells (in diastole) step every 1 ms instead of every 0.05 ms
  // (docs/electrophysiology.md, "Quiescent cells").
  p.monodomain.quiescent_step = 1;
  p.numerics.solid.hourglass_control = sph::HourglassControl::energy;
  p.numerics.solid.artificial_viscosity = Real(0.25);
  p.numerics.solid.cfl = Real(0.45);
  // The closed loop of Regazzoni et al. 2022 for this heart, whose cavities hold about half the
  // blood of an adult's (unloaded LV 54 mL): twice their systemic arterial resistance, so that half
  // their cardiac output meets the same arterial pressure, and half their systemic arterial
  // compliance (the impedance doubled with RC kept: an adult's pulse pressure from this smaller
  // stroke volume); a starting state near the beat's own (venous pressures at the preload
  // instead of their 30 and 24 mmHg).
  p.circulation.systemic_arterial.resistance *= 2;
  p.circulation.systemic_arterial.compliance /= 2;
  p.circulation.initial_systemic_venous_pressure = 1.6;
  p.circulation.initial_pulmonary_venous_pressure = 1.4;
  return p;
}

void declare_heart_parameters(sph::Parameters& p, HeartParameters& p_) {
  p_.geometry.declare(p);
  p.add_preset<Preset>("preset", p_.preset,
                       {{"coarse", Preset::coarse}, {"default", Preset::standard}, {"fine", Preset::fine},
                        {"sphinxsys", Preset::sphinxsys, sphinxsys_preset()}},
                       "resolution preset when dp = 0: coarse 3 mm, default 2 mm, fine 1 mm (research resolution); "
                       "sphinxsys: the SPHinXsys heart case (docs/electromechanics.md; needs its mesh, "
                       "$CARDIOSPH_SHARED_MESHES/biventricular_heart.stl)");
  p.add_enum("cell_model", p_.cell_model,
             {{"aliev_panfilov", CellModel::aliev_panfilov},
              {"aliev_panfilov_dimensionless", CellModel::aliev_panfilov_dimensionless},
              {"ten_tusscher_panfilov", CellModel::ten_tusscher_panfilov}},
             "cell model (Aliev-Panfilov with the Nash-Panfilov parameters in mV and ms, the same in its own units "
             "V = u and t = tau, or ten Tusscher-Panfilov 2006 epicardial)");
  p.add("diffusivity_fibre", p_.diffusivity_fibre, "mm^2/ms",
        "D along the fibre (0: 1.0; for ten Tusscher-Panfilov a fast conduction that stands for the Purkinje network "
        "and that the 2-3 mm spacing resolves, where the tissue value 0.13 does not propagate)", sph::Range::non_negative());
  p.add("diffusivity_cross", p_.diffusivity_cross, "mm^2/ms", "D across the fibre (0: a quarter of the fibre value)",
        sph::Range::non_negative());
  p.add_enum("stimulus_site", p_.stimulus_site,
             {{"lv-apex", StimulusSite::lv_apex},
              {"point", StimulusSite::point},
              {"box", StimulusSite::box},
              {"surface", StimulusSite::surface},
              {"nodes", StimulusSite::nodes},
              {"endocardium", StimulusSite::endocardium}},
             "stimulated region: within stimulus_radius of the LV endocardial particle farthest from the base (the LV "
             "apex) or of stimulus_point, the particles in the box stimulus_box_min to stimulus_box_max, the particles "
             "labelled stimulus_surface, those within stimulus_radius of the mesh nodes listed in stimulus_nodes, or "
             "every LV and RV endocardial particle at its distance from the LV apex over purkinje_velocity (a Purkinje "
             "surrogate)");
  p.add_choice("stimulus_surface", p_.stimulus_surface, {"epi", "lv_endo", "rv_endo", "base"},
               "labelled surface for stimulus_site = surface");
  p.add_path("stimulus_nodes", p_.stimulus_nodes,
             "stimulus_site = nodes: node indices of the tetrahedral mesh, an openCARP .vtx file (count, optional "
             "intra/extra, one index per line)");
  p.add("purkinje_velocity", p_.purkinje_velocity, "mm/ms",
        "stimulus_site = endocardium: speed at which the pacing spreads from the LV apex over the endocardia "
        "(Purkinje fibres conduct at 2-4 m/s)", sph::Range::positive());
  p.add_choice("early_sites", p_.early_sites, {"lv_apex", "durrer", "list"},
               "stimulus_site = endocardium: the surrogate spreads from the LV apex, from the four endocardial sites of "
               "Durrer et al. 1970 (LV anterior and posterior paraseptal, LV septal at 0 ms, RV anterior at 5 ms), or "
               "from early_site_list");
  p.add_text("early_site_list", p_.early_site_list, "early-activation sites x,y,z@t;... [mm, ms] for early_sites = list");
  p.add("endocardial_conduction", p_.endocardial_conduction, "1",
        "factor on D of the endocardial particles: a fast endocardial layer standing for the Purkinje network (1: none)",
        sph::Range::positive());
  p.add_vector("stimulus_point", p_.stimulus_point, "mm", "stimulus centre x,y,z for stimulus_site = point", true);
  p.add_vector("stimulus_box_min", p_.stimulus_box_min, "mm", "lowest corner x,y,z of the box for stimulus_site = box", true);
  p.add_vector("stimulus_box_max", p_.stimulus_box_max, "mm", "highest corner x,y,z of the box for stimulus_site = box", true);
  p.add("stimulus_radius", p_.stimulus_radius, "mm", "particles within this distance of the centre are stimulated",
        sph::Range::positive());
  p.add("stimulus_strength", p_.stimulus_strength, "mV/ms", "applied dV/dt of each pulse", sph::Range::positive());
  p.add("stimulus_duration", p_.stimulus_duration, "ms", "length of each pulse", sph::Range::positive());
  p.add("beats", p_.beats, "1", "number of paced beats (at most, with the circulation and beat_tolerance > 0)",
        sph::Range::closed(1, 1000));
  p.add("beat_tolerance", p_.beat_tolerance, "1",
        "stop once both stroke volumes changed by less than this fraction from the beat before (circulation; 0: every beat)",
        sph::Range::closed(0, 1));
  p.add("cycle_length", p_.cycle_length, "ms", "pacing period", sph::Range::positive());
  p.add("end_time", p_.end_time, "ms", "simulated time (0: preload_time + beats x cycle_length)", sph::Range::non_negative());
  cardio::declare_parameters(p, p_.monodomain, "ms");
  declare_apd_percent(p, p_.apd_percent);
  declare_parameters(p, p_.ecg, {"twelve_lead"});
  declare_parameters(p, p_.cells, true);
  p.add("deformed_conduction", p_.coupling.deformed_conduction,
        "conduction follows the deformed fibres (D pulled back through F); false: D of the reference configuration");
  p.add("conduction_update_interval", p_.coupling.conduction_update_interval, "ms",
        "time between updates of the pulled-back D", sph::Range::positive());
  p.add_enum("tension_model", p_.tension_model,
             {{"land_2017", cardio::TensionModel::land_2017}, {"nash_panfilov", cardio::TensionModel::nash_panfilov}},
             "active tension: Land et al. 2017 crossbridges driven by the calcium of ten Tusscher-Panfilov and the fibre "
             "stretch, or Nash-Panfilov driven by the potential (k_a, tension_*)");
  p.add("land_reference_tension", p_.land_reference_tension, "kPa", "T_ref of the Land model, its maximal isometric tension (Land et al. 2017: 120 at the cell; "
        "600 calibrated for the default heart's ejection, docs/electromechanics.md)", sph::Range::positive());
  p.add("land_velocity_dependence", p_.land_velocity_dependence,
        "the Land model sees the fibre stretch rate (crossbridge distortion); false: the length dependence only");
  p.add("k_a", p_.k_a, "kPa/mV", "active tension per mV above rest (Nash-Panfilov k_a; the SPHinXsys heart: 0.1, i.e. 10 kPa per unit of u)",
        sph::Range::non_negative());
  p.add("tension_threshold", p_.tension_threshold, "mV", "V_th - V_r of the activation function eps(V)", sph::Range::any());
  p.add("tension_allow_negative", p_.tension_allow_negative, "let the active tension fall below zero");
  p.add("tension_rate_rest", p_.tension_rates.eps_rest, "1/ms", "eps_0: rate of dT_a/dt at rest (relaxation)", sph::Range::positive());
  p.add("tension_rate_active", p_.tension_rates.eps_active, "1/ms", "eps_inf: rate of dT_a/dt once excited (development)",
        sph::Range::positive());
  p.add("tension_steepness", p_.tension_rates.steepness, "1/mV", "xi: how sharply eps switches at the threshold",
        sph::Range::positive());
  p.add_enum("passive_law", p_.passive_law,
             {{"holzapfel_ogden_2009", PassiveLaw::holzapfel_ogden_2009},
              {"holzapfel_ogden_2009_transverse", PassiveLaw::holzapfel_ogden_2009_transverse},
              {"zhang_2021", PassiveLaw::zhang_2021}},
             "Holzapfel-Ogden constants: those of Holzapfel & Ogden 2009 (Phil. Trans. R. Soc. A 367:3445, fitted to "
             "shear tests of human-like myocardium), the same without the sheet and fibre-sheet terms (transversely "
             "isotropic, the default: the wall thickens in systole instead of compressing; docs/electromechanics.md), "
             "or those of the SPHinXsys heart case (Zhang et al. 2021), stiffer");
  p.add("density", p_.density, "mg/mm^3", "tissue density", sph::Range::positive());
  p.add("bulk_modulus", p_.bulk_modulus, "kPa", "K of the volumetric penalty (near incompressibility)", sph::Range::positive());
  p.add("damping_rate", p_.damping_rate, "1/ms", "velocity damping c of dv/dt = ... - c v (surrounding tissue and blood)",
        sph::Range::non_negative());
  p.add("clamp_depth", p_.clamp_depth, "mm",
        "fixed particles: 0, those labelled base; > 0, every particle within this distance of the base plane",
        sph::Range::non_negative());
  p.add_enum("base_condition", p_.base_condition, {{"springs", BaseCondition::springs}, {"clamp", BaseCondition::clamp}},
             "the base: springs (base_stiffness) with the pericardium as normal springs on the epicardium "
             "(pericardium_stiffness), or clamped (clamp_depth; no pericardium)");
  p.add("pericardium_stiffness", p_.pericardium_stiffness, "kPa/mm",
        "normal spring per epicardial area (Robin condition; Regazzoni et al. 2022: 0.2)", sph::Range::non_negative());
  p.add("base_stiffness", p_.base_stiffness, "kPa/mm", "spring per base area, every direction", sph::Range::non_negative());
  cardio::declare_parameters(p, p_.cavity_pressure);
  p.add("preload_time", p_.preload_time, "ms",
        "with cavity_pressure = circulation: time before the first stimulus, in which the cavities are inflated to "
        "lv_pressure and rv_pressure (ramped over pressure_ramp_time)", sph::Range::non_negative());
  cardio::declare_parameters(p, p_.circulation, false);
  p.add("sample_interval", p_.sample_interval, "ms", "time between rows of cavities.csv and observers.csv",
        sph::Range::positive());
  declare_solid_numerics(p, p_.numerics, "ms");
  p.add_path("reference_run", p_.reference_run,
             "report.json of a run of the same heart (or its folder): the report's errors are this run's ejection "
             "fractions, peak and end-diastolic pressures against it, on the last beat both ran (for `study`)");
}

void check_heart_parameters(const HeartParameters& p_) {
  (void)p_.geometry.resolved(preset_spacing(p_.preset));
  if (p_.tension_model == cardio::TensionModel::land_2017 && p_.cell_model != CellModel::ten_tusscher_panfilov)
    throw sph::ParameterError("parameter 'tension_model' = land_2017 needs the calcium of cell_model = ten_tusscher_panfilov");
  if (p_.cavity_pressure.mode == cardio::CavityPressureMode::circulation) {
    if (p_.preload_time < p_.cavity_pressure.ramp_time)
      throw sph::ParameterError("parameter 'preload_time' must be at least 'pressure_ramp_time' (the preload ramp)");
    try {
      auto c = p_.circulation;
      c.lv_mode = c.rv_mode = cardio::VentricleMode::coupled;
      c.heart_period = p_.cycle_length;
      c.check();
    } catch (const std::invalid_argument& e) {
      throw sph::ParameterError(e.what());
    }
  }
  if (p_.stimulus_duration >= p_.cycle_length)
    throw sph::ParameterError("parameter 'stimulus_duration' must be shorter than 'cycle_length'");
  if (p_.ecg.mode == "electrodes") (void)parse_electrodes(p_.ecg.electrodes);
  if (p_.early_sites == "list") (void)cardio::parse_early_sites(p_.early_site_list);
  const auto cells = cell_heterogeneity(p_.cells);
  if (p_.cell_model != CellModel::ten_tusscher_panfilov &&
      (cells.transmural || cells.needs_coordinates() || !cells.scalings.empty() || !cells.drugs.empty() ||
       cells.uniform_type != sph::TenTusscherPanfilov2006::CellType::epicardial))
    throw sph::ParameterError("the cell types, conductance scalings, drug block and populations need cell_model = "
                              "ten_tusscher_panfilov");
  if (p_.stimulus_site == StimulusSite::nodes) {
    if (p_.stimulus_nodes.empty()) throw sph::ParameterError("stimulus_site = nodes needs parameter 'stimulus_nodes' (a .vtx file)");
    if (!geometry::is_tet_mesh_file(p_.geometry.settings.mesh))
      throw sph::ParameterError("stimulus_site = nodes needs a tetrahedral 'mesh' (.vtu, .pts/.elem), not '" +
                                p_.geometry.settings.mesh.string() + "'");
  }
  if (p_.stimulus_site == StimulusSite::box && !(p_.stimulus_box_min.array() < p_.stimulus_box_max.array()).all())
    throw sph::ParameterError("parameter 'stimulus_box_min' must lie below 'stimulus_box_max' in x, y and z");
  if (!p_.reference_run.empty()) {
    if (p_.cavity_pressure.mode != cardio::CavityPressureMode::circulation)
      throw sph::ParameterError("parameter 'reference_run' compares beats: it needs cavity_pressure = circulation");
    (void)reference_beats(p_.reference_run);
  }
}

nlohmann::json reference_beats(const std::filesystem::path& run) {
  const auto file = std::filesystem::is_directory(run) ? run / "report.json" : run;
  std::ifstream in(file);
  if (!in) throw sph::ParameterError("parameter 'reference_run': cannot read '" + file.string() + "'");
  nlohmann::json report;
  try {
    report = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw sph::ParameterError("parameter 'reference_run': '" + file.string() + "' is not a report (" + e.what() + ")");
  }
  const auto results = report.find("results");
  if (results == report.end() || !results->contains("beats") || !(*results)["beats"].is_array() || (*results)["beats"].empty())
    throw sph::ParameterError("parameter 'reference_run': '" + file.string() +
                              "' holds no beat (a heart run with cavity_pressure = circulation that completed a beat)");
  return (*results)["beats"];
}

const std::vector<CalibratedParameter>& calibrated_parameters() {
  static const std::vector<CalibratedParameter> table{
      {"land_reference_tension", 600, "LV EF 55-65 %, LV peak 15-17 kPa (from Land et al. 2017's 120 kPa)",
       "coarse heart (dp 3 mm), first beat", [](const HeartParameters& p) { return p.land_reference_tension; }},
      {"purkinje_velocity", 1.1, "total activation 60-80 ms (Durrer et al. 1970)", "coarse heart, first beat",
       [](const HeartParameters& p) { return p.purkinje_velocity; }},
      {"circulation_systemic_arterial_resistance", 2 * cardio::CirculationSettings{}.systemic_arterial.resistance,
       "LV peak 15-17 kPa (twice Regazzoni et al. 2022's, for a heart with half an adult's blood)", "coarse heart, first beat",
       [](const HeartParameters& p) { return p.circulation.systemic_arterial.resistance; }},
      {"circulation_systemic_arterial_compliance", cardio::CirculationSettings{}.systemic_arterial.compliance / 2,
       "LV peak 15-17 kPa (half Regazzoni et al. 2022's, RC kept)", "coarse heart, first beat",
       [](const HeartParameters& p) { return p.circulation.systemic_arterial.compliance; }},
      {"circulation_initial_systemic_venous_pressure", 1.6, "a starting state near the beat's own (fewer beats to settle)",
       "default heart (dp 2 mm), beats 1-4", [](const HeartParameters& p) { return p.circulation.initial_systemic_venous_pressure; }},
      {"circulation_initial_pulmonary_venous_pressure", 1.4, "a starting state near the beat's own (fewer beats to settle)",
       "default heart, beats 1-4", [](const HeartParameters& p) { return p.circulation.initial_pulmonary_venous_pressure; }},
      {"lv_pressure", 1.2, "LV EDP 1-1.6 kPa (the preload sets it)", "chosen inside the range",
       [](const HeartParameters& p) { return p.cavity_pressure.lv_pressure; }},
      {"rv_pressure", 0.4, "RV filling (the preload)", "chosen", [](const HeartParameters& p) { return p.cavity_pressure.rv_pressure; }},
      {"base_stiffness", 100, "the RV free wall's base edge does not invert; LV EF", "coarse heart, first beat; default heart, beats 1-2",
       [](const HeartParameters& p) { return p.base_stiffness; }},
      {"passive_law (1: without the sheet terms)", 1, "LV EF 55-65 % (the sheet term resists wall thickening)",
       "coarse heart, first beat",
       [](const HeartParameters& p) { return p.passive_law == PassiveLaw::holzapfel_ogden_2009_transverse ? 1.0 : 0.0; }},
      {"bulk_modulus", 1000, "|J - 1| of a few per cent under the Land tension", "coarse heart, first beat",
       [](const HeartParameters& p) { return p.bulk_modulus; }},
      {"mass_scaling", 16, "a stable beat at an affordable step; EFs within 0.1 point of 4", "default heart, first beat",
       [](const HeartParameters& p) { return double(p.numerics.solid.mass_scaling); }},
      {"acoustic_cfl", double(Real(0.45)), "no inversion on the RV free wall", "default heart, beats 1-2",
       [](const HeartParameters& p) { return double(p.numerics.solid.cfl); }},
  };
  return table;
}

}  // namespace cardiosph
