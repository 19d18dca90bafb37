// `cardiosph heart`: excitation-contraction of a ventricular mesh on one particle set.
//
// Geometry: the cached heart-geometry stage (particles, surface labels, LDRB fibres). Physics:
// monodomain with Aliev-Panfilov (physical units, Nash-Panfilov parameters) or ten Tusscher-
// Panfilov 2006 cells, conduction D_l along the fibre and D_t across, pulled back through F
// (cardio/electromechanics.hpp); Nash-Panfilov active tension (cardio/active_tension.hpp);
// Holzapfel-Ogden passive law with the constants of the SPHinXsys heart case (Zhang et al. 2021,
// CMAME 381:113847) plus the active stress T_a f0 (x) f0; base fixed. Cavity volumes from the
// labelled endocardia moved with the tissue (cardio/cavity.hpp), optional cavity pressure
// (constant, ramped, or a two-element Windkessel).
//
// Outputs: heart_*.vtu / heart.pvd (potential, activation time, T_a, displacement, J, fibre stretch,
// von Mises stress, labels, fibres), cavities.csv (volumes, pressures, energies, J range, peak T_a),
// observers.csv (potential, T_a and displacement at three particles), report.json.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <limits>
#include <optional>

#include "apps/scenes/electromechanics/em_scenes.hpp"
#include "apps/scenes/electromechanics/em_setup.hpp"
#include "apps/scenes/geometry/heart_geometry_parameters.hpp"
#include "apps/scenes/solid/solid_run.hpp"
#include "cardio/cavity.hpp"
#include "cardio/electromechanics.hpp"
#include "libsph/core/numerical_failure.hpp"
#include "libsph/core/parallel.hpp"
#include "libsph/io/particle_output.hpp"
#include "libsph/io/progress.hpp"
#include "libsph/io/time_series.hpp"

namespace cardiosph {
namespace {

using sph::Real;
using Vec3 = sph::Vec<3>;

struct HeartParameters {
  HeartGeometryParameters geometry;
  std::string preset = "default";
  // Electrophysiology.
  std::string cell_model = "aliev_panfilov";
  double diffusivity_fibre = 0, diffusivity_cross = 0;  ///< 0: the cell model's default
  double stimulus_strength = 50, stimulus_duration = 2, stimulus_radius = 5;
  std::string stimulus_site = "lv-apex";
  std::string stimulus_point = "0,0,0";
  long beats = 1;
  double cycle_length = 800;
  double end_time = 0;  ///< 0: beats x cycle length
  double ep_time_step = 0.1;
  std::string diffusion_correction = "moment";
  bool clip_negative_coefficients = true;
  bool deformed_conduction = true;
  double conduction_update_interval = 2;
  // Active tension.
  double k_a = 0.01;
  double tension_threshold = 1;  ///< V_th - V_r [mV]
  bool tension_allow_negative = false;
  // Mechanics.
  double density = 1.06;
  double bulk_modulus = 100;
  double damping_rate = 0.02;
  // Cavity pressure.
  std::string cavity_pressure = "none";
  double lv_pressure = 0, rv_pressure = 0, pressure_ramp_time = 50;
  // Systemic values of an adult (Westerhof, Lankhaar & Westerhof 2009, Med. Biol. Eng. Comput. 47:131):
  // R about 1 mmHg s/mL = 0.13 kPa ms/mm^3, C about 1.5 mL/mmHg = 11,000 mm^3/kPa (RC about 1.5 s).
  double windkessel_resistance = 0.13, windkessel_compliance = 11000;
  double sample_interval = 2;
  SolidNumerics numerics;
};

/// Spacing of each preset on the shipped biventricular heart (the research resolution is "fine").
double preset_spacing(const std::string& preset) {
  if (preset == "coarse") return 3.0;
  if (preset == "fine") return 1.0;
  return 2.0;
}

double peak_rss_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;
}

/// Pressure of one cavity: none, constant, ramped to a value, or a two-element Windkessel (whose
/// pressure also rises over the ramp time from zero)
///   C dp/dt = Q - p / R,  Q = max(-dV/dt, 0) (outflow from the cavity; a valve that closes
/// against backflow, so filling draws nothing from the compliance), integrated exactly over each
/// sample interval for the mean Q. The cavity sees p throughout (no separate filling pressure).
struct CavityPressure {
  std::string mode;
  double value = 0, ramp = 0, resistance = 0, compliance = 0;
  double pressure = 0, last_volume = std::nan(""), last_time = 0;

  double at(double t) const {
    const double rise = ramp > 0 ? std::min(1.0, t / ramp) : 1.0;  // a sudden load would shock the tissue
    if (mode == "none") return 0;
    if (mode == "ramp") return value * rise;
    return mode == "constant" ? value : pressure * rise;
  }
  void update(double t, double volume) {
    if (mode == "windkessel" && !std::isnan(last_volume) && t > last_time) {
      const double dt = t - last_time, flow = std::max(0.0, -(volume - last_volume) / dt);
      const double tau = resistance * compliance, equilibrium = flow * resistance;
      pressure = equilibrium + (pressure - equilibrium) * std::exp(-dt / tau);
    }
    last_volume = volume;
    last_time = t;
  }
};

class HeartScene final : public Scene {
 public:
  HeartScene() {
    p_.geometry.mesh = shipped_mesh("biventricular.stl").string();
    p_.geometry.dp = 0;
    p_.geometry.dp_from_preset = true;
    p_.geometry.relaxation_steps = 60;
    p_.numerics.output_interval = 20;
  }

  void declare(sph::Parameters& p) override {
    p_.geometry.declare(p);
    p.add_choice("preset", p_.preset, {"coarse", "default", "fine"},
                 "resolution preset when dp = 0: coarse 3 mm, default 2 mm, fine 1 mm (research resolution)");
    p.add_choice("cell_model", p_.cell_model, {"aliev_panfilov", "ten_tusscher_panfilov"},
                 "cell model (Aliev-Panfilov with the Nash-Panfilov parameters, or ten Tusscher-Panfilov 2006 epicardial)");
    p.add("diffusivity_fibre", p_.diffusivity_fibre, "mm^2/ms",
          "D along the fibre (0: 1.0 for Aliev-Panfilov, 0.13 for ten Tusscher-Panfilov)", sph::Range::non_negative());
    p.add("diffusivity_cross", p_.diffusivity_cross, "mm^2/ms", "D across the fibre (0: a quarter of the fibre value)",
          sph::Range::non_negative());
    p.add_choice("stimulus_site", p_.stimulus_site, {"lv-apex", "point"},
                 "stimulus centre: the LV endocardial particle farthest from the base, or stimulus_point");
    p.add_text("stimulus_point", p_.stimulus_point, "stimulus centre x,y,z [mm] for stimulus_site = point");
    p.add("stimulus_radius", p_.stimulus_radius, "mm", "particles within this distance of the centre are stimulated",
          sph::Range::positive());
    p.add("stimulus_strength", p_.stimulus_strength, "mV/ms", "applied dV/dt of each pulse", sph::Range::positive());
    p.add("stimulus_duration", p_.stimulus_duration, "ms", "length of each pulse", sph::Range::positive());
    p.add("beats", p_.beats, "1", "number of paced beats", sph::Range::closed(1, 1000));
    p.add("cycle_length", p_.cycle_length, "ms", "pacing period", sph::Range::positive());
    p.add("end_time", p_.end_time, "ms", "simulated time (0: beats x cycle_length)", sph::Range::non_negative());
    p.add("ep_time_step", p_.ep_time_step, "ms",
          "splitting step of the monodomain, the coupling step of the fields", sph::Range::positive());
    p.add_choice("diffusion_correction", p_.diffusion_correction, {"none", "gradient", "moment"},
                 "correction of the anisotropic diffusion operator (libsph/diffusion/diffusion_operator.hpp)");
    p.add("clip_negative_coefficients", p_.clip_negative_coefficients,
          "clip negative pair coefficients of the anisotropic diffusion (monotone and stable; widens cross-fibre conduction)");
    p.add("deformed_conduction", p_.deformed_conduction,
          "conduction follows the deformed fibres (D pulled back through F); false: D of the reference configuration");
    p.add("conduction_update_interval", p_.conduction_update_interval, "ms", "time between updates of the pulled-back D",
          sph::Range::positive());
    p.add("k_a", p_.k_a, "kPa/mV", "active tension per mV above rest (Nash-Panfilov k_a; 0.001 = the 100 Pa per unit of u of the SPHinXsys heart)",
          sph::Range::non_negative());
    p.add("tension_threshold", p_.tension_threshold, "mV", "V_th - V_r of the activation function eps(V)", sph::Range::any());
    p.add("tension_allow_negative", p_.tension_allow_negative, "let the active tension fall below zero");
    p.add("density", p_.density, "mg/mm^3", "tissue density", sph::Range::positive());
    p.add("bulk_modulus", p_.bulk_modulus, "kPa", "K of the volumetric penalty (near incompressibility)", sph::Range::positive());
    p.add("damping_rate", p_.damping_rate, "1/ms", "velocity damping c of dv/dt = ... - c v (surrounding tissue and blood)",
          sph::Range::non_negative());
    p.add_choice("cavity_pressure", p_.cavity_pressure, {"none", "constant", "ramp", "windkessel"},
                 "endocardial pressure load: none, constant, ramped over pressure_ramp_time, or a two-element Windkessel (ramped in as well)");
    p.add("lv_pressure", p_.lv_pressure, "kPa", "LV cavity pressure (constant, ramp target, or Windkessel start)", sph::Range::any());
    p.add("rv_pressure", p_.rv_pressure, "kPa", "RV cavity pressure", sph::Range::any());
    p.add("pressure_ramp_time", p_.pressure_ramp_time, "ms", "duration of the pressure ramp", sph::Range::non_negative());
    p.add("windkessel_resistance", p_.windkessel_resistance, "kPa ms/mm^3", "R of the Windkessel", sph::Range::positive());
    p.add("windkessel_compliance", p_.windkessel_compliance, "mm^3/kPa", "C of the Windkessel", sph::Range::positive());
    p.add("sample_interval", p_.sample_interval, "ms", "time between rows of cavities.csv and observers.csv",
          sph::Range::positive());
    declare_solid_numerics(p, p_.numerics, "ms");
  }

  void check() const override {
    (void)geometry_settings();
    if (p_.stimulus_site == "point") (void)parse_vector("stimulus_point", p_.stimulus_point, true);
    if (p_.stimulus_duration >= p_.cycle_length)
      throw sph::ParameterError("parameter 'stimulus_duration' must be shorter than 'cycle_length'");
  }

  void run(RunContext& ctx) override;

 private:
  cardio::HeartGeometrySettings geometry_settings() const {
    HeartGeometryParameters g = p_.geometry;
    if (g.dp == 0) g.dp = preset_spacing(p_.preset);
    return g.settings();
  }

  HeartParameters p_;
};

void HeartScene::run(RunContext& ctx) {
  const auto wall_start = std::chrono::steady_clock::now();
  auto log = [&](const std::string& line) {
    if (!ctx.quiet) std::cout << line << '\n' << std::flush;
  };
  const auto gs = geometry_settings();
  if (gs.fibres == "none") throw sph::ParameterError("parameter 'fibres' = none: the heart needs fibre directions");
  const auto g = cardio::prepare_heart_geometry(gs, p_.geometry.cache_folder(), log);
  const double geometry_seconds = g.seconds;
  const Real dp = Real(gs.spacing);
  const Real h = Real(p_.numerics.smoothing_length_ratio) * dp;
  auto body = make_particle_set(g, "heart");
  const std::size_t n = body.n_particles();
  auto label = body.field(body.register_field<int>("label"));
  for (std::size_t i = 0; i < n; ++i) label[i] = g.labels[i];
  const auto kernel = sph::make_kernel<3>(p_.numerics.kernel);
  const auto relation = sph::build_inner_relation<3>(body.position, kernel, h);

  // Mechanics: Holzapfel-Ogden (SPHinXsys heart constants, kPa) with active stress.
  sph::HolzapfelOgden<3> law;
  law.a = Real(0.496), law.b = Real(7.209), law.a_f = Real(15.196), law.b_f = Real(20.417);
  law.a_s = Real(3.283), law.b_s = Real(11.176), law.a_fs = Real(0.662), law.b_fs = Real(9.466);
  law.bulk_modulus = Real(p_.bulk_modulus);
  sph::ElasticSolid<3>::Settings solid_settings;
  solid_settings.material = law;
  solid_settings.density = Real(p_.density);
  solid_settings.damping_rate = Real(p_.damping_rate);
  solid_settings.active_stress = true;
  apply_solid_numerics<3>(p_.numerics, solid_settings);
  sph::ElasticSolid<3> solid(body, relation, solid_settings);
  const auto base = attach_heart_geometry(solid, g, "heart");

  // Electrophysiology.
  const bool ttp = p_.cell_model == "ten_tusscher_panfilov";
  const double D_fibre = p_.diffusivity_fibre > 0 ? p_.diffusivity_fibre : (ttp ? 0.13 : 1.0);
  const double D_cross = p_.diffusivity_cross > 0 ? p_.diffusivity_cross : D_fibre / 4;
  cardio::Monodomain<3>::Settings ep;
  if (ttp) ep.cell_model = sph::TenTusscherPanfilov2006{};
  else ep.cell_model = sph::AlievPanfilov::nash_panfilov_2004();
  ep.time_step = Real(p_.ep_time_step);
  ep.correction = p_.diffusion_correction == "none"       ? sph::DiffusionCorrection::none
                  : p_.diffusion_correction == "gradient" ? sph::DiffusionCorrection::gradient
                                                          : sph::DiffusionCorrection::moment;
  ep.clip_negative_coefficients = p_.clip_negative_coefficients;
  ep.diffusion_tensor.resize(n);
  {
    const auto f = body.field(solid.fiber_field());
    for (std::size_t i = 0; i < n; ++i)
      ep.diffusion_tensor[i] = sph::transversely_isotropic_tensor<3>(Real(D_fibre), Real(D_cross), f[i]);
  }
  // Stimulus: every particle within the radius of the centre.
  Vec3 centre;
  if (p_.stimulus_site == "point") {
    centre = parse_vector("stimulus_point", p_.stimulus_point, true).cast<Real>();
  } else {
    const Vec3 normal = g.base_normal.cast<Real>();
    Real farthest = -std::numeric_limits<Real>::infinity();
    for (std::size_t i = 0; i < n; ++i)
      if (g.labels[i] == cardio::label_lv_endo && -normal.dot(body.position[i]) > farthest) {
        farthest = -normal.dot(body.position[i]);
        centre = body.position[i];
      }
    if (!std::isfinite(farthest)) throw std::invalid_argument("heart: no LV endocardium labelled, so no lv-apex stimulus site");
  }
  cardio::Monodomain<3>::StimulusRegion stimulus;
  stimulus.name = p_.stimulus_site;
  for (std::size_t i = 0; i < n; ++i)
    if ((body.position[i] - centre).norm() <= p_.stimulus_radius) stimulus.particles.push_back(i);
  if (stimulus.particles.empty())
    throw sph::ParameterError("no particle lies within 'stimulus_radius' of the stimulus centre " +
                              sph::NumericalFailure::format_position(centre));
  stimulus.protocol.start = 0;
  stimulus.protocol.duration = p_.stimulus_duration;
  stimulus.protocol.strength = p_.stimulus_strength;
  stimulus.protocol.period = p_.cycle_length;
  stimulus.protocol.count = int(p_.beats);
  ep.stimuli.push_back(stimulus);
  ep.activation_threshold = ttp ? Real(-40) : Real(-30);
  ep.longitudinal_diffusivity = Real(D_fibre);
  ep.transverse_diffusivity = Real(D_cross);
  cardio::Monodomain<3> monodomain(body, relation, ep);
  const Real rest = body.field(monodomain.potential_field())[0];

  cardio::ActiveTensionSettings ts;
  ts.k_a = p_.k_a;
  ts.rest_potential = rest;
  ts.threshold = rest + p_.tension_threshold;
  ts.allow_negative = p_.tension_allow_negative;
  cardio::ActiveTension<3> tension(body, monodomain.potential_field(), ts);

  cardio::ElectromechanicsSettings em;
  em.deformed_conduction = p_.deformed_conduction;
  em.conduction_update_interval = Real(p_.conduction_update_interval);

  // Cavities and their pressure loads.
  const auto mesh = read_geometry_mesh(gs);
  std::vector<Real> volumes(body.volume.begin(), body.volume.end());
  const auto cavities = cardio::cavity_surfaces(mesh, cavity_face_labels(mesh, g), body.position, volumes, g.labels, dp, kernel, h);
  std::vector<CavityPressure> pressures(cavities.size());
  for (std::size_t c = 0; c < cavities.size(); ++c) {
    auto& cp = pressures[c];
    cp.mode = p_.cavity_pressure;
    cp.value = cavities[c].label == cardio::label_lv_endo ? p_.lv_pressure : p_.rv_pressure;
    cp.pressure = cp.value;
    cp.ramp = p_.pressure_ramp_time;
    cp.resistance = p_.windkessel_resistance;
    cp.compliance = p_.windkessel_compliance;
  }
  const auto X = body.field(solid.reference_position_field());
  for (std::size_t c = 0; c < cavities.size(); ++c)
    if (p_.cavity_pressure != "none")
      solid.add_force_load([&, c](Real t, std::span<Vec3> force) {
        cavities[c].add_pressure_forces(Real(pressures[c].at(double(t))), body.position,
                                        body.field(solid.deformation_gradient_field()), X, force);
      });
  auto cavity_volume = [&](std::size_t c) {
    return cavities[c].volume(body.position, body.field(solid.deformation_gradient_field()), X);
  };

  // Observers: the stimulus centre, and the LV and RV endocardial particles farthest from it.
  std::vector<std::pair<std::string, std::size_t>> observers;
  {
    auto nearest = [&](const Vec3& p) {
      std::size_t best = 0;
      for (std::size_t i = 1; i < n; ++i)
        if ((body.position[i] - p).squaredNorm() < (body.position[best] - p).squaredNorm()) best = i;
      return best;
    };
    observers.emplace_back("stimulus", nearest(centre));
    for (auto [name, l] : {std::pair{"lv_far", cardio::label_lv_endo}, std::pair{"rv_far", cardio::label_rv_endo}}) {
      std::optional<std::size_t> far;
      for (std::size_t i = 0; i < n; ++i)
        if (g.labels[i] == l && (!far || (body.position[i] - centre).norm() > (body.position[*far] - centre).norm())) far = i;
      if (far) observers.emplace_back(name, *far);
    }
  }

  const double end_time = p_.end_time > 0 ? p_.end_time : double(p_.beats) * p_.cycle_length;
  sph::TimeStepper stepper(0, Real(end_time));
  sph::SectionTimers timers;
  cardio::add_electromechanics<3>(stepper, monodomain, tension, solid, em, timers);

  sph::ParticleOutput<3> output(ctx.output_dir, "heart");
  double io_seconds = 0;
  auto write_state = [&](double t) {
    const auto start = std::chrono::steady_clock::now();
    solid.update_output_fields();
    output.write(body, t);
    io_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  const double output_interval = p_.numerics.output_interval > 0 ? p_.numerics.output_interval : end_time;
  stepper.add_periodic_callback(Real(output_interval), [&](const sph::StepInfo& s) { write_state(s.time); });

  std::vector<std::string> header{"time"};
  for (const auto& c : cavities) {
    const std::string name(c.label == cardio::label_lv_endo ? "lv" : "rv");
    header.push_back(name + "_volume");
    header.push_back(name + "_pressure");
  }
  for (const char* column : {"kinetic", "strain", "min_J", "max_J", "max_T_a", "mean_V"}) header.push_back(column);
  sph::TimeSeriesCsv cavity_csv(ctx.output_dir / "cavities.csv", header);
  std::vector<std::string> observer_header{"time"};
  for (const auto& [name, i] : observers)
    for (const char* q : {"_V", "_T_a", "_displacement"}) observer_header.push_back(name + q);
  sph::TimeSeriesCsv observer_csv(ctx.output_dir / "observers.csv", observer_header);

  // End-diastolic volume: the largest sampled; end-systolic: the smallest sampled after it.
  std::vector<double> volume_min(cavities.size(), std::numeric_limits<double>::infinity());
  std::vector<double> volume_max(cavities.size(), 0), peak_pressure(cavities.size(), 0);
  double min_J = 1, max_J = 1, peak_tension = 0, peak_kinetic = 0, peak_strain = 0, peak_displacement = 0;
  std::vector<double> end_of_beat_energy, end_of_beat_lv_volume, end_of_beat_max_displacement, end_of_beat_max_tension, end_of_beat_mean_V;
  auto sample = [&](const sph::StepInfo& s) {
    const auto start = std::chrono::steady_clock::now();
    const auto e = solid.energies();  // leaves F at the current positions
    std::vector<double> row{double(s.time)};
    for (std::size_t c = 0; c < cavities.size(); ++c) {
      const double v = cavity_volume(c);
      pressures[c].update(s.time, v);
      if (v > volume_max[c]) volume_max[c] = v, volume_min[c] = v;
      volume_min[c] = std::min(volume_min[c], v);
      row.push_back(v);
      row.push_back(pressures[c].at(s.time));
      peak_pressure[c] = std::max(peak_pressure[c], pressures[c].at(s.time));
    }
    const auto V = body.field(monodomain.potential_field());
    const auto T = tension.tension();
    const double max_T = *std::max_element(T.begin(), T.end());
    const double mean_V = sph::parallel_sum(n, 0.0, [&](std::size_t i) { return double(V[i]); }) / double(n);
    const double max_u = sph::parallel_max(n, Real(0), [&](std::size_t i) { return (body.position[i] - X[i]).norm(); });
    row.insert(row.end(), {e.kinetic, e.strain, double(e.min_jacobian), double(e.max_jacobian), max_T, mean_V});
    cavity_csv.record(row);
    min_J = std::min<double>(min_J, e.min_jacobian);
    max_J = std::max<double>(max_J, e.max_jacobian);
    peak_tension = std::max(peak_tension, max_T);
    peak_kinetic = std::max(peak_kinetic, e.kinetic);
    peak_strain = std::max(peak_strain, e.strain);
    peak_displacement = std::max<double>(peak_displacement, max_u);
    std::vector<double> obs{double(s.time)};
    for (const auto& [name, i] : observers)
      obs.insert(obs.end(), {double(V[i]), double(T[i]), double((body.position[i] - X[i]).norm())});
    observer_csv.record(obs);
    io_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  stepper.add_periodic_callback(Real(p_.sample_interval), sample, false);
  stepper.add_periodic_callback(Real(p_.cycle_length), [&](const sph::StepInfo& s) {
    if (s.time <= 0) return;
    const auto T = tension.tension();
    const auto V = body.field(monodomain.potential_field());
    end_of_beat_energy.push_back(solid.energies().total());  // also leaves F at the current positions
    end_of_beat_lv_volume.push_back(cavities.empty() ? 0.0 : cavity_volume(0));
    end_of_beat_max_displacement.push_back(
        sph::parallel_max(n, Real(0), [&](std::size_t i) { return (body.position[i] - X[i]).norm(); }));
    end_of_beat_max_tension.push_back(*std::max_element(T.begin(), T.end()));
    end_of_beat_mean_V.push_back(sph::parallel_sum(n, 0.0, [&](std::size_t i) { return double(V[i]); }) / double(n));
  });

  double last_good_time = 0;
  sph::Progress progress("heart", ctx.quiet);
  stepper.add_step_callback([&](const sph::StepInfo& s) {
    last_good_time = s.time;
    progress.update(s);
  });

  auto& r = ctx.report;
  r.simulated_time = end_time;
  r.particles["heart"] = n;
  r.memory_bytes["heart_fields"] = body.bytes_per_particle() * n;
  r.memory_bytes["heart_relation"] = relation.bytes();
  r.results["particle_spacing_mm"] = dp;
  r.results["geometry_from_cache"] = g.from_cache;
  r.results["geometry_seconds"] = geometry_seconds;
  r.results["fixed_base_particles"] = base.size();
  r.results["stimulated_particles"] = stimulus.particles.size();
  r.results["stimulus_centre_mm"] = {centre[0], centre[1], centre[2]};
  r.results["diffusivity_mm2_per_ms"] = {D_fibre, D_cross};
  r.results["initial_mechanics_time_step_ms"] = solid.stable_time_step();
  r.results["diffusion_time_step_limit_ms"] = monodomain.diffusion_time_step();
  const auto run_start = std::chrono::steady_clock::now();
  try {
    r.steps = stepper.run();
  } catch (const sph::NumericalFailure&) {
    progress.finish();
    write_state(last_good_time);
    r.simulated_time = last_good_time;
    throw;
  }
  progress.finish();
  const double run_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - run_start).count();

  for (std::size_t c = 0; c < cavities.size(); ++c) {
    const std::string name(cavities[c].label == cardio::label_lv_endo ? "lv" : "rv");
    r.results[name + "_reference_volume_mm3"] = cavities[c].reference_volume;
    r.results[name + "_end_diastolic_volume_mm3"] = volume_max[c];
    r.results[name + "_end_systolic_volume_mm3"] = volume_min[c];
    r.results[name + "_peak_pressure_kPa"] = peak_pressure[c];
    r.results[name + "_ejection_fraction"] = volume_max[c] > 0 ? (volume_max[c] - volume_min[c]) / volume_max[c] : 0.0;
  }
  r.results["max_activation_ms"] = monodomain.latest_activation();
  {
    const auto activation = body.field(monodomain.activation_field());
    const auto activated = std::count_if(activation.begin(), activation.end(), [](Real a) { return a >= 0; });
    r.results["activated_fraction"] = double(activated) / double(n);
  }
  r.results["min_jacobian"] = min_J;
  r.results["max_jacobian"] = max_J;
  r.results["peak_active_tension_kPa"] = peak_tension;
  r.results["peak_kinetic_energy"] = peak_kinetic;
  r.results["peak_displacement_mm"] = peak_displacement;
  r.results["peak_strain_energy"] = peak_strain;
  r.results["end_of_beat"] = {{"energy", end_of_beat_energy},
                              {"lv_volume_mm3", end_of_beat_lv_volume},
                              {"max_displacement_mm", end_of_beat_max_displacement},
                              {"max_active_tension_kPa", end_of_beat_max_tension},
                              {"mean_potential_mV", end_of_beat_mean_V}};
  r.results["seconds"] = {{"geometry", geometry_seconds},
                          {"reaction", monodomain.timings().reaction},
                          {"diffusion", monodomain.timings().diffusion},
                          {"active_tension", timers.seconds("active_tension")},
                          {"mechanics", timers.seconds("mechanics")},
                          {"conduction_update", timers.seconds("conduction_update")},
                          {"output_and_sampling", io_seconds},
                          {"time_loop", run_seconds}};
  const std::size_t mechanics_substeps = timers.calls("mechanics");
  r.results["mechanics_substeps"] = mechanics_substeps;
  r.results["conduction_updates"] = timers.calls("conduction_update");
  r.results["diffusion_substeps"] = monodomain.diffusion_substeps();
  if (mechanics_substeps > 0)
    r.results["mechanics_microseconds_per_particle_step"] =
        1e6 * timers.seconds("mechanics") / (double(mechanics_substeps) * double(n));
  r.results["seconds_per_beat"] = run_seconds / (end_time / p_.cycle_length);
  r.results["peak_rss_mb"] = peak_rss_mb();
  r.results["total_seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
}

}  // namespace

std::unique_ptr<Scene> make_heart_scene() { return std::make_unique<HeartScene>(); }

}  // namespace cardiosph
