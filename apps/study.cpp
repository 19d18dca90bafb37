#include "apps/study.hpp"

#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include "apps/plot.hpp"
#include "libsph/io/atomic_file.hpp"

namespace cardiosph {
namespace {

namespace fs = std::filesystem;

struct Sweep {
  std::string key;
  std::vector<std::string> values;
};

Sweep parse_sweep(const std::string& text, const std::string& option = "--sweep") {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
    throw sph::ParameterError("option '" + option + "' = '" + text + "': expected key=value1,value2,...");
  Sweep sweep{text.substr(0, eq), {}};
  std::stringstream values(text.substr(eq + 1));
  for (std::string v; std::getline(values, v, ',');) {
    if (v.empty()) throw sph::ParameterError("option '" + option + "' = '" + text + "': empty value");
    sweep.values.push_back(v);
  }
  if (sweep.values.size() < 2) throw sph::ParameterError("option '" + option + "' = '" + text + "': give at least two values");
  return sweep;
}

bool parse_number(const std::string& s, double& v) {
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return end && *end == '\0' && std::isfinite(v);
}

void plot(const fs::path& folder, const std::vector<std::string>& error_names, const std::string& scene,
          const std::string& key) {
  CsvPlot plot{"study.csv", "study.png", scene + ": error against wall time (sweep of " + key + ")", "wall time [s]",
                  "error", {}};
  for (std::size_t e = 0; e < error_names.size(); ++e) plot.series.push_back({5, 6 + static_cast<int>(e), error_names[e], ""});
  plot_csv(folder, plot);
}

struct SweepResult {
  int exit_code = exit_ok;
  std::vector<std::string> error_names;
};

// Runs the sweep into `folder` (one subfolder a value, study.csv, study.png), with `fixed` added to
// every run's assignments, and prints the errors and their observed orders.
SweepResult run_sweep(const std::string& scene_name, const Sweep& sweep, const CommonOptions& options, const fs::path& folder,
                      const std::vector<std::string>& fixed) {
  fs::create_directories(folder);
  std::vector<sph::RunReport> reports;
  SweepResult out;
  for (const auto& value : sweep.values) {
    CommonOptions run = options;
    run.output = folder / (sweep.key + "-" + value);
    run.quiet = true;
    std::vector<std::string> assignments = fixed;
    assignments.push_back(sweep.key + "=" + value);
    if (!options.quiet) std::cout << "study " << scene_name << ": " << sweep.key << " = " << value << " ..." << std::flush;
    const auto result = run_scene(scene_name, run, assignments);
    if (!options.quiet) std::cout << " " << result.report.status << " in " << result.report.wall_time_s << " s\n";
    if (result.exit_code != exit_ok) {
      std::cerr << "study: the run with " << sweep.key << " = " << value << " failed; see " << run.output.string() << '\n';
      out.exit_code = result.exit_code;
      return out;
    }
    reports.push_back(result.report);
  }

  // Table.
  auto& error_names = out.error_names;
  for (auto it = reports.front().errors.json().begin(); it != reports.front().errors.json().end(); ++it) error_names.push_back(it.key());
  std::ostringstream csv;
  csv << std::setprecision(10) << sweep.key << ",particles,steps,threads,wall_time_s";
  for (const auto& e : error_names) csv << ',' << e;
  csv << '\n';
  for (std::size_t k = 0; k < reports.size(); ++k) {
    std::size_t particles = 0;
    for (const auto& n : reports[k].particles.json()) particles += n.get<std::size_t>();
    csv << sweep.values[k] << ',' << particles << ',' << reports[k].steps << ',' << reports[k].threads << ','
        << reports[k].wall_time_s;
    for (const auto& e : error_names) csv << ',' << reports[k].errors.value(e, std::nan(""));
    csv << '\n';
  }
  sph::write_file_atomically(folder / "study.csv", csv.str());
  if (!error_names.empty()) plot(folder, error_names, scene_name, sweep.key);

  // Observed orders.
  std::cout << "study " << scene_name;
  for (const auto& f : fixed) std::cout << " (" << f << ")";
  std::cout << ": results in " << folder.string() << " (study.csv, study.png)\n";
  std::cout << std::setprecision(4);
  for (const auto& e : error_names) {
    std::cout << "  " << e << ":";
    for (std::size_t k = 0; k < reports.size(); ++k) std::cout << ' ' << reports[k].errors.value(e, std::nan(""));
    std::cout << "\n    observed order with respect to " << sweep.key << ":";
    for (std::size_t k = 0; k + 1 < reports.size(); ++k) {
      double v0, v1;
      const double e0 = reports[k].errors.value(e, std::nan("")), e1 = reports[k + 1].errors.value(e, std::nan(""));
      if (parse_number(sweep.values[k], v0) && parse_number(sweep.values[k + 1], v1) && v0 > 0 && v1 > 0 && v0 != v1 &&
          e0 > 0 && e1 > 0)
        std::cout << ' ' << std::log(e0 / e1) / std::abs(std::log(v1 / v0));  // a resolution or a spacing
      else
        std::cout << " n/a";
    }
    std::cout << '\n';
  }
  return out;
}

}  // namespace

int run_study(const std::string& scene_name, const std::string& sweep_text, const std::string& compare_text,
              const CommonOptions& options) {
  const Sweep sweep = parse_sweep(sweep_text);
  const Sweep compare = compare_text.empty() ? Sweep{} : parse_sweep(compare_text, "--compare");
  if (!find_scene(scene_name)) throw sph::ParameterError("unknown scene '" + scene_name + "' (see 'cardiosph list')");
  if (compare.key == sweep.key) throw sph::ParameterError("options '--sweep' and '--compare' name the same key '" + sweep.key + "'");
  const fs::path folder = options.output.empty() ? fs::path("output") / ("study-" + scene_name) : options.output;
  if (fs::exists(folder) && !fs::is_empty(folder) && !fs::exists(folder / "study.csv") && !fs::exists(folder / "study.png"))
    throw sph::ParameterError("output folder '" + folder.string() +
                              "' exists and does not hold an earlier study (no study.csv); choose another --output");
  // Check every setting before running any of them (bad input costs nothing).
  const std::vector<std::string> compared = compare.key.empty() ? std::vector<std::string>{""} : compare.values;
  for (const auto& c : compared)
    for (const auto& value : sweep.values) {
      CommonOptions check = options;
      check.check_only = true;
      std::vector<std::string> assignments{sweep.key + "=" + value};
      if (!c.empty()) assignments.push_back(compare.key + "=" + c);
      run_scene(scene_name, check, assignments);
    }
  if (compare.key.empty()) return run_sweep(scene_name, sweep, options, folder, {}).exit_code;

  // One sweep a compared value, in its own subfolder; one picture of them all.
  CsvPlot plot{"", "study.png", scene_name + ": error against wall time (sweep of " + sweep.key + ", by " + compare.key + ")",
                  "wall time [s]", "error", {}};
  for (const auto& c : compare.values) {
    const std::string sub = compare.key + "-" + c;
    const auto result = run_sweep(scene_name, sweep, options, folder / sub, {compare.key + "=" + c});
    if (result.exit_code != exit_ok) return result.exit_code;
    for (std::size_t e = 0; e < result.error_names.size(); ++e)
      plot.series.push_back({5, 6 + static_cast<int>(e), result.error_names[e] + " (" + compare.key + " = " + c + ")", sub + "/study.csv"});
  }
  plot_csv(folder, plot);
  std::cout << "study " << scene_name << ": comparison in " << (folder / "study.png").string() << '\n';
  return exit_ok;
}

}  // namespace cardiosph
