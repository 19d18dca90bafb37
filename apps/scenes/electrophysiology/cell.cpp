// `cell`: single-cell action potentials of every cell model, paced, integrated by every cell scheme
// over a ladder of time steps and compared with the CVODE (BDF) reference: RMS voltage error and
// APD90 error against wall time, per model a table (cell_<model>.csv) and a plot (cell_<model>.png).
// Also measured: the forward-Euler stability limit along the reference trajectory (from the
// eigenvalues of the Jacobian) and, per scheme, the largest step of the ladder that stays stable.
#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>

#include "apps/plot.hpp"
#include "apps/scenes/electrophysiology/ep_scenes.hpp"
#include "libsph/io/atomic_file.hpp"
#include "libsph/reaction/cell_models.hpp"
#include "libsph/reaction/cell_simulation.hpp"
#if CARDIOSPH_HAVE_CVODE
#include "libsph/reaction/cvode_integrator.hpp"
#endif

namespace cardiosph {
namespace {

constexpr std::array<sph::ReactionScheme, 3> schemes{sph::ReactionScheme::forward_euler, sph::ReactionScheme::rush_larsen,
                                                     sph::ReactionScheme::rbr_qss};

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

struct Trace {
  std::vector<double> t, V;
};

class CellScene final : public Scene {
 public:
  explicit CellScene(CellParameters p) : p_(std::move(p)) {}
  void declare(sph::Parameters& p) override {
    std::vector<std::string> models{"all"};
    for (auto name : sph::cell_model_names) models.emplace_back(name);
    p.add_choice("model", p_.model, models, "cell model, or all of them");
    p.add("resolution", p_.resolution, "-", "rungs of the step ladder: smallest_time_step times 1, 2, 4, ...",
          sph::Range::closed(1, 16));
    p.add("end_time", p_.end_time, "ms", "simulated time; APD90 is measured on the last paced beat", sph::Range::positive());
    p.add("period", p_.period, "ms", "pacing cycle length", sph::Range::positive());
    p.add("stimulus_strength", p_.stimulus_strength, "mV/ms", "applied dV/dt during a pulse", sph::Range::positive());
    p.add("stimulus_duration", p_.stimulus_duration, "ms", "pulse length", sph::Range::positive());
    p.add("smallest_time_step", p_.smallest_time_step, "ms", "first rung of the step ladder", sph::Range::positive());
    p.add("sample_interval", p_.sample_interval, "ms", "spacing of the samples where the voltage error is measured",
          sph::Range::positive());
    p.add("reaction_lookup_table", p_.lookup_table, "mV",
          "ten Tusscher-Panfilov also by rbr_qss with the functions of V in lookup tables of this step (rbr_qss_table); 0: not",
          sph::Range::closed(0, 1));
    p.add("cvode_tolerance", p_.cvode_tolerance, "-", "relative tolerance of the CVODE reference (absolute: 1e-3 of it)",
          {1e-14, 1e-4, false, false});
  }
  void check() const override {
#if !CARDIOSPH_HAVE_CVODE
    throw sph::ParameterError("scene 'cell' needs the CVODE reference: build with CARDIOSPH_WITH_CVODE=ON");
#endif
    if (p_.end_time < p_.period) throw sph::ParameterError("parameter 'end_time' must cover at least one 'period'");
  }
  void run(RunContext& ctx) override {
#if CARDIOSPH_HAVE_CVODE
    for (std::size_t m = 0; m < sph::cell_model_names.size(); ++m) {
      const std::string name(sph::cell_model_names[m]);
      if (p_.model != "all" && p_.model != name) continue;
      std::visit([&](const auto& model) { run_model(model, name, ctx); }, sph::make_cell_model(name));
    }
    ctx.report.simulated_time = p_.end_time;
    std::ostringstream reference;
    reference << "SUNDIALS CVODE (BDF, Newton, dense) at relative tolerance " << p_.cvode_tolerance;
    ctx.report.reference = reference.str();
#else
    (void)ctx;
#endif
  }

 private:
#if CARDIOSPH_HAVE_CVODE
  template <class M>
  void run_model(const M& model, const std::string& name, RunContext& ctx) {
    const int beats = static_cast<int>(std::ceil(p_.end_time / p_.period - 1e-9));
    const sph::StimulusProtocol stimulus{0, p_.stimulus_duration, p_.stimulus_strength, p_.period, beats};
    const double last_beat = (beats - 1) * p_.period;

    // Reference, and the forward-Euler limit along it.
    Trace ref;
    double euler_limit = std::numeric_limits<double>::infinity();
    const auto start = std::chrono::steady_clock::now();
    const long cvode_steps = sph::solve_cell_with_cvode(
        model, stimulus, p_.end_time, p_.sample_interval,
        [&](double t, const auto& y) {
          ref.t.push_back(t);
          ref.V.push_back(y[0]);
        },
        {p_.cvode_tolerance, 1e-3 * p_.cvode_tolerance, 0, 1'000'000});
    const double cvode_seconds = seconds_since(start);
    sph::solve_cell_with_cvode(model, stimulus, p_.end_time, p_.sample_interval, [&](double t, const auto& y) {
      euler_limit = std::min(euler_limit, sph::explicit_euler_step_limit(model, y, stimulus.average(t, 0)));
    });
    const double apd_ref = sph::measure_action_potential(ref.t, ref.V, last_beat, p_.end_time).duration();

    auto& results = ctx.report.results[name];
    results["cvode_apd90_ms"] = apd_ref;
    results["cvode_steps"] = cvode_steps;
    results["cvode_wall_s"] = cvode_seconds;
    results["forward_euler_step_limit_ms"] = euler_limit;

    // The ladder: every scheme at every step, and for a model with lookup tables rbr_qss with them.
    struct Variant {
      std::string key;
      sph::ReactionScheme scheme;
      bool table;
    };
    std::vector<Variant> variants;
    for (auto s : schemes) variants.push_back({std::string(sph::to_string(s)), s, false});
    M tabulated = model;
    if constexpr (requires { model.with_voltage_table(0.1); }) {
      if (p_.lookup_table > 0) {
        tabulated = model.with_voltage_table(p_.lookup_table);
        variants.push_back({"rbr_qss_table", sph::ReactionScheme::rbr_qss, true});
      }
    }
    std::ostringstream csv;
    csv << "time_step_ms";
    for (const auto& v : variants)
      for (const char* column : {"_wall_s", "_rms_mV", "_apd90_ms", "_apd90_error_ms"}) csv << ',' << v.key << column;
    csv << '\n' << std::setprecision(8);
    std::map<std::string, double> largest_stable, largest_within_5pct;
    for (long rung = 0; rung < p_.resolution; ++rung) {
      const double dt = p_.smallest_time_step * std::pow(2.0, static_cast<double>(rung));
      csv << dt;
      results["time_steps_ms"].push_back(dt);
      for (const auto& v : variants) {
        Trace trace;
        const auto scheme_start = std::chrono::steady_clock::now();
        const bool stable = sph::simulate_cell(v.table ? tabulated : model, v.scheme, dt, stimulus, p_.end_time, [&](double t, const auto& y) {
          trace.t.push_back(t);
          trace.V.push_back(y[0]);
        });
        const double wall = seconds_since(scheme_start);
        const std::string& key = v.key;
        results[key]["stable"].push_back(stable);
        if (!stable) {
          csv << ",nan,nan,nan,nan";
          results[key]["apd90_error_ms"].push_back(nullptr);
          results[key]["rms_mV"].push_back(nullptr);
          continue;
        }
        double sum = 0;
        for (std::size_t i = 0; i < ref.t.size(); ++i)
          sum += std::pow(sph::interpolate_trace(trace.t, trace.V, ref.t[i]) - ref.V[i], 2);
        const double rms = std::sqrt(sum / static_cast<double>(ref.t.size()));
        const double apd = sph::measure_action_potential(trace.t, trace.V, last_beat, p_.end_time).duration();
        const double apd_error = apd > 0 ? std::abs(apd - apd_ref) : std::numeric_limits<double>::infinity();
        csv << ',' << wall << ',' << rms << ',' << apd << ',' << apd_error;
        results[key]["apd90_error_ms"].push_back(apd_error);
        results[key]["rms_mV"].push_back(rms);
        largest_stable[key] = dt;
        if (apd_error <= 0.05 * apd_ref) largest_within_5pct[key] = std::max(largest_within_5pct[key], dt);
        if (rung == 0) ctx.report.errors[name + "_" + key + "_apd90_relative"] = apd_error / apd_ref;
        if (rung == 0) ctx.report.errors[name + "_" + key + "_rms_mV"] = rms;
      }
      csv << '\n';
    }
    for (const auto& v : variants) {
      const std::string& key = v.key;
      results[key]["largest_stable_time_step_ms"] = largest_stable.count(key) ? largest_stable[key] : 0.0;
      results[key]["largest_time_step_within_5pct_apd90_ms"] =
          largest_within_5pct.count(key) ? largest_within_5pct[key] : 0.0;
    }
    const std::string file = "cell_" + name + ".csv";
    sph::write_file_atomically(ctx.output_dir / file, csv.str());
    CsvPlot plot{file, "cell_" + name + ".png", name + ": error against wall time (CVODE reference)", "wall time [s]",
                    "RMS voltage error [mV], APD90 error [ms]", {}};
    for (std::size_t s = 0; s < variants.size(); ++s) {
      const int first = 2 + 4 * static_cast<int>(s);
      plot.series.push_back({first, first + 1, variants[s].key + " RMS V", ""});
      plot.series.push_back({first, first + 3, variants[s].key + " APD90", ""});
    }
    plot_csv(ctx.output_dir, plot);
  }
#endif
  CellParameters p_;
};

}  // namespace

std::unique_ptr<Scene> make_cell_scene(CellParameters p) { return std::make_unique<CellScene>(std::move(p)); }

}  // namespace cardiosph
