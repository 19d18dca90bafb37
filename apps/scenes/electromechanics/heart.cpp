// `cardiosph heart`: excitation-contraction of a ventricular mesh on one particle set, beating
// against a circulation.
//
// Geometry: the cached heart-geometry stage (particles, surface labels, LDRB fibres). Physics
// (docs/electromechanics.md, "A physiological beat"): monodomain with ten Tusscher-Panfilov 2006
// (or Aliev-Panfilov) cells, conduction D_l along the fibre and D_t across, pulled back through F
// (cardio/electromechanics.hpp); Land et al. 2017 tension from the cells' calcium and the fibre
// stretch (or Nash-Panfilov from the potential; cardio/active_tension.hpp); Holzapfel-Ogden
// passive law plus the active stress T_a f0 (x) f0; pericardial and base springs (or a clamped
// base). Cavity volumes from the labelled endocardia moved with the tissue (cardio/cavity.hpp);
// the cavity pressure from the 0D circulation (cardio/circulation.hpp: closed loop or Windkessel,
// after a preload) or constant, ramped or none. The run ends when the stroke volumes settle.
//
// Outputs: heart_*.vtu / heart.pvd (potential, activation time, T_a, displacement, J, fibre stretch,
// von Mises stress, labels, fibres), cavities.csv (volumes, pressures, energies, J range, peak T_a),
// observers.csv (potential, T_a and displacement at three particles), circulation.csv and
// pv_loop.png (with the circulation), report.json (per-beat PV measures, healthy ranges, timings).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include "apps/scenes/electromechanics/em_scenes.hpp"
#include "apps/scenes/electromechanics/em_setup.hpp"
#include "apps/scenes/electrophysiology/cell_variation.hpp"
#include "apps/scenes/electrophysiology/ecg_output.hpp"
#include "apps/scenes/electrophysiology/ep_run.hpp"
#include "apps/scenes/geometry/heart_geometry_parameters.hpp"
#include "apps/scenes/solid/solid_run.hpp"
#include "apps/plot.hpp"
#include "cardio/beat_metrics.hpp"
#include "cardio/cavity.hpp"
#include "cardio/cavity_pressure.hpp"
#include "cardio/circulation.hpp"
#include "cardio/electromechanics.hpp"
#include "libsph/core/numerical_failure.hpp"
#include "libsph/io/atomic_file.hpp"
#include "libsph/core/parallel.hpp"
#include "libsph/core/point_probes.hpp"
#include "libsph/io/run_harness.hpp"

namespace cardiosph {
namespace {

using sph::Real;
using Vec3 = sph::Vec<3>;

enum class CellModel { aliev_panfilov, aliev_panfilov_dimensionless, ten_tusscher_panfilov };
enum class StimulusSite { lv_apex, point, box, surface, nodes, endocardium };
enum class Preset { coarse, standard, fine, sphinxsys };
enum class BaseCondition { springs, clamp };
enum class PassiveLaw { holzapfel_ogden_2009, holzapfel_ogden_2009_transverse, zhang_2021 };

/// The heart's pseudo-ECG: the 12 leads by default.
EcgParameters twelve_lead_ecg() {
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
};

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
      {"mass_scaling", 4, "a stable beat at an affordable step", "coarse heart, first beat",
       [](const HeartParameters& p) { return double(p.numerics.solid.mass_scaling); }},
      {"acoustic_cfl", double(Real(0.45)), "no inversion on the RV free wall", "default heart, beats 1-2",
       [](const HeartParameters& p) { return double(p.numerics.solid.cfl); }},
  };
  return table;
}

/// An early-activation site of the endocardial Purkinje surrogate: position [mm] and time [ms].
struct EarlySite {
  Vec3 position;
  double time = 0;
};

/// "x,y,z@t;..." into sites; throws sph::ParameterError naming 'early_site_list' and the entry.
std::vector<EarlySite> parse_early_sites(const std::string& text) {
  std::vector<EarlySite> sites;
  std::istringstream entries(text);
  std::string entry;
  while (std::getline(entries, entry, ';')) {
    if (entry.find_first_not_of(" \t") == std::string::npos) continue;
    auto fail = [&] {
      return sph::ParameterError("parameter 'early_site_list': entry '" + entry + "' is not x,y,z@t (mm, ms)");
    };
    double x = 0, y = 0, z = 0, t = 0;
    char c1 = 0, c2 = 0, at = 0;
    std::istringstream in(entry);
    if (!(in >> x >> c1 >> y >> c2 >> z >> at >> t) || c1 != ',' || c2 != ',' || at != '@') throw fail();
    std::string rest;
    if (in >> rest || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z) || !(t >= 0) || !std::isfinite(t)) throw fail();
    sites.push_back({Vec3(Real(x), Real(y), Real(z)), t});
  }
  if (sites.empty()) throw sph::ParameterError("parameter 'early_site_list' names no site (early_sites = list)");
  return sites;
}

/// The time of the first stimulus: after the preload phase when the circulation drives the cavities.
double beat_origin(const HeartParameters& p) {
  return p.cavity_pressure.mode == cardio::CavityPressureMode::circulation ? p.preload_time : 0.0;
}

/// Spacing of each preset on the shipped biventricular heart (the research resolution is "fine").
double preset_spacing(Preset preset) {
  switch (preset) {
    case Preset::coarse: return 3.0;
    case Preset::fine: return 1.0;
    case Preset::standard:
    case Preset::sphinxsys: return 2.0;
  }
  return 2.0;
}

/// The LV endocardial particle farthest from the base (along -base normal): the apex stimulus site.
Vec3 lv_apex(const cardio::HeartGeometry& g, std::span<const Vec3> x) {
  const Vec3 normal = g.base_normal.cast<Real>();
  Real farthest = -std::numeric_limits<Real>::infinity();
  Vec3 apex = Vec3::Zero();
  for (std::size_t i = 0; i < x.size(); ++i)
    if (g.labels[i] == cardio::label_lv_endo && -normal.dot(x[i]) > farthest) {
      farthest = -normal.dot(x[i]);
      apex = x[i];
    }
  if (!std::isfinite(farthest)) throw std::invalid_argument("heart: no LV endocardium labelled, so no lv-apex stimulus site");
  return apex;
}

/// The systems of one heart on one particle set, built in the order the physics needs them:
/// particles and relation, the solid (fibres, clamped base), the monodomain (conduction along the
/// solid's fibres, stimulus), the active tension on the monodomain's potential, and the cavities
/// with their pressure loads on the solid.
class HeartModel {
 public:
  HeartModel(const HeartParameters& p, const cardio::HeartGeometry& g, const cardio::HeartGeometrySettings& gs)
      : dp(Real(gs.spacing)),
        h(Real(p.numerics.discretisation.smoothing_length_ratio) * dp),
        kernel(sph::make_kernel<3>(p.numerics.discretisation.kernel)),
        labels(g.labels),
        body(particle_set(g)),
        relation(sph::build_inner_relation<3>(body.position, kernel, h)),
        solid(body, relation, solid_settings(p)),
        base(attach_heart_geometry(solid, g, "heart", Real(p.clamp_depth), p.base_condition == BaseCondition::clamp)),
        ttp(p.cell_model == CellModel::ten_tusscher_panfilov),
        dimensionless(p.cell_model == CellModel::aliev_panfilov_dimensionless),
        D_fibre(p.diffusivity_fibre > 0 ? p.diffusivity_fibre : 1.0),
        D_cross(p.diffusivity_cross > 0 ? p.diffusivity_cross : D_fibre / 4),
        stimulus_centre(stimulus_centre_of(p, g)),
        monodomain(body, relation, monodomain_settings(p, g)),
        tension(body, p.tension_model == cardio::TensionModel::land_2017 ? monodomain.calcium_field() : monodomain.potential_field(),
                tension_settings(p)),
        X(body.field(solid.reference_position_field())) {
    // Cavities: the labelled endocardia, moved with the tissue, each with its pressure.
    const auto mesh = read_geometry_mesh(gs);
    const std::vector<Real> volumes(body.volume.begin(), body.volume.end());
    const auto face_labels = cavity_face_labels(mesh, g);
    cavities = cardio::cavity_surfaces(mesh, face_labels, body.position, volumes, g.labels, dp, kernel, h);
    for (const auto& c : cavities)
      pressures.emplace_back(p.cavity_pressure, c.label == cardio::label_lv_endo ? p.cavity_pressure.lv_pressure
                                                                                 : p.cavity_pressure.rv_pressure);
    for (std::size_t c = 0; c < cavities.size(); ++c)
      if (pressures[c].active())
        wall_loads.push_back([this, c](Real t, std::span<Vec3> force) {
          const auto F = body.field(solid.deformation_gradient_field());
          if (pressure_of_volume)
            cavities[c].add_pressure_forces([this, c](double V) { return Real(pressure_of_volume(c, V)); }, body.position, F, X, force);
          else
            cavities[c].add_pressure_forces(Real(pressures[c].at(double(t))), body.position, F, X, force);
        });
    if (p.base_condition == BaseCondition::springs) add_springs(p, mesh, face_labels, volumes, g.labels);
  }
  HeartModel(const HeartModel&) = delete;

  std::size_t n() const { return body.n_particles(); }
  double cavity_volume(std::size_t c) const {
    return cavities[c].volume(body.position, body.field(solid.deformation_gradient_field()), X);
  }
  std::string cavity_name(std::size_t c) const { return cavities[c].label == cardio::label_lv_endo ? "lv" : "rv"; }
  double max_displacement() const {
    return sph::parallel_max(n(), Real(0), [&](std::size_t i) { return (body.position[i] - X[i]).norm(); });
  }
  double mean_potential() const {
    const auto V = body.field(monodomain.potential_field());
    return sph::parallel_sum(n(), 0.0, [&](std::size_t i) { return double(V[i]); }) / double(n());
  }
  double max_tension() const {
    const auto& T = tension.tension();
    return *std::max_element(T.begin(), T.end());
  }

  const Real dp, h;
  const sph::AnyKernel<3> kernel;
  const std::span<const std::int8_t> labels;  ///< cardio::SurfaceLabel per particle
  sph::ParticleSet<3> body;
  const sph::InnerRelation<3> relation;
  sph::ElasticSolid<3> solid;
  const std::vector<sph::Index> base;
  const bool ttp, dimensionless;
  const double D_fibre, D_cross;
  const Vec3 stimulus_centre;
  std::size_t stimulated = 0;
  cardio::CellGroups cell_groups;  ///< the cell types and scalings of the ten Tusscher-Panfilov tissue
  std::vector<EarlySite> early;    ///< the early-activation sites of the endocardial surrogate
  cardio::Monodomain<3> monodomain;
  cardio::ActiveTension<3> tension;
  std::span<const Vec3> X;
  std::vector<cardio::CavitySurface> cavities;
  std::vector<cardio::CavityPressure> pressures;
  std::vector<cardio::CavitySurface> spring_surfaces;  ///< epicardium and base (base_condition = springs)
  /// When set (the circulation, once started): the pressure of cavity c at its current volume,
  /// evaluated at every mechanics sub-step.
  std::function<double(std::size_t cavity, double volume)> pressure_of_volume;
  /// The loads on the wall at the mid-step (cavity pressures, springs): force added per particle.
  std::vector<std::function<void(Real time, std::span<Vec3> force)>> wall_loads;

 private:
  /// The pericardium and the base as springs on the surface particles, per reference area A_i n_i
  /// of the mesh faces nearest to each (CavitySurface::area_normals), on the displacement u = x - X:
  ///   epicardium: f_i = -k_peri (u_i . n_i) n_i |A_i|   (normal Robin condition: the pericardial sac
  ///               resists motion along the normal and lets the wall slide along it);
  ///   base:       f_i = -k_base u_i |A_i|               (every direction).
  /// As in the pericardium model of Pfaller et al. 2019 (Biomech. Model. Mechanobiol. 18:503) and
  /// Regazzoni et al. 2022 (J. Comput. Phys. 457:111083), without their damping term (the solid's
  /// velocity damping stands for it).
  void add_springs(const HeartParameters& p, const geometry::TriangleMesh& mesh, std::span<const cardio::SurfaceLabel> face_labels,
                   std::span<const Real> volumes, std::span<const std::int8_t> particle_labels) {
    static constexpr cardio::SurfaceLabel wanted[] = {cardio::label_epi, cardio::label_base};
    spring_surfaces = cardio::cavity_surfaces(mesh, face_labels, body.position, volumes, particle_labels, dp, kernel, h, wanted);
    bool has_base = false;
    for (const auto& surface : spring_surfaces) {
      const bool normal_only = surface.label == cardio::label_epi;
      has_base = has_base || surface.label == cardio::label_base;
      const Real k = Real(normal_only ? p.pericardium_stiffness : p.base_stiffness);
      if (k == 0) continue;
      wall_loads.push_back([this, &surface, normal_only, k](Real, std::span<Vec3> force) {
        for (std::size_t m = 0; m < surface.loaded_particles.size(); ++m) {
          const auto i = surface.loaded_particles[m];
          const Vec3 u = body.position[i] - X[i], A = surface.area_normals[m];
          force[i] -= normal_only ? Vec3(k * u.dot(A) / A.norm() * A) : Vec3(k * A.norm() * u);
        }
      });
    }
    if (!has_base)
      throw std::invalid_argument("heart: no mesh face is labelled base, so base_condition = springs has no base to hold "
                                  "(use base_condition = clamp)");
  }
  static sph::ParticleSet<3> particle_set(const cardio::HeartGeometry& g) {
    auto body = make_particle_set(g, "heart");
    auto label = body.field(body.register_field<int>("label"));
    for (std::size_t i = 0; i < body.n_particles(); ++i) label[i] = g.labels[i];
    return body;
  }
  /// Holzapfel-Ogden (passive_law; kPa) with active stress.
  static sph::ElasticSolid<3>::Settings solid_settings(const HeartParameters& p) {
    sph::ElasticSolid<3>::Settings s;
    auto law = p.passive_law == PassiveLaw::zhang_2021 ? sph::holzapfel_ogden_zhang_2021_kpa<3>(Real(p.bulk_modulus))
                                                       : sph::holzapfel_ogden_2009_kpa<3>(Real(p.bulk_modulus));
    if (p.passive_law == PassiveLaw::holzapfel_ogden_2009_transverse) law.a_s = law.a_fs = 0;
    s.material = law;
    s.density = Real(p.density);
    s.damping_rate = Real(p.damping_rate);
    s.active_stress = true;
    s.active_stiffness = p.tension_model == cardio::TensionModel::land_2017 && p.land_velocity_dependence;
    s.active_tension_non_negative = !p.tension_allow_negative;
    s.numerics = p.numerics.solid;
    return s;
  }
  /// Aliev-Panfilov (Nash-Panfilov parameters) or ten Tusscher-Panfilov 2006, conduction D_l along
  /// the solid's fibres and D_t across, and the paced stimulus within the radius of the centre.
  cardio::Monodomain<3>::Settings monodomain_settings(const HeartParameters& p, const cardio::HeartGeometry& g) {
    cardio::Monodomain<3>::Settings ep;
    if (ttp) {
      const auto& f = g.fibres;
      const auto cells = cell_heterogeneity(p.cells);
      const auto in_rv = cells.needs_coordinates() && f.lv.size() == n() ? cardio::rv_ventricle(f.lv, f.rv, relation)
                                                                         : std::vector<std::uint8_t>{};
      cell_groups = cardio::ten_tusscher_groups(cells, n(), f.transmural, f.apicobasal, in_rv);
      if (cell_groups.models.size() == 1) ep.cell_model = cell_groups.models[0];
      else ep.cell_variants = cell_groups.models, ep.cell_variant = cell_groups.group;
    }
    else if (dimensionless) ep.cell_model = nash_panfilov_dimensionless();
    else ep.cell_model = sph::AlievPanfilov::nash_panfilov_2004();
    ep.numerics = p.monodomain;
    ep.repolarisation_percent = Real(p.apd_percent);
    ep.longitudinal_diffusivity = Real(D_fibre);
    ep.transverse_diffusivity = Real(D_cross);
    const auto f = body.field(solid.fiber_field());
    // A fast endocardial layer: D times endocardial_conduction on the endocardial particles.
    if (p.endocardial_conduction != 1) {
      ep.conduction_scale.assign(n(), Real(1));
      for (std::size_t i = 0; i < n(); ++i)
        if (labels[i] == cardio::label_lv_endo || labels[i] == cardio::label_rv_endo)
          ep.conduction_scale[i] = Real(p.endocardial_conduction);
    }
    ep.diffusion_tensor.resize(n());
    for (std::size_t i = 0; i < n(); ++i) {
      const Real k = ep.conduction_scale.empty() ? Real(1) : ep.conduction_scale[i];
      ep.diffusion_tensor[i] = sph::transversely_isotropic_tensor<3>(k * Real(D_fibre), k * Real(D_cross), f[i]);
    }
    cardio::Monodomain<3>::StimulusRegion stimulus;
    const Vec3 lo = p.stimulus_box_min.cast<Real>(), hi = p.stimulus_box_max.cast<Real>();
    switch (p.stimulus_site) {
      case StimulusSite::box:
        stimulus.name = "box";
        for (std::size_t i = 0; i < n(); ++i)
          if ((body.position[i].array() >= lo.array()).all() && (body.position[i].array() <= hi.array()).all())
            stimulus.particles.push_back(i);
        if (stimulus.particles.empty())
          throw sph::ParameterError("no particle lies in the stimulus box " + sph::NumericalFailure::format_position(lo) +
                                    " to " + sph::NumericalFailure::format_position(hi) +
                                    " ('stimulus_box_min', 'stimulus_box_max', mesh coordinates)");
        break;
      case StimulusSite::point:
      case StimulusSite::lv_apex:
        stimulus.name = p.stimulus_site == StimulusSite::point ? "point" : "lv-apex";
        for (std::size_t i = 0; i < n(); ++i)
          if ((body.position[i] - stimulus_centre).norm() <= p.stimulus_radius) stimulus.particles.push_back(i);
        if (stimulus.particles.empty())
          throw sph::ParameterError("no particle lies within 'stimulus_radius' of the stimulus centre " +
                                    sph::NumericalFailure::format_position(stimulus_centre));
        break;
      case StimulusSite::surface: {
        const auto label = cardio::label_of_surface_name(p.stimulus_surface);
        stimulus.name = p.stimulus_surface;
        for (std::size_t i = 0; i < n(); ++i)
          if (labels[i] == label) stimulus.particles.push_back(i);
        if (stimulus.particles.empty())
          throw sph::ParameterError("parameter 'stimulus_surface' = " + p.stimulus_surface + ": no particle carries that label (labels by " +
                                    g.label_method + ")");
        break;
      }
      case StimulusSite::nodes: {
        // Mesh nodes of the tetrahedral mesh (an openCARP .vtx list): the particles within
        // stimulus_radius of any of them.
        const auto gs = p.geometry.resolved(preset_spacing(p.preset));
        const auto mesh = geometry::read_tet_mesh(gs.mesh, gs.scale);
        const auto nodes = geometry::read_vertex_list(p.stimulus_nodes, mesh.vertices.size());
        stimulus.name = "nodes";
        for (std::size_t i = 0; i < n(); ++i)
          for (std::size_t k : nodes)
            if ((body.position[i] - mesh.vertices[k].cast<Real>()).norm() <= p.stimulus_radius) {
              stimulus.particles.push_back(i);
              break;
            }
        if (stimulus.particles.empty())
          throw sph::ParameterError("no particle lies within 'stimulus_radius' of the " + std::to_string(nodes.size()) +
                                    " nodes of '" + p.stimulus_nodes.string() + "'");
        break;
      }
      case StimulusSite::endocardium: endocardial_stimuli(p, g, ep); break;
    }
    if (p.stimulus_site != StimulusSite::endocardium) {
      stimulated = stimulus.particles.size();
      stimulus.protocol = {beat_origin(p), p.stimulus_duration, p.stimulus_strength, p.cycle_length, int(p.beats)};
      ep.stimuli.push_back(stimulus);
    }
    // Activation: the upstroke through -40 mV (ten Tusscher-Panfilov), -30 mV (u = 0.5), or u = 0.5.
    ep.activation_threshold = ttp ? Real(-40) : dimensionless ? Real(0.5) : Real(-30);
    return ep;
  }
  /// A Purkinje surrogate: every LV and RV endocardial particle is paced at
  ///   t_i = min_k (t_k + |x_i - c_k| / v_P)
  /// after the beat's origin, over the early-activation sites c_k with their times t_k (by default the
  /// LV apex at 0) and v_P = purkinje_velocity. The network that spreads the beat over the
  /// endocardium (Durrer et al. 1970, Circulation 41:899: the human ventricles activate in 60-80 ms
  /// from a few endocardial sites) is not resolved; the tissue conducts from the endocardium
  /// outwards. The pulses of particles whose onsets fall in the same splitting step share one
  /// stimulus region.
  void endocardial_stimuli(const HeartParameters& p, const cardio::HeartGeometry& g, cardio::Monodomain<3>::Settings& ep) {
    early = early_activation_sites(p, g);
    const double bin = double(p.monodomain.time_step);
    std::map<long, cardio::Monodomain<3>::StimulusRegion> regions;
    for (std::size_t i = 0; i < n(); ++i) {
      if (labels[i] != cardio::label_lv_endo && labels[i] != cardio::label_rv_endo) continue;
      double delay = std::numeric_limits<double>::infinity();
      for (const auto& site : early)
        delay = std::min(delay, site.time + double((body.position[i] - site.position).norm()) / p.purkinje_velocity);
      auto& region = regions[std::lround(delay / bin)];
      region.particles.push_back(i);
    }
    if (regions.empty()) throw sph::ParameterError("parameter 'stimulus_site' = endocardium: no particle is labelled LV or RV endocardium");
    stimulated = 0;
    for (auto& [k, region] : regions) {
      char name[64];
      std::snprintf(name, sizeof name, "endocardium +%.2f ms", double(k) * bin);
      region.name = name;
      region.protocol = {beat_origin(p) + double(k) * bin, p.stimulus_duration, p.stimulus_strength, p.cycle_length, int(p.beats)};
      stimulated += region.particles.size();
      ep.stimuli.push_back(std::move(region));
    }
  }
  /// The early-activation sites: the LV apex at 0; a list; or the Durrer preset, four endocardial
  /// sites after Durrer et al. 1970, placed by the LDRB apico-basal coordinate a (0 apex, 1 base;
  /// the bands below are fractions of the range of a over each endocardium) and the heart's frame (long axis, LV-to-RV direction r, and the anterior direction of a heart
  /// placed in the body as for the 12-lead ECG, cardio/pseudo_ecg.hpp):
  ///   LV anterior paraseptal, high (a in [0.7, 0.9], towards r + anterior), 0 ms;
  ///   LV central septal (a in [0.4, 0.6], towards r), 0 ms;
  ///   LV posterior paraseptal, a third from apex to base (a in [0.23, 0.43], towards r - anterior), 0 ms;
  ///   RV anterior free wall near the anterior papillary muscle (a in [0.4, 0.6], anterior), 5 ms
  /// (Durrer: the three LV areas are excited 0-5 ms after the onset, the RV 5-10 ms).
  std::vector<EarlySite> early_activation_sites(const HeartParameters& p, const cardio::HeartGeometry& g) const {
    if (p.early_sites == "lv_apex") return {{stimulus_centre, 0}};
    if (p.early_sites == "list") return parse_early_sites(p.early_site_list);
    const auto& a = g.fibres.apicobasal;
    if (a.size() != n())
      throw sph::ParameterError("parameter 'early_sites' = durrer places its sites by the LDRB apico-basal coordinate, "
                                "which needs labelled epicardium, LV endocardium and base (fibres = ldrb or mesh)");
    Vec3 c_lv = Vec3::Zero(), c_rv = Vec3::Zero();
    std::size_t n_lv = 0, n_rv = 0;
    for (std::size_t i = 0; i < n(); ++i) {
      if (labels[i] == cardio::label_lv_endo) c_lv += body.position[i], ++n_lv;
      if (labels[i] == cardio::label_rv_endo) c_rv += body.position[i], ++n_rv;
    }
    if (n_lv == 0 || n_rv == 0) throw sph::ParameterError("parameter 'early_sites' = durrer needs labelled LV and RV endocardia");
    c_lv /= Real(n_lv);
    c_rv /= Real(n_rv);
    const Vec3 apex = -g.base_normal.cast<Real>().normalized();
    const Vec3 r = (c_rv - c_lv - (c_rv - c_lv).dot(apex) * apex).normalized();
    const Vec3 normal = apex.cross(r);
    // The body's anterior direction in the heart frame (apex (1,1,-1)/sqrt3, RV (-1,1,0)/sqrt2 in
    // body axes left, anterior, superior), without its long-axis part.
    const Vec3 anterior = (Real(std::sqrt(0.5)) * r + Real(std::sqrt(1.0 / 6.0)) * normal).normalized();
    // Bands of a are taken over each endocardium's own range of a (the RV endocardium does not
    // reach the apex).
    auto site = [&](cardio::SurfaceLabel label, double lo, double hi, const Vec3& towards, const Vec3& centre, double time,
                    const char* name) {
      double a_min = std::numeric_limits<double>::infinity(), a_max = -a_min;
      for (std::size_t i = 0; i < n(); ++i)
        if (labels[i] == label) a_min = std::min(a_min, a[i]), a_max = std::max(a_max, a[i]);
      const double from = a_min + lo * (a_max - a_min), to = a_min + hi * (a_max - a_min);
      std::optional<std::size_t> best;
      for (std::size_t i = 0; i < n(); ++i)
        if (labels[i] == label && a[i] >= from && a[i] <= to &&
            (!best || (body.position[i] - centre).dot(towards) > (body.position[*best] - centre).dot(towards)))
          best = i;
      if (!best)
        throw sph::ParameterError(std::string("parameter 'early_sites' = durrer: no endocardial particle for the ") + name +
                                  " site");
      return EarlySite{body.position[*best], time};
    };
    return {site(cardio::label_lv_endo, 0.7, 0.9, (r + anterior).normalized(), c_lv, 0, "LV anterior paraseptal"),
            site(cardio::label_lv_endo, 0.4, 0.6, r, c_lv, 0, "LV septal"),
            site(cardio::label_lv_endo, 0.23, 0.43, (r - anterior).normalized(), c_lv, 0, "LV posterior paraseptal"),
            site(cardio::label_rv_endo, 0.4, 0.6, anterior, c_rv, 5, "RV anterior")};
  }
  /// Aliev-Panfilov with the Nash-Panfilov parameters in its own units (V = u, t = tau), as the
  /// SPHinXsys heart case runs it (../shared/PARITY.md).
  static sph::AlievPanfilov nash_panfilov_dimensionless() {
    auto parameters = sph::AlievPanfilov::nash_panfilov_2004().parameters();
    parameters.scaling = {1, 0, 1};
    return sph::AlievPanfilov(parameters);
  }
  /// The centre of the stimulus: the point, the LV apex, or the centre of the box.
  Vec3 stimulus_centre_of(const HeartParameters& p, const cardio::HeartGeometry& g) const {
    switch (p.stimulus_site) {
      case StimulusSite::point: return p.stimulus_point.cast<Real>();
      case StimulusSite::box: return (Real(0.5) * (p.stimulus_box_min + p.stimulus_box_max)).cast<Real>();
      case StimulusSite::lv_apex:
      case StimulusSite::surface:
      case StimulusSite::nodes:
      case StimulusSite::endocardium: break;
    }
    return lv_apex(g, body.position);
  }
  cardio::ActiveTensionSettings tension_settings(const HeartParameters& p) const {
    const Real rest = body.field(monodomain.potential_field())[0];
    cardio::ActiveTensionSettings ts = p.tension_rates;
    ts.model = p.tension_model;
    ts.land.T_ref = p.land_reference_tension;
    ts.velocity_dependence = p.land_velocity_dependence;
    ts.k_a = p.k_a;
    ts.rest_potential = rest;
    ts.threshold = rest + p.tension_threshold;
    ts.allow_negative = p.tension_allow_negative;
    return ts;
  }
};

/// What the heart records while it beats: cavities.csv (volumes, pressures, energies, J range,
/// peak T_a, mean V), observers.csv (V, T_a and displacement at three material points) and the
/// end-of-beat states, with the extremes that the report needs.
class HeartRecorder {
 public:
  HeartRecorder(HeartModel& heart, sph::RunHarness& run, sph::TimeStepper& stepper, const HeartParameters& p)
      : heart_(heart),
        volume_min_(heart.cavities.size(), std::numeric_limits<double>::infinity()),
        volume_max_(heart.cavities.size(), 0),
        peak_pressure_(heart.cavities.size(), 0),
        probes_(observer_points(), heart.body.position, heart.body.volume, heart.kernel, heart.h) {
    std::vector<std::string> cavity_columns;
    for (std::size_t c = 0; c < heart.cavities.size(); ++c)
      for (const char* q : {"_volume", "_pressure"}) cavity_columns.push_back(heart.cavity_name(c) + q);
    for (const char* column : {"kinetic", "strain", "min_J", "max_J", "max_T_a", "mean_V"}) cavity_columns.push_back(column);
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
                                 {"peak_displacement", &peak_displacement_}})
        a.io(name, *value);
      std::string end_of_beat = end_of_beat_.dump();
      a.io("end_of_beat", end_of_beat);
      if (a.loading()) end_of_beat_ = nlohmann::json::parse(end_of_beat);
    });
  }

  void report(sph::RunReport& r) const {
    for (std::size_t c = 0; c < heart_.cavities.size(); ++c) {
      const std::string name = heart_.cavity_name(c);
      r.results[name + "_reference_volume_mm3"] = heart_.cavities[c].reference_volume;
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
  }

 private:
  /// The particle nearest to the stimulus centre, and the LV and RV endocardial particles farthest from it.
  std::vector<Vec3> observer_points() {
    const auto& x = heart_.body.position;
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
    const auto e = heart_.solid.energies();  // leaves F at the current positions
    std::vector<double> row;
    for (std::size_t c = 0; c < heart_.cavities.size(); ++c) {
      const double v = heart_.cavity_volume(c);
      if (v > volume_max_[c]) volume_max_[c] = v, volume_min_[c] = v;
      volume_min_[c] = std::min(volume_min_[c], v);
      const double pressure = heart_.pressures[c].at(s.time);
      row.insert(row.end(), {v, pressure});
      peak_pressure_[c] = std::max(peak_pressure_[c], pressure);
    }
    const double max_T = heart_.max_tension();
    row.insert(row.end(), {e.kinetic, e.strain, double(e.min_jacobian), double(e.max_jacobian), max_T, heart_.mean_potential()});
    min_J_ = std::min<double>(min_J_, e.min_jacobian);
    max_J_ = std::max<double>(max_J_, e.max_jacobian);
    peak_tension_ = std::max(peak_tension_, max_T);
    peak_kinetic_ = std::max(peak_kinetic_, e.kinetic);
    peak_strain_ = std::max(peak_strain_, e.strain);
    peak_displacement_ = std::max(peak_displacement_, heart_.max_displacement());
    return row;
  }
  std::vector<double> observer_row() const {
    const auto V = heart_.body.field(heart_.monodomain.potential_field());
    const std::span<const Real> T(heart_.tension.tension());
    const auto x = material_point_positions<3>(probes_, heart_.solid);
    std::vector<double> row;
    for (std::size_t p = 0; p < probes_.size(); ++p)
      row.insert(row.end(), {probes_.sample(p, V), probes_.sample(p, T), double((x[p] - probes_.point(p)).norm())});
    return row;
  }
  void end_of_beat() {
    end_of_beat_["energy"].push_back(heart_.solid.energies().total());  // also leaves F at the current positions
    end_of_beat_["lv_volume_mm3"].push_back(heart_.cavities.empty() ? 0.0 : heart_.cavity_volume(0));
    end_of_beat_["max_displacement_mm"].push_back(heart_.max_displacement());
    end_of_beat_["max_active_tension_kPa"].push_back(heart_.max_tension());
    end_of_beat_["mean_potential_mV"].push_back(heart_.mean_potential());
  }

  HeartModel& heart_;
  std::vector<std::string> observer_names_;
  std::vector<double> volume_min_, volume_max_, peak_pressure_;
  double min_J_ = 1, max_J_ = 1, peak_tension_ = 0, peak_kinetic_ = 0, peak_strain_ = 0, peak_displacement_ = 0;
  nlohmann::json end_of_beat_ = {{"energy", nlohmann::json::array()},
                                 {"lv_volume_mm3", nlohmann::json::array()},
                                 {"max_displacement_mm", nlohmann::json::array()},
                                 {"max_active_tension_kPa", nlohmann::json::array()},
                                 {"mean_potential_mV", nlohmann::json::array()}};
  const sph::PointProbes<3> probes_;  // in the reference configuration: material points
};

/// The 0D circulation coupled to the cavities (cavity_pressure = circulation), and the measures of
/// each beat. Preload: over [0, preload_time] the cavity pressures ramp to lv_pressure and
/// rv_pressure over pressure_ramp_time and then hold; at preload_time the circulation starts
/// (its time 0 is the first stimulus) with the coupled ventricles' blood volumes equal to the
/// cavity volumes at those pressures. After every coupling step the circulation advances with the
/// new cavity volumes (cardio/circulation.hpp: V_3D linear over the step) and its ventricular
/// pressures load the endocardia over the next step. At each beat's end the PV measures of both
/// ventricles are taken (cardio/beat_metrics.hpp), and the run ends early once both stroke volumes
/// changed by less than beat_tolerance from the beat before.
class HeartCirculation {
 public:
  HeartCirculation(HeartModel& heart, sph::TimeStepper& stepper, sph::RunHarness& run, const HeartParameters& p, bool quiet)
      : heart_(heart), p_(p), origin_(beat_origin(p)), quiet_(quiet), circulation_(settings(heart, p)) {
    for (std::size_t c = 0; c < heart_.cavities.size(); ++c)
      (heart_.cavities[c].label == cardio::label_lv_endo ? lv_ : rv_) = c;
    if (origin_ == 0) {
      start();
    } else {  // a step ends where the circulation starts; until then it follows the unloaded cavities
      stepper.add_event("end of preload", {stepper.end_time(), true, true, false, Real(origin_)}, [](const sph::StepInfo&) {});
      const auto v = volumes();
      circulation_.initialise(0, v[0], v[1], 0, 0);
    }
    stepper.add_step_callback([this, &stepper](const sph::StepInfo& s) { after_step(s, stepper); });
    run.add_state("circulation", [this](sph::StateArchive& a) { checkpoint(a); });
    auto columns = circulation_.columns();
    columns.erase(columns.begin());  // its own time: the run's time is the first column
    run.add_time_series("circulation.csv", columns, Real(p.sample_interval / 4), [this](const sph::StepInfo&) {
      auto row = circulation_.row();
      row.erase(row.begin());
      return row;
    });
  }

  void report(sph::RunReport& r) const {
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
    r.results["total_blood_volume_mm3"] = {initial_blood_, circulation_.total_blood_volume()};
    r.results["unsettled_valve_steps"] = circulation_.unsettled_valve_steps();
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

  /// pv_loop.png: pressure against volume of both ventricles over every beat (from circulation.csv).
  void plot(const std::filesystem::path& folder) const {
    const auto columns = circulation_.columns();
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

  const cardio::Circulation& circulation() const { return circulation_; }

 private:
 public:
  /// Throws ParameterError unless the mesh has both endocardia (checked before anything is written).
  static void require_cavities(const HeartModel& heart) {
    bool lv = false, rv = false;
    for (const auto& c : heart.cavities) lv = lv || c.label == cardio::label_lv_endo, rv = rv || c.label == cardio::label_rv_endo;
    if (!lv || !rv)
      throw sph::ParameterError(std::string("cavity_pressure = circulation needs the LV and the RV endocardium of the mesh; no ") +
                                (lv ? "RV" : "LV") + " endocardium is labelled, so its volume cannot be computed "
                                "(use cavity_pressure = none, constant or ramp)");
  }

 private:
  static cardio::CirculationSettings settings(const HeartModel& heart, const HeartParameters& p) {
    require_cavities(heart);
    cardio::CirculationSettings s = p.circulation;
    s.lv_mode = s.rv_mode = cardio::VentricleMode::coupled;
    s.heart_period = p.cycle_length;
    return s;
  }
  static nlohmann::json measures_json(const cardio::BeatMeasures& m) {
    return {{"edv_mm3", m.edv}, {"esv_mm3", m.esv}, {"stroke_volume_mm3", m.stroke_volume}, {"ejection_fraction", m.ejection_fraction},
            {"edp_kPa", m.edp}, {"peak_pressure_kPa", m.peak_pressure}, {"dpdt_max_kPa_per_ms", m.dpdt_max},
            {"dpdt_min_kPa_per_ms", m.dpdt_min}};
  }
  static double relative_change(const cardio::BeatMeasures& a, const cardio::BeatMeasures& b) {
    return std::abs(b.stroke_volume - a.stroke_volume) / std::max(std::abs(b.stroke_volume), 1e-12);
  }
  std::array<double, 2> volumes() const { return {heart_.cavity_volume(lv_), heart_.cavity_volume(rv_)}; }
  void checkpoint(sph::StateArchive& a) {
    auto model = a.part("model");
    circulation_.checkpoint(model);
    a.io("started", started_);
    a.io("initial_blood", initial_blood_);
    for (int k = 0; k < 2; ++k) {
      auto recorder = a.part("recorder" + std::to_string(k));
      recorders_[k].checkpoint(recorder);
    }
    a.io("beats", beats_);
    a.io("converged_at", converged_at_);
    a.io("was_closed", was_closed_);
    a.io("closed_volume", closed_volume_);
    a.io("isovolumic_change", isovolumic_change_);
    if (a.loading() && started_) couple_pressures();
  }
  void start() {
    const auto v = volumes();
    circulation_.initialise(0, v[0], v[1], heart_.pressures[lv_].at(origin_), heart_.pressures[rv_].at(origin_));
    initial_blood_ = circulation_.total_blood_volume();
    started_ = true;
    set_pressures();
    couple_pressures();
  }
  // The cavity loads take their pressures from the circulation at the current volumes.
  void couple_pressures() {
    heart_.pressure_of_volume = [this](std::size_t c, double V) {
      return circulation_.pressure_at_volume(c == lv_ ? cardio::Ventricle::left : cardio::Ventricle::right, V);
    };
  }
  void set_pressures() {
    heart_.pressures[lv_].set(circulation_.pressure(cardio::Ventricle::left));
    heart_.pressures[rv_].set(circulation_.pressure(cardio::Ventricle::right));
  }
  void after_step(const sph::StepInfo& s, sph::TimeStepper& stepper) {
    const double t = s.time, tolerance = 1e-9 * p_.cycle_length;
    if (!started_) {
      // Preload: the ramp to the end-diastolic pressures, then rest (CavityPressure in ramp form).
      const double rise = p_.cavity_pressure.ramp_time > 0 ? std::min(1.0, t / p_.cavity_pressure.ramp_time) : 1.0;
      for (std::size_t c = 0; c < heart_.cavities.size(); ++c)
        heart_.pressures[c].set(rise * (heart_.cavities[c].label == cardio::label_lv_endo ? p_.cavity_pressure.lv_pressure
                                                                                          : p_.cavity_pressure.rv_pressure));
      if (t >= origin_ - tolerance) {
        start();
      } else {  // the circulation follows the cavities at the preload pressures (circulation.csv)
        const auto v = volumes();
        circulation_.initialise(0, v[0], v[1], heart_.pressures[lv_].at(t), heart_.pressures[rv_].at(t));
      }
      return;
    }
    const auto v = volumes();
    circulation_.advance(t - s.time_step - origin_, s.time_step, v[0], v[1]);
    set_pressures();
    const double p_lv = circulation_.pressure(cardio::Ventricle::left), p_rv = circulation_.pressure(cardio::Ventricle::right);
    recorders_[0].add(t, v[0], p_lv);
    recorders_[1].add(t, v[1], p_rv);
    // Isovolumic phases: the largest change of a cavity's volume while both of its valves are closed.
    using V = cardio::Valve;
    const bool closed[2] = {!circulation_.valve_open(V::mitral) && !circulation_.valve_open(V::aortic),
                            !circulation_.valve_open(V::tricuspid) && !circulation_.valve_open(V::pulmonary)};
    for (int k = 0; k < 2; ++k) {
      if (closed[k] && was_closed_[k]) isovolumic_change_[k] = std::max(isovolumic_change_[k], std::abs(v[k] - closed_volume_[k]));
      if (closed[k] && !was_closed_[k]) closed_volume_[k] = v[k];
      was_closed_[k] = closed[k];
    }
    const double beat_end = origin_ + double(beats_.size() + 1) * p_.cycle_length;
    if (t >= beat_end - tolerance) {
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
  }

  HeartModel& heart_;
  const HeartParameters& p_;
  const double origin_;
  const bool quiet_;
  cardio::Circulation circulation_;
  std::size_t lv_ = 0, rv_ = 1;
  bool started_ = false;
  double initial_blood_ = 0;
  cardio::BeatRecorder recorders_[2];
  std::vector<std::array<cardio::BeatMeasures, 2>> beats_;
  long converged_at_ = -1;
  bool was_closed_[2] = {false, false};
  double closed_volume_[2] = {0, 0}, isovolumic_change_[2] = {0, 0};
};

class HeartScene final : public Scene {
 public:
  HeartScene() {
    p_.geometry.settings.mesh = shipped_mesh("biventricular.stl");
    p_.geometry.settings.spacing = 0;
    p_.geometry.dp_from_preset = true;
    p_.geometry.settings.relaxation_steps = 60;
    p_.numerics.discretisation.output_interval = 20;
    // The beat's solid numerics (docs/electromechanics.md, "A physiological beat"): inertia scaled by
    // 4 (the beat is slow against the wall's acoustic time), the conservative hourglass control and
    // the pair viscosity, which damp the particle-scale modes that physiological tension excites,
    // and a step of 0.45 of the acoustic limit (at 0.6 the transversely isotropic wall inverted).
    p_.numerics.solid.mass_scaling = 4;
    p_.numerics.solid.hourglass_control = sph::HourglassControl::energy;
    p_.numerics.solid.artificial_viscosity = Real(0.25);
    p_.numerics.solid.cfl = Real(0.45);
    // The closed loop of Regazzoni et al. 2022 for this heart, whose cavities hold about half the
    // blood of an adult's (unloaded LV 54 mL): twice their systemic arterial resistance, so that half
    // their cardiac output meets the same arterial pressure, and half their systemic arterial
    // compliance (the impedance doubled with RC kept: an adult's pulse pressure from this smaller
    // stroke volume); a starting state near the beat's own (venous pressures at the preload
    // instead of their 30 and 24 mmHg).
    p_.circulation.systemic_arterial.resistance *= 2;
    p_.circulation.systemic_arterial.compliance /= 2;
    p_.circulation.initial_systemic_venous_pressure = 1.6;
    p_.circulation.initial_pulmonary_venous_pressure = 1.4;
  }

  void declare(sph::Parameters& p) override {
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
  }

  void check() const override {
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
    if (p_.early_sites == "list") (void)parse_early_sites(p_.early_site_list);
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
  }

  void run(RunContext& ctx) override;
  bool checkpoints() const override { return true; }

 private:
  /// The SPHinXsys heart case (test_3d_heart_electromechanics, ../shared/PARITY.md) in this scene's
  /// parameters: its mesh (without the translation, so the boxes are in mesh coordinates: theirs
  /// plus (53.5, 70, 32.5) mm), dp 2 mm with h = 1.15 dp, Aliev-Panfilov in its own units with
  /// isotropic D = 0.8 and a splitting step of 0.5 h^2 / (3 D) = 1.102, their tension law
  /// (100 k_a V with k_a = 1e-4 MPa = 10 kPa per unit of V, eps 0.1 to 1 switching at V = 0.8
  /// with xi = 100), K = 495.8 kPa, the base clamped 4 mm deep, the stimulus box raised to V = 0.92
  /// (here by a pulse of 0.92 per unit time for one time unit), its solid scheme (no hourglass
  /// control, its pair viscosity 0.25, the acoustic step of the small-strain modulus), and end time 100.
  static std::vector<std::pair<std::string, std::string>> sphinxsys_preset() {
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

  HeartParameters p_;
};

/// activation_map.csv (reference x, y, z, first activation time after the first stimulus at
/// `origin`, -1 where not activated, and with the maps the latest APD) and activation_map.png, the
/// particles coloured by their activation time.
void write_activation_map(const std::filesystem::path& folder, const HeartModel& heart, double origin) {
  const auto activation = heart.body.field(heart.monodomain.activation_field());
  const auto* maps = heart.monodomain.maps();
  std::ostringstream csv;
  csv << "x,y,z,activation_time" << (maps ? "," + maps->apd_name() : "") << '\n';
  for (std::size_t i = 0; i < heart.n(); ++i) {
    csv << heart.X[i][0] << ',' << heart.X[i][1] << ',' << heart.X[i][2] << ','
        << (activation[i] >= 0 ? double(activation[i]) - origin : -1.0);
    if (maps) csv << ',' << heart.body.field(maps->apd_field())[i];
    csv << '\n';
  }
  sph::write_file_atomically(folder / "activation_map.csv", csv.str());
  if (std::none_of(activation.begin(), activation.end(), [](Real a) { return a >= 0; })) return;  // nothing to draw
  plot_scatter(folder, {"activation_map.csv", "activation_map.png", "first activation (mesh coordinates)",
                        "activation time after the first stimulus [ms]", 4, 60, 30});
}

/// The electrodes of the pseudo-ECG: the 12-lead set placed by the heart's frame (its centre, the
/// base-to-apex direction -base_normal and the LV-to-RV endocardial centroids), or the given ones.
std::vector<cardio::Electrode> heart_electrodes(const HeartModel& heart, const cardio::HeartGeometry& g, const EcgParameters& p) {
  if (p.mode != "twelve_lead") return parse_electrodes(p.electrodes);
  Vec3 centre = Vec3::Zero(), lv = Vec3::Zero(), rv = Vec3::Zero();
  std::size_t n_lv = 0, n_rv = 0;
  for (std::size_t i = 0; i < heart.n(); ++i) {
    centre += heart.X[i];
    if (heart.labels[i] == cardio::label_lv_endo) lv += heart.X[i], ++n_lv;
    if (heart.labels[i] == cardio::label_rv_endo) rv += heart.X[i], ++n_rv;
  }
  if (n_lv == 0 || n_rv == 0)
    throw sph::ParameterError("parameter 'ecg' = twelve_lead places the electrodes by the LV and RV endocardia, and this "
                              "heart has no particle labelled " + std::string(n_lv == 0 ? "LV" : "RV") +
                              " endocardium (use ecg = electrodes)");
  centre /= Real(heart.n());
  return cardio::twelve_lead_electrodes(centre, -g.base_normal.cast<Real>(), rv / Real(n_rv) - lv / Real(n_lv),
                                        p.chest_radius, p.limb_distance);
}

// The scene as a short program: geometry, systems, coupling, run, report.
void HeartScene::run(RunContext& ctx) {
  const auto wall_start = std::chrono::steady_clock::now();
  auto log = [&](const std::string& line) {
    if (!ctx.quiet) std::cout << line << '\n' << std::flush;
  };

  // 1. Geometry: the cached stage (particles, surface labels, LDRB fibres).
  const auto gs = p_.geometry.resolved(preset_spacing(p_.preset));
  if (gs.fibres == "none") throw sph::ParameterError("parameter 'fibres' = none: the heart needs fibre directions");
  const auto g = cardio::prepare_heart_geometry(gs, p_.geometry.cache_folder(), log);

  // 2. Systems: solid, monodomain, active tension and cavities on one particle set.
  HeartModel heart(p_, g, gs);

  if (p_.cavity_pressure.mode == cardio::CavityPressureMode::circulation) HeartCirculation::require_cavities(heart);

  // 3. Coupling: the electromechanical stage and its conduction update (cardio/electromechanics.hpp).
  const double end_time = p_.end_time > 0 ? p_.end_time : beat_origin(p_) + double(p_.beats) * p_.cycle_length;
  sph::TimeStepper stepper(0, Real(end_time));
  sph::RunHarness run(stepper, ctx.report, {ctx.output_dir, "heart", ctx.quiet, ctx.checkpoint});
  cardio::add_electromechanics<3>(stepper, heart.monodomain, heart.tension, heart.solid, p_.coupling, run.timers());
  if (!heart.wall_loads.empty()) {
    const auto external = heart.solid.external_force_field();
    stepper.fill(heart.solid.loads_slot(), "wall loads", [&heart, external](Real t, Real dt) {
      for (const auto& load : heart.wall_loads) load(t + dt / 2, heart.body.field(external));
    });
  }

  // 4. Outputs and run.
  run.add_body(heart.body, Real(p_.numerics.discretisation.output_interval), [&](double) {
    heart.solid.update_output_fields();
    heart.monodomain.update_conduction_velocity();
  });
  run.add_relation("heart", heart.relation);
  // What changes besides the particle fields (checkpoints; the relation is in the reference configuration).
  run.add_state("heart", [&](sph::StateArchive& a) {
    auto solid = a.part("solid"), monodomain = a.part("monodomain"), tension = a.part("tension");
    heart.solid.checkpoint(solid);
    heart.monodomain.checkpoint(monodomain);
    heart.tension.checkpoint(tension);
    for (std::size_t c = 0; c < heart.pressures.size(); ++c) {
      auto pressure = a.part("pressure" + std::to_string(c));
      heart.pressures[c].checkpoint(pressure);
    }
  });
  HeartRecorder recorder(heart, run, stepper, p_);
  std::optional<EcgRecorder> ecg;
  if (p_.ecg.mode != "none") {
    EcgRecorder::Source source{[&] { return std::span<const Real>(heart.body.field(heart.monodomain.potential_field())); },
                               [&] { return std::span<const sph::Mat<3>>(heart.monodomain.diffusion_tensor()); },
                               [&] { return std::span<const Vec3>(heart.body.position); },
                               [&] { return std::span<const sph::Mat<3>>(heart.body.field(heart.solid.deformation_gradient_field())); }};
    ecg.emplace(p_.ecg, heart_electrodes(heart, g, p_.ecg), p_.ecg.mode == "twelve_lead", heart.relation, heart.X,
                heart.body.volume, heart.dp, source, run);
  }
  std::optional<HeartCirculation> circulation;
  if (p_.cavity_pressure.mode == cardio::CavityPressureMode::circulation) circulation.emplace(heart, stepper, run, p_, ctx.quiet);
  auto& r = ctx.report;
  r.results["initial_mechanics_time_step_ms"] = heart.solid.stable_time_step();
  r.results["diffusion_time_step_limit_ms"] = heart.monodomain.diffusion_time_step();
  run.run();

  // 5. Report.
  recorder.report(r);
  // The first beat's QRS (within 150 ms of its stimulus: ventricular activation takes 60-80 ms), T
  // wave and QT interval.
  if (ecg) ecg->finish(ctx.output_dir, r, EcgRecorder::Beat{beat_origin(p_), p_.cycle_length, 150});
  if (heart.monodomain.maps()) r.results["maps"] = ep_map_summary(heart.monodomain);
  write_activation_map(ctx.output_dir, heart, beat_origin(p_));
  if (circulation) {
    circulation->report(r);
    circulation->plot(ctx.output_dir);
  }
  for (const auto& c : calibrated_parameters())
    r.results["calibration"].push_back({{"parameter", c.key},
                                        {"value", c.value(p_)},
                                        {"calibrated", c.calibrated},
                                        {"target", c.target},
                                        {"tuned_on", c.tuned_on}});
  r.results["particle_spacing_mm"] = heart.dp;
  r.results["geometry_from_cache"] = g.from_cache;
  r.results["label_method"] = g.label_method;
  r.results["fibre_method"] = g.fibre_method;
  if (g.tets) r.results["tetrahedra"] = g.tets;
  r.results["fixed_base_particles"] = heart.base.size();
  r.results["stimulated_particles"] = heart.stimulated;
  for (const auto& site : heart.early)
    r.results["early_activation_sites"].push_back(
        {{"position_mm", {site.position[0], site.position[1], site.position[2]}}, {"time_ms", site.time}});
  // The cell groups, with the median APD of each (the gradient across the wall with layers).
  const auto* maps = heart.monodomain.maps();
  for (std::size_t k = 0; k < heart.cell_groups.names.size(); ++k) {
    auto& group = r.results["cell_groups"][heart.cell_groups.names[k]];
    group["particles"] = heart.cell_groups.counts[k];
    if (!maps) continue;
    std::vector<double> apd;
    const auto values = heart.body.field(maps->apd_field());
    for (std::size_t i = 0; i < heart.n(); ++i)
      if ((heart.cell_groups.group.empty() || heart.cell_groups.group[i] == k) && values[i] > 0) apd.push_back(values[i]);
    if (apd.empty()) continue;
    std::nth_element(apd.begin(), apd.begin() + std::ptrdiff_t(apd.size() / 2), apd.end());
    group[maps->apd_name() + "_median_ms"] = apd[apd.size() / 2];
  }
  r.results["stimulus_centre_mm"] = {heart.stimulus_centre[0], heart.stimulus_centre[1], heart.stimulus_centre[2]};
  r.results["diffusivity_mm2_per_ms"] = {heart.D_fibre, heart.D_cross};
  r.results["max_activation_ms"] = heart.monodomain.latest_activation();
  const auto activation = heart.body.field(heart.monodomain.activation_field());
  if (heart.monodomain.all_activated()) {
    // The first beat's activation spread: latest minus earliest activation time (healthy human
    // ventricles: 60-80 ms, Durrer et al. 1970).
    const auto [first, last] = std::minmax_element(activation.begin(), activation.end());
    r.results["total_activation_ms"] = double(*last - *first);
  }
  r.results["activated_fraction"] =
      double(std::count_if(activation.begin(), activation.end(), [](Real a) { return a >= 0; })) / double(heart.n());
  const auto& timers = run.timers();
  r.results["seconds"]["geometry"] = g.seconds;
  r.results["seconds"]["reaction"] = heart.monodomain.timings().reaction;
  r.results["seconds"]["diffusion"] = heart.monodomain.timings().diffusion;
  const std::size_t mechanics_substeps = timers.calls("mechanics");
  r.results["mechanics_substeps"] = mechanics_substeps;
  r.results["conduction_updates"] = timers.calls("conduction_update");
  r.results["diffusion_substeps"] = heart.monodomain.diffusion_substeps();
  r.results["ep_steps"] = heart.monodomain.steps();
  if (mechanics_substeps > 0)
    r.results["mechanics_microseconds_per_particle_step"] =
        1e6 * timers.seconds("mechanics") / (double(mechanics_substeps) * double(heart.n()));
  const double beats_run = std::max(1e-9, (double(stepper.end_time()) - beat_origin(p_)) / p_.cycle_length);
  r.results["seconds_per_beat"] = run.time_loop_seconds() / beats_run;
  r.results["total_seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
}

}  // namespace

std::unique_ptr<Scene> make_heart_scene() { return std::make_unique<HeartScene>(); }

}  // namespace cardiosph
