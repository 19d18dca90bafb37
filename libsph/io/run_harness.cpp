#include "libsph/io/run_harness.hpp"

#include <sys/resource.h>

#include <chrono>

#include "libsph/core/numerical_failure.hpp"
#include "libsph/io/progress.hpp"

namespace sph {
namespace {

double peak_rss_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

}  // namespace

RunHarness::RunHarness(TimeStepper& stepper, RunReport& report, Options options)
    : stepper_(stepper), report_(report), options_(std::move(options)), last_completed_(double(stepper.start_time())) {
  stepper_.add_step_callback([this](const StepInfo& s) {
    last_completed_ = double(s.time);
    if (progress_) progress_->update(s);
  });
}

RunHarness::~RunHarness() = default;

void RunHarness::add_time_series(const std::string& file, std::vector<std::string> columns, Real interval, Row row) {
  columns.insert(columns.begin(), "time");
  const std::size_t n_columns = columns.size();
  series_.push_back(std::make_unique<TimeSeriesCsv>(options_.output_dir / file, std::move(columns)));
  TimeSeriesCsv& csv = *series_.back();
  stepper_.add_periodic_callback(
      interval,
      [this, &csv, n_columns, row = std::move(row)](const StepInfo& s) {
        timers_.measure("output_and_sampling", [&] {
          std::vector<double> values = row(s);
          values.insert(values.begin(), double(s.time));
          if (values.size() != n_columns)
            throw std::logic_error("time series: a row of " + std::to_string(values.size()) + " values for " +
                                   std::to_string(n_columns) + " columns");
          csv.record(values);
        });
      },
      false);
}

void RunHarness::write_bodies(double time) {
  for (const auto& write : writers_) write(time);
}

std::size_t RunHarness::run() {
  progress_ = std::make_unique<Progress>(options_.label, options_.quiet);
  report_.simulated_time = double(stepper_.end_time());
  const auto start = std::chrono::steady_clock::now();
  auto finish = [&] {
    progress_->finish();
    time_loop_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    nlohmann::json seconds = nlohmann::json::object();
    for (const auto& [name, value] : timers_.all()) seconds[name] = value;
    seconds["time_loop"] = time_loop_seconds_;
    report_.results["seconds"] = seconds;
    report_.results["peak_rss_mb"] = peak_rss_mb();
  };
  try {
    report_.steps = stepper_.run();
  } catch (const NumericalFailure&) {
    finish();
    write_bodies(last_completed_);
    report_.simulated_time = last_completed_;
    for (auto& s : series_) s->close();
    throw;
  }
  finish();
  report_.simulated_time = double(stepper_.end_time());
  for (auto& s : series_) s->close();
  return report_.steps;
}

}  // namespace sph
