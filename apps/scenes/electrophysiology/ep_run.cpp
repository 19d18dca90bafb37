#include "apps/scenes/electrophysiology/ep_run.hpp"

#include <algorithm>

#include "libsph/core/distribution.hpp"
#include "libsph/core/time_stepper.hpp"
#include "libsph/io/run_harness.hpp"

namespace cardiosph {

void declare_ep_numerics(sph::Parameters& p, EpSceneNumerics& n, const std::string& time_unit) {
  declare_parameters(p, n.discretisation, time_unit);
  cardio::declare_parameters(p, n.monodomain, time_unit);
  declare_apd_percent(p, n.apd_percent);
}

void declare_apd_percent(sph::Parameters& p, double& percent) {
  p.add("apd_percent", percent, "%",
        "action potential maps at this repolarisation percentage (fields apdNN, latest_activation_time, "
        "repolarisation_time, diastolic_interval, max_upstroke_velocity, beats, conduction_velocity; summary in "
        "report.json); 0: none",
        sph::Range{0, 100, false, true});
}

std::pair<sph::Real, sph::Real> TissueProperties::diffusivities() const {
  const double sigma_l = sigma_il * sigma_el / (sigma_il + sigma_el), sigma_t = sigma_it * sigma_et / (sigma_it + sigma_et);
  return {cardio::monodomain_diffusivity(sigma_l, surface_to_volume, capacitance),
          cardio::monodomain_diffusivity(sigma_t, surface_to_volume, capacitance)};
}

void declare_parameters(sph::Parameters& p, TissueProperties& t) {
  p.add("sigma_il", t.sigma_il, "S/m", "intracellular conductivity along the fibres", sph::Range::positive());
  p.add("sigma_it", t.sigma_it, "S/m", "intracellular conductivity across the fibres", sph::Range::positive());
  p.add("sigma_el", t.sigma_el, "S/m", "extracellular conductivity along the fibres", sph::Range::positive());
  p.add("sigma_et", t.sigma_et, "S/m", "extracellular conductivity across the fibres", sph::Range::positive());
  p.add("surface_to_volume", t.surface_to_volume, "1/mm", "membrane surface-to-volume ratio chi", sph::Range::positive());
  p.add("capacitance", t.capacitance, "uF/mm^2", "membrane capacitance C_m", sph::Range::positive());
}

template <int Dim>
EpTraces run_monodomain(cardio::Monodomain<Dim>& monodomain, sph::ParticleSet<Dim>& body,
                        const sph::NeighbourList<Dim>& relation, const sph::PointProbes<Dim>& probes,
                        const EpRunPlan& plan, RunContext& ctx) {
  const auto V = body.field(monodomain.potential_field());
  EpTraces traces;
  traces.potential.resize(probes.size());

  sph::TimeStepper stepper(0, static_cast<sph::Real>(plan.end_time));
  stepper.add_stage(monodomain.stage("monodomain"));
  stepper.add_step_callback([&](const sph::StepInfo& s) {
    if (plan.every_step) plan.every_step(s);
    if (plan.stop_when_all_activated && monodomain.all_activated()) stepper.stop_after_this_step();
  });
  sph::RunHarness run(stepper, ctx.report, {ctx.output_dir, plan.scene, ctx.quiet, ctx.checkpoint});
  run.add_body(body, static_cast<sph::Real>(plan.output_interval), [&](double) { monodomain.update_conduction_velocity(); });
  run.add_relation(body.name(), relation);
  std::vector<std::string> columns;
  for (std::size_t p = 0; p < probes.size(); ++p)
    columns.push_back((p < plan.probe_names.size() ? plan.probe_names[p] : "P" + std::to_string(p)) + "_potential");
  const double sample = plan.sample_interval > 0 ? plan.sample_interval : plan.end_time / 1000;
  std::vector<sph::Real> whole_V;  // the probes lie on the whole body (a distributed run gathers V)
  run.add_time_series("observers.csv", columns, static_cast<sph::Real>(sample), [&](const sph::StepInfo& s) {
    std::vector<double> row;
    traces.time.push_back(s.time);
    const auto V_all = sph::gather_all(body, std::span<const sph::Real>(V), whole_V);
    for (std::size_t p = 0; p < probes.size(); ++p) {
      row.push_back(probes.sample(p, V_all));
      traces.potential[p].push_back(row.back());
    }
    return row;
  });

  run.keep("monodomain", monodomain);
  run.keep("traces", traces);
  plan.attach(run, static_cast<sph::Real>(sample));
  if (plan.before_run) plan.before_run(run);
  auto& report = ctx.report;
  report.results["time_step"] = monodomain.time_step();
  report.results["diffusion_time_step_limit"] = monodomain.diffusion_time_step();
  run.run();
  const auto& timing = monodomain.timings();
  report.results["reaction_seconds"] = timing.reaction;
  report.results["diffusion_seconds"] = timing.diffusion;
  report.results["diffusion_substeps"] = monodomain.diffusion_substeps();
  report.results["reaction_steps_taken"] = monodomain.reaction_steps_taken();
  if (monodomain.maps()) report.results["maps"] = ep_map_summary(monodomain);
  if (run.time_loop_seconds() > 0 && report.steps > 0)
    report.results["particle_steps_per_second"] =
        double(report.steps) * double(body.partition() ? body.partition()->n_global : body.n_particles()) / run.time_loop_seconds();
  return traces;
}

namespace {
nlohmann::json distribution(std::vector<double> values) {
  nlohmann::json d;
  d["count"] = values.size();
  if (values.empty()) return d;
  std::sort(values.begin(), values.end());
  auto at = [&](double q) { return values[std::size_t(q * double(values.size() - 1) + 0.5)]; };
  d["min"] = values.front();
  d["p10"] = at(0.1);
  d["median"] = at(0.5);
  d["p90"] = at(0.9);
  d["max"] = values.back();
  return d;
}
}  // namespace

template <int Dim>
nlohmann::json ep_map_summary(cardio::Monodomain<Dim>& monodomain) {
  const auto* maps = monodomain.maps();
  if (!maps) return nullptr;
  monodomain.update_conduction_velocity();
  const auto& body = monodomain.particles();
  auto values = [&](sph::FieldHandle<sph::Real> field, double lowest) {  // over the whole set (gathered)
    std::vector<sph::Real> whole;
    std::vector<double> v;
    for (sph::Real x : sph::gather_all(body, std::span<const sph::Real>(body.field(field)), whole))
      if (x > lowest) v.push_back(x);
    return v;
  };
  nlohmann::json s;
  s["repolarisation_percent"] = maps->repolarisation_percent();
  s[maps->apd_name() + "_ms"] = distribution(values(maps->apd_field(), 0));
  s["diastolic_interval_ms"] = distribution(values(maps->diastolic_interval_field(), -1));
  s["max_upstroke_velocity_mV_per_ms"] = distribution(values(maps->upstroke_velocity_field(), 0));
  s["conduction_velocity_mm_per_ms"] = distribution(values(monodomain.conduction_velocity_field(), 0));
  s["seconds"] = monodomain.timings().maps;
  const std::size_t steps = monodomain.steps();
  if (steps > 0) s["seconds_per_step"] = monodomain.timings().maps / double(steps);
  return s;
}

std::vector<double> upward_crossings(const std::vector<double>& time, const std::vector<double>& value, double level) {
  std::vector<double> crossings;
  for (std::size_t i = 1; i < time.size(); ++i)
    if (value[i - 1] < level && value[i] >= level)
      crossings.push_back(time[i - 1] + (level - value[i - 1]) / (value[i] - value[i - 1]) * (time[i] - time[i - 1]));
  return crossings;
}

template nlohmann::json ep_map_summary<2>(cardio::Monodomain<2>&);
template nlohmann::json ep_map_summary<3>(cardio::Monodomain<3>&);
template EpTraces run_monodomain<2>(cardio::Monodomain<2>&, sph::ParticleSet<2>&, const sph::NeighbourList<2>&,
                                    const sph::PointProbes<2>&, const EpRunPlan&, RunContext&);
template EpTraces run_monodomain<3>(cardio::Monodomain<3>&, sph::ParticleSet<3>&, const sph::NeighbourList<3>&,
                                    const sph::PointProbes<3>&, const EpRunPlan&, RunContext&);

}  // namespace cardiosph
