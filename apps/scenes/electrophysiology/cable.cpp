// `cable`: a strand of ten Tusscher-Panfilov 2006 cells (epicardial by default; any cell type,
// conductance scaling, drug block or population member) (length x width x width mm,
// fibres along x, the monodomain conductivities of Niederer et al. 2011) paced at its x = 0 end by a
// protocol (apps/scenes/electrophysiology/pacing.hpp): a train, S1-S2, or the S1-S2 restitution
// protocol. Per-beat APD and diastolic interval at the middle, CV between the quarter points, the
// restitution curves (restitution.csv, restitution.png) and optionally a pseudo-ECG at electrodes.
// Reference: the single cell under the same protocol and scheme (results.single_cell), against
// which the APD of every S2 beat is compared (errors.restitution_apd_max_relative).
#include <cmath>

#include "apps/scenes/electrophysiology/cell_variation.hpp"
#include "apps/scenes/electrophysiology/ecg_output.hpp"
#include "apps/scenes/electrophysiology/ep_scenes.hpp"
#include "apps/scenes/electrophysiology/pacing.hpp"
#include "apps/scenes/solid/solid_run.hpp"
#include "geometry/lattice.hpp"
#include "libsph/reaction/cell_simulation.hpp"

namespace cardiosph {
namespace {

using sph::Real;
using Vec3 = sph::Vec<3>;

class CableScene final : public Scene {
 public:
  explicit CableScene(CableParameters p) : p_(std::move(p)) {}
  void declare(sph::Parameters& p) override {
    p.add("length", p_.length, "mm", "length of the strand along the fibres (x)", sph::Range::positive());
    p.add("width", p_.width, "mm", "side of its square cross-section", sph::Range::positive());
    p.add("resolution", p_.resolution, "-", "particles across the width: dx = width / resolution", sph::Range::closed(1, 1000));
    p.add("end_time", p_.end_time, "ms", "simulated time (0: one pacing period after the protocol's last pulse)",
          sph::Range::non_negative());
    declare_parameters(p, p_.tissue);
    p.add("stimulus_current", p_.stimulus_current, "uA/mm^3", "stimulus current density", sph::Range::positive());
    p.add("stimulus_duration", p_.stimulus_duration, "ms", "length of each pulse", sph::Range::positive());
    p.add("stimulus_length", p_.stimulus_length, "mm", "the particles with x below this are stimulated",
          sph::Range::positive());
    declare_parameters(p, p_.pacing);
    declare_parameters(p, p_.cells, false);
    declare_parameters(p, p_.ecg, {}, false);
    declare_ep_numerics(p, p_.numerics, "ms");
  }
  void check() const override {
    const double dx = p_.width / double(p_.resolution);
    check_whole_spacings(p_.length, dx, "resolution (length / dx)");
    if (p_.numerics.apd_percent <= 0) throw sph::ParameterError("parameter 'apd_percent' must be positive: the cable reports APDs");
    (void)pacing_plan(p_.pacing, p_.stimulus_duration, 1);
    if (p_.ecg.mode == "electrodes") (void)parse_electrodes(p_.ecg.electrodes);
    (void)cell_heterogeneity(p_.cells);
  }
  bool checkpoints() const override { return true; }
  void run(RunContext& ctx) override {
    const Real dx = Real(p_.width / double(p_.resolution));
    auto body = geometry::lattice_box<3>("cable", Vec3(0, 0, 0), Vec3(Real(p_.length), Real(p_.width), Real(p_.width)), dx);
    const auto kernel = sph::make_kernel<3>(p_.numerics.discretisation.kernel);
    const Real h = static_cast<Real>(p_.numerics.discretisation.smoothing_length_ratio) * dx;
    const auto relation = sph::build_inner_relation<3>(body.position, kernel, h);

    // Monodomain conductivity: harmonic mean sigma_i sigma_e / (sigma_i + sigma_e), then D = sigma / (chi C_m).
    const auto [D_l, D_t] = p_.tissue.diffusivities();
    const double strength = p_.tissue.stimulus_rate(p_.stimulus_current);  // mV/ms
    const PacingPlan pacing = pacing_plan(p_.pacing, p_.stimulus_duration, strength);

    // One cell type, with the scalings, drug block and population member applied.
    const auto cell = std::get<sph::TenTusscherPanfilov2006>(
        cardio::ten_tusscher_groups(cell_heterogeneity(p_.cells), body.n_particles(), {}, {}, {}).models.at(0));
    cardio::Monodomain<3>::Settings settings;
    settings.cell_model = cell;
    settings.diffusion_tensor = {sph::transversely_isotropic_tensor<3>(D_l, D_t, Vec3(1, 0, 0))};
    settings.activation_threshold = 0;
    settings.numerics = p_.numerics.monodomain;
    settings.repolarisation_percent = Real(p_.numerics.apd_percent);
    std::vector<std::size_t> stimulated;
    for (std::size_t i = 0; i < body.n_particles(); ++i)
      if (body.position[i][0] < p_.stimulus_length) stimulated.push_back(i);
    if (stimulated.empty())
      throw sph::ParameterError("parameter 'stimulus_length' = " + std::to_string(p_.stimulus_length) +
                                " mm selects no particle (the first lie at x = " + std::to_string(dx / 2) + " mm)");
    settings.stimuli = {{"x = 0 end", stimulated, pacing.stimulus}};
    cardio::Monodomain<3> monodomain(body, relation, settings);

    // Measuring points on the axis: the middle (APD), the quarter points (CV).
    const double c = p_.width / 2, L = p_.length;
    const std::vector<Vec3> points{Vec3(Real(L / 2), Real(c), Real(c)), Vec3(Real(L / 4), Real(c), Real(c)),
                                   Vec3(Real(3 * L / 4), Real(c), Real(c))};
    auto nearest = [&](const Vec3& x) {
      std::size_t best = 0;
      for (std::size_t i = 1; i < body.n_particles(); ++i)
        if ((body.position[i] - x).squaredNorm() < (body.position[best] - x).squaredNorm()) best = i;
      return best;
    };
    BeatRecorder<3> beats(monodomain, {{"middle", nearest(points[0])}, {"quarter", nearest(points[1])},
                                      {"three_quarters", nearest(points[2])}}, 1, 2);
    const sph::PointProbes<3> probes(points, body.position, body.volume, kernel, h);
    const double end_time = p_.end_time > 0 ? p_.end_time : pacing.end_time;
    EpRunPlan plan("cable", end_time, p_.numerics.discretisation.output_interval, 1, {"middle", "quarter", "three_quarters"});
    plan.every_step = [&](const sph::StepInfo&) { beats.record(); };
    std::optional<EcgRecorder> ecg;
    plan.before_run = [&](sph::RunHarness& run) {
      if (p_.ecg.mode == "none") return;
      EcgParameters e = p_.ecg;
      e.surface_to_volume = p_.tissue.surface_to_volume;
      e.capacitance = p_.tissue.capacitance;
      EcgRecorder::Source source{[&] { return std::span<const Real>(body.field(monodomain.potential_field())); },
                                 [&] { return std::span<const sph::Mat<3>>(monodomain.diffusion_tensor()); },
                                 [&] { return std::span<const Vec3>(body.position); },
                                 {}};
      ecg.emplace(e, parse_electrodes(e.electrodes), false, relation, body.position, body.volume, dx, source, run);
    };
    plan.keep("beats", beats);  // the ECG saves its own
    run_monodomain<3>(monodomain, body, relation, probes, plan, ctx);

    auto& r = ctx.report;
    beats.finish(ctx.output_dir, pacing, p_.pacing.period, r);
    if (ecg) ecg->finish(ctx.output_dir, r);
    r.results["particle_spacing"] = dx;
    r.results["diffusivity_longitudinal"] = D_l;
    r.results["stimulus_rate"] = strength;
    r.results["stimulated_particles"] = stimulated.size();

    // The single cell under the same pulses, scheme and step: its APD of every beat.
    std::vector<double> t, V;
    const double dt = double(p_.numerics.monodomain.time_step);
    sph::simulate_cell(cell, p_.numerics.monodomain.scheme, dt, pacing.stimulus, end_time,
                       [&](double s, const auto& y) {
                         t.push_back(s);
                         V.push_back(y[0]);
                       });
    const auto onsets = pacing.stimulus.onsets();
    nlohmann::json single_cell = nlohmann::json::array();
    double worst = 0;
    for (std::size_t k = 0; k < onsets.size(); ++k) {
      const double next = k + 1 < onsets.size() ? onsets[k + 1] : end_time;
      const double apd = sph::measure_action_potential(t, V, onsets[k], next, p_.numerics.apd_percent / 100).duration();
      single_cell.push_back({{"onset_ms", onsets[k]}, {"apd_ms", apd}});
      if (std::find(pacing.s2_onsets.begin(), pacing.s2_onsets.end(), onsets[k]) == pacing.s2_onsets.end()) continue;
      for (const auto& row : r.results["beats"]["restitution"])
        if (row.contains("apd_ms") && apd > 0 && std::abs(row["coupling_ms"].get<double>() - (onsets[k] - onsets[k - 1])) < 1e-9)
          worst = std::max(worst, std::abs(row["apd_ms"].get<double>() - apd) / apd);
    }
    r.results["single_cell"] = single_cell;
    if (!pacing.s2_onsets.empty()) r.errors["restitution_apd_max_relative"] = worst;
    r.reference = "the single cell under the same protocol, scheme and step (results.single_cell)";
  }

 private:
  CableParameters p_;
};

}  // namespace

std::unique_ptr<Scene> make_cable_scene(CableParameters p) { return std::make_unique<CableScene>(std::move(p)); }

}  // namespace cardiosph
