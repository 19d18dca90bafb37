#include "apps/scenes/electrophysiology/pacing.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "apps/plot.hpp"
#include "libsph/io/atomic_file.hpp"

namespace cardiosph {

void declare_parameters(sph::Parameters& p, PacingParameters& pacing) {
  p.add_choice("pacing", pacing.protocol, {"train", "s1s2", "restitution"},
               "pacing protocol: pacing_count pulses every pacing_period (train); s1_count S1 pulses then an S2 at "
               "s2_coupling (s1s2); or an S1-S2 block for each of restitution_couplings, writing restitution.csv/png "
               "(restitution)");
  p.add("pacing_period", pacing.period, "ms", "time between S1 pulses (basic cycle length)", sph::Range::positive());
  p.add("pacing_count", pacing.count, "1", "pulses of a train", sph::Range::closed(1, 10000));
  p.add("s1_count", pacing.s1_count, "1", "S1 pulses before each S2 (s1s2, restitution)", sph::Range::closed(1, 10000));
  p.add("s2_coupling", pacing.s2_coupling, "ms", "S2 onset after the last S1 onset (s1s2)", sph::Range::positive());
  p.add_text("restitution_couplings", pacing.couplings,
             "S2 coupling intervals of the restitution protocol, comma-separated [ms], one S1-S2 block each");
}

namespace {
std::vector<double> parse_couplings(const std::string& text) {
  std::vector<double> values;
  std::istringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      throw sph::ParameterError("parameter 'restitution_couplings': '" + item + "' is not a number");
    }
    if (item.find_first_not_of(" \t", used) != std::string::npos || !(v > 0) || !std::isfinite(v))
      throw sph::ParameterError("parameter 'restitution_couplings': '" + item + "' is not a positive number");
    values.push_back(v);
  }
  if (values.empty()) throw sph::ParameterError("parameter 'restitution_couplings' lists no coupling interval");
  return values;
}
}  // namespace

PacingPlan pacing_plan(const PacingParameters& p, double duration, double strength) {
  if (!(p.period > duration))
    throw sph::ParameterError("parameter 'pacing_period' must be longer than the stimulus duration");
  PacingPlan plan;
  plan.stimulus = {0, duration, strength, p.period, 1};
  if (p.protocol == "train") {
    plan.stimulus.count = int(p.count);
    plan.end_time = double(p.count) * p.period;
    return plan;
  }
  const std::vector<double> couplings = p.protocol == "s1s2" ? std::vector<double>{p.s2_coupling} : parse_couplings(p.couplings);
  const std::string key = p.protocol == "s1s2" ? "s2_coupling" : "restitution_couplings";
  plan.stimulus.count = 0;
  double block = 0;
  for (double ci : couplings) {
    if (!(ci > duration))
      throw sph::ParameterError("parameter '" + key + "': the coupling interval " + std::to_string(ci) +
                                " ms must be longer than the stimulus duration");
    for (long k = 0; k < p.s1_count; ++k) plan.stimulus.extra_onsets.push_back(block + double(k) * p.period);
    const double s2 = block + double(p.s1_count - 1) * p.period + ci;
    plan.stimulus.extra_onsets.push_back(s2);
    plan.s2_onsets.push_back(s2);
    block = s2 + p.period;
  }
  plan.end_time = block;
  return plan;
}

template <int Dim>
BeatRecorder<Dim>::BeatRecorder(const cardio::Monodomain<Dim>& monodomain, std::vector<Point> points, std::size_t cv_from,
                                std::size_t cv_to)
    : monodomain_(monodomain), points_(std::move(points)), cv_from_(cv_from), cv_to_(cv_to),
      beats_(points_.size()), counted_(points_.size(), 0) {
  if (!monodomain.maps()) throw sph::ParameterError("the beat records need the action potential maps (apd_percent > 0)");
  const auto& x = monodomain.particles().position;
  distance_ = double((x.at(points_.at(cv_to).particle) - x.at(points_.at(cv_from).particle)).norm());
}

template <int Dim>
void BeatRecorder<Dim>::record() {
  const auto* maps = monodomain_.maps();
  const auto& body = monodomain_.particles();
  const auto beats = body.field(maps->beats_field());
  for (std::size_t p = 0; p < points_.size(); ++p) {
    const std::size_t i = points_[p].particle;
    if (beats[i] <= counted_[p]) continue;
    counted_[p] = beats[i];
    beats_[p].push_back({double(body.field(maps->latest_activation_field())[i]), double(body.field(maps->apd_field())[i]),
                         double(body.field(maps->diastolic_interval_field())[i])});
  }
}

template <int Dim>
void BeatRecorder<Dim>::finish(const std::filesystem::path& folder, const PacingPlan& plan, double period,
                               sph::RunReport& report) const {
  std::ostringstream csv;
  csv << "point,beat,activation_ms,apd_ms,diastolic_interval_ms\n";
  auto& s = report.results["beats"];
  for (std::size_t p = 0; p < points_.size(); ++p) {
    for (std::size_t b = 0; b < beats_[p].size(); ++b)
      csv << points_[p].name << ',' << b + 1 << ',' << beats_[p][b].activation << ',' << beats_[p][b].apd << ','
          << beats_[p][b].diastolic_interval << '\n';
    s["count"][points_[p].name] = beats_[p].size();
  }
  sph::write_file_atomically(folder / "beats.csv", csv.str());
  const auto& main = beats_[0];
  s["apd_point"] = points_[0].name;
  if (!main.empty()) s["last_apd_ms"] = main.back().apd;
  if (main.size() >= 2) s["last_two_apd_change_ms"] = main.back().apd - main[main.size() - 2].apd;
  // The beat of a point activated within [onset, onset + period), if any.
  auto beat_after = [&](std::size_t p, double onset) -> const Beat* {
    for (const auto& b : beats_[p])
      if (b.activation >= onset && b.activation < onset + period) return &b;
    return nullptr;
  };
  // CV of every beat that reached both points: the first activation of the far point after the near
  // one's and before the near point's next beat (a beat blocked in between has none).
  std::vector<double> cv_of_beats;
  const auto& near = beats_[cv_from_];
  for (std::size_t k = 0; k < near.size(); ++k) {
    const double next = k + 1 < near.size() ? near[k + 1].activation : std::numeric_limits<double>::infinity();
    for (const auto& far : beats_[cv_to_])
      if (far.activation > near[k].activation && far.activation < next) {
        cv_of_beats.push_back(distance_ / (far.activation - near[k].activation));
        break;
      }
  }
  s["cv_points"] = {points_[cv_from_].name, points_[cv_to_].name};
  s["cv_mm_per_ms"] = cv_of_beats;
  if (plan.s2_onsets.empty()) return;

  std::ostringstream table;
  table << "coupling_ms,diastolic_interval_ms,apd_ms,cv_mm_per_ms\n";
  auto& curve = s["restitution"];
  for (std::size_t k = 0; k < plan.s2_onsets.size(); ++k) {
    const double onset = plan.s2_onsets[k];
    const Beat* b = beat_after(0, onset);
    const Beat* from = beat_after(cv_from_, onset);
    const Beat* to = beat_after(cv_to_, onset);
    // The S2's coupling interval: its onset minus the S1 onset before it.
    double coupling = 0;
    for (double o : plan.stimulus.onsets())
      if (o < onset) coupling = onset - o;
    nlohmann::json row = {{"coupling_ms", coupling}, {"captured", b != nullptr}};
    if (b) {
      const double cv = from && to && to->activation > from->activation ? distance_ / (to->activation - from->activation) : -1;
      row["diastolic_interval_ms"] = b->diastolic_interval;
      row["apd_ms"] = b->apd;
      row["cv_mm_per_ms"] = cv;
      table << coupling << ',' << b->diastolic_interval << ',' << b->apd << ',' << cv << '\n';
    }
    curve.push_back(row);
  }
  sph::write_file_atomically(folder / "restitution.csv", table.str());
  CsvPlot plot{"restitution.csv", "restitution.png", "restitution (S2 beats)", "diastolic interval [ms]", "", {}, false,
               "linespoints", 2};
  plot.series = {{2, 3, "APD [ms] at " + points_[0].name, ""},
                 {2, 4, "CV [mm/ms] from " + points_[cv_from_].name + " to " + points_[cv_to_].name, ""}};
  plot_csv(folder, plot);
}

template class BeatRecorder<2>;
template class BeatRecorder<3>;

}  // namespace cardiosph
