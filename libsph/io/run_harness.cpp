#include "libsph/io/run_harness.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <limits>

#include <nlohmann/json.hpp>

#include "libsph/core/numerical_failure.hpp"
#include "libsph/io/parameters.hpp"
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
  series_.push_back(writes_files_ ? std::make_unique<TimeSeriesCsv>(options_.output_dir / file, std::move(columns)) : nullptr);
  TimeSeriesCsv* csv = series_.back().get();
  stepper_.add_periodic_callback(
      interval,
      [this, csv, n_columns, row = std::move(row)](const StepInfo& s) {
        timers_.measure("output_and_sampling", [&] {
          std::vector<double> values = row(s);
          values.insert(values.begin(), double(s.time));
          if (values.size() != n_columns)
            throw std::logic_error("time series: a row of " + std::to_string(values.size()) + " values for " +
                                   std::to_string(n_columns) + " columns");
          if (csv) csv->record(values);
        });
      },
      false);
}

void RunHarness::add_state(const std::string& name, std::function<void(StateArchive&)> state) {
  for (const auto& [existing, _] : states_)
    if (existing == name) throw std::logic_error("run harness: two states named '" + name + "'");
  states_.emplace_back(name, std::move(state));
}

void RunHarness::save_or_load(StateArchive& archive) {
  auto stepper = archive.part("stepper");
  stepper_.checkpoint(stepper);
  auto harness = archive.part("harness");
  harness.io("next_checkpoint", next_checkpoint_);
  int ranks = Communicator::world().size();
  harness.io("ranks", ranks);
  if (archive.loading() && ranks != Communicator::world().size())
    throw StateError("it was written by " + std::to_string(ranks) + " MPI ranks, this run has " +
                     std::to_string(Communicator::world().size()));
  double loop_seconds = time_loop_before_ + std::chrono::duration<double>(std::chrono::steady_clock::now() - loop_start_).count();
  harness.io("time_loop_seconds", loop_seconds);
  if (archive.loading()) time_loop_before_ = loop_seconds;
  timers_.checkpoint(harness);
  for (std::size_t k = 0; k < series_.size(); ++k) {
    auto series = archive.part("series" + std::to_string(k));
    if (series_[k]) series_[k]->checkpoint(series);
  }
  for (auto& [name, state] : states_) {
    auto part = archive.part(name);
    state(part);
  }
}

bool RunHarness::checkpoint_after_step(const StepInfo& s) {
  const CheckpointPlan& plan = options_.checkpoint;
  const double t = double(s.time), start = double(stepper_.start_time());
  const double tolerance = plan.interval > 0 ? 1e-9 * plan.interval : 0.0;
  const bool periodic = plan.interval > 0 && start + double(next_checkpoint_) * plan.interval <= t + tolerance;
  const Communicator& comm = Communicator::world();
  bool stop = interrupt_requested() || t >= plan.interrupt_at;
  if (comm.size() > 1) stop = comm.any(stop);  // a signal may reach the ranks at different steps
  if (!periodic && !stop) return false;
  while (plan.interval > 0 && start + double(next_checkpoint_) * plan.interval <= t + tolerance) ++next_checkpoint_;
  timers_.measure("checkpoint", [&] {
    Checkpoint checkpoint{plan.scene, plan.parameters, t, {}};
    StateArchive archive(checkpoint.records, StateArchive::Mode::save);
    save_or_load(archive);
    // Every rank its own part; the barrier holds the ranks until all parts are written.
    write_checkpoint(options_.output_dir / checkpoint_file_of_rank(comm.rank()), checkpoint);
    comm.barrier();
  });
  return stop;
}

void RunHarness::report_traffic(const Communicator::Traffic& before) {
  const Communicator& comm = Communicator::world();
  if (comm.size() == 1) return;
  const Communicator::Traffic& now = comm.traffic();
  const unsigned long long mine[4] = {now.exchanges - before.exchanges, now.messages - before.messages,
                                      now.bytes - before.bytes, now.collectives - before.collectives};
  std::vector<std::byte> bytes(sizeof(mine));
  std::memcpy(bytes.data(), mine, sizeof(mine));
  unsigned long long exchanges = 0, collectives = 0, messages_max = 0, messages_total = 0, bytes_max = 0, bytes_total = 0;
  for (const auto& part : comm.all_gather(bytes)) {
    unsigned long long r[4];
    std::memcpy(r, part.data(), sizeof(r));
    exchanges = std::max(exchanges, r[0]);
    messages_max = std::max(messages_max, r[1]);
    messages_total += r[1];
    bytes_max = std::max(bytes_max, r[2]);
    bytes_total += r[2];
    collectives = std::max(collectives, r[3]);
  }
  const double steps = double(std::max<std::size_t>(report_.steps, 1));
  nlohmann::json t;
  t["steps"] = report_.steps;
  t["halo_exchanges_per_step"] = double(exchanges) / steps;
  t["messages_per_step_max"] = double(messages_max) / steps;  // sent by the busiest rank
  t["messages_per_step_total"] = double(messages_total) / steps;
  t["bytes_per_step_max"] = double(bytes_max) / steps;
  t["bytes_per_step_total"] = double(bytes_total) / steps;
  t["collectives_per_step"] = double(collectives) / steps;
  report_.results["distribution"]["traffic"] = t;
}

void RunHarness::report_partition(const std::string& body, std::size_t owned, std::size_t ghosts, std::size_t neighbours) {
  const std::size_t mine[3] = {owned, ghosts, neighbours};
  std::vector<std::byte> bytes(sizeof(mine));
  std::memcpy(bytes.data(), mine, sizeof(mine));
  std::size_t owned_min = std::numeric_limits<std::size_t>::max(), owned_max = 0, ghosts_total = 0, ghosts_max = 0,
              neighbours_max = 0, owned_total = 0;
  for (const auto& part : Communicator::world().all_gather(bytes)) {
    std::size_t r[3];
    std::memcpy(r, part.data(), sizeof(r));
    owned_min = std::min(owned_min, r[0]);
    owned_max = std::max(owned_max, r[0]);
    owned_total += r[0];
    ghosts_total += r[1];
    ghosts_max = std::max(ghosts_max, r[1]);
    neighbours_max = std::max(neighbours_max, r[2]);
  }
  nlohmann::json d;
  d["ranks"] = Communicator::world().size();
  d["owned_min"] = owned_min;
  d["owned_max"] = owned_max;
  d["ghosts_total"] = ghosts_total;
  d["ghosts_max"] = ghosts_max;
  d["ghost_fraction"] = double(ghosts_total) / double(owned_total);
  d["neighbour_ranks_max"] = neighbours_max;
  report_.results["distribution"][body] = d;
}

void RunHarness::write_bodies(double time) {
  for (const auto& write : writers_) write(time);
}

std::size_t RunHarness::run() {
  const CheckpointPlan& plan = options_.checkpoint;
  // Particles that migrate between ranks (fluids) are laid out by their history, which a resumed
  // run could not restore: no checkpoints for them on several ranks.
  const bool can_checkpoint = plan.enabled && (fixed_layout_ || Communicator::world().size() == 1);
  if (plan.enabled && !can_checkpoint && (plan.resume || plan.interval > 0 || std::isfinite(plan.interrupt_at)))
    throw ParameterError("checkpoints (--checkpoint-interval, --interrupt-at, --resume) are not available on several ranks for "
                         "bodies whose particles migrate between the ranks (fluids); run on one rank to checkpoint");
  if (plan.resume) {
    if (!plan.enabled) throw std::logic_error("run harness: a checkpoint to resume from, but checkpoints are not enabled");
    StateArchive archive(plan.resume->records, StateArchive::Mode::load);
    try {
      save_or_load(archive);
    } catch (const StateError& error) {
      throw ParameterError("checkpoint of '" + plan.resume->scene + "' does not fit this run: " + error.what());
    }
    last_completed_ = plan.resume->time;
  }
  if (can_checkpoint) stepper_.set_interruption_check([this](const StepInfo& s) { return checkpoint_after_step(s); });
  progress_ = std::make_unique<Progress>(options_.label, options_.quiet || !writes_files_);
  report_.simulated_time = double(stepper_.end_time());
  const Communicator::Traffic traffic_before = Communicator::world().traffic();
  loop_start_ = std::chrono::steady_clock::now();
  const auto start = loop_start_;
  auto finish = [&] {
    progress_->finish();
    time_loop_seconds_ = time_loop_before_ + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
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
    for (auto& s : series_)
      if (s) s->close();
    throw;
  }
  finish();
  report_traffic(traffic_before);
  for (auto& s : series_)
    if (s) s->close();
  if (stepper_.interrupted()) {
    report_.simulated_time = last_completed_;
    throw RunInterrupted(last_completed_, options_.output_dir / checkpoint_file_name);
  }
  report_.simulated_time = double(stepper_.end_time());
  return report_.steps;
}

}  // namespace sph
