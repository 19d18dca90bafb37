#include "apps/run_scene.hpp"

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstdio>
#include <iostream>

#include "libsph/core/communicator.hpp"
#include "libsph/core/numerical_failure.hpp"
#include "libsph/core/parallel.hpp"
#include "libsph/io/checkpoint.hpp"
#include "libsph/io/particle_output.hpp"

namespace cardiosph {
namespace {

namespace fs = std::filesystem;

// An existing output folder is replaced only if it is empty or holds an earlier run (report.json).
void check_output_folder(const fs::path& output) {
  std::error_code ec;
  if (!fs::exists(output, ec)) return;
  if (!fs::is_directory(output, ec))
    throw sph::ParameterError("output '" + output.string() + "' exists and is not a folder");
  if (fs::is_empty(output, ec) || fs::exists(output / "report.json", ec)) return;
  throw sph::ParameterError("output folder '" + output.string() +
                            "' exists and does not hold an earlier run (no report.json); choose another --output");
}

void replace_folder(const fs::path& staging, const fs::path& output) {
  if (fs::exists(output)) fs::remove_all(output);
  fs::rename(staging, output);
}

// A number as text that parses back to the same double.
std::string exact(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.17g", v);
  return text;
}

// The parameters saved in a checkpoint as key=value assignments that give back the same values.
std::vector<std::string> saved_assignments(const sph::Checkpoint& checkpoint, const fs::path& file) {
  nlohmann::json values;
  try {
    values = nlohmann::json::parse(checkpoint.parameters);
  } catch (const nlohmann::json::exception& error) {
    throw sph::ParameterError("checkpoint '" + file.string() + "': its parameters are not valid JSON: " + error.what());
  }
  if (!values.is_object()) throw sph::ParameterError("checkpoint '" + file.string() + "': its parameters are not a JSON object");
  std::vector<std::string> out;
  for (auto it = values.begin(); it != values.end(); ++it) {
    const auto& v = it.value();
    std::string text;
    if (v.is_string()) text = v.get<std::string>();
    else if (v.is_boolean()) text = v.get<bool>() ? "true" : "false";
    else if (v.is_number_integer()) text = std::to_string(v.get<long long>());
    else if (v.is_number()) text = exact(v.get<double>());
    else if (v.is_array() && v.size() == 3 && v[0].is_number() && v[1].is_number() && v[2].is_number())
      text = exact(v[0].get<double>()) + "," + exact(v[1].get<double>()) + "," + exact(v[2].get<double>());
    else throw sph::ParameterError("checkpoint '" + file.string() + "': parameter '" + it.key() + "' has a value of unknown form");
    out.push_back(it.key() + "=" + text);
  }
  return out;
}

// Ranks that read their parameters differently (a config file that differs between nodes, mixed
// command lines) would compute different problems; every rank stops with the first difference.
void check_ranks_agree(const sph::Parameters& parameters, const fs::path& output, bool output_pieces) {
  const sph::Communicator& world = sph::Communicator::world();
  if (world.size() == 1) return;
  nlohmann::json mine = parameters.to_json();
  mine["(output folder)"] = output.string();
  mine["(--output-pieces)"] = output_pieces;
  const std::string text = mine.dump();
  const auto all = world.all_gather(std::vector<std::byte>(reinterpret_cast<const std::byte*>(text.data()),
                                                           reinterpret_cast<const std::byte*>(text.data()) + text.size()));
  const auto parse = [](const std::vector<std::byte>& bytes) {
    return nlohmann::json::parse(std::string(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
  };
  const nlohmann::json root = parse(all[0]);
  for (std::size_t q = 1; q < all.size(); ++q) {
    const nlohmann::json other = parse(all[q]);
    if (other == root) continue;
    for (auto it = root.begin(); it != root.end(); ++it)
      if (!other.contains(it.key()) || other[it.key()] != it.value())
        throw sph::ParameterError("the MPI ranks disagree about parameter '" + it.key() + "': " + it.value().dump() + " on rank 0, " +
                                  (other.contains(it.key()) ? other[it.key()].dump() : std::string("none")) + " on rank " +
                                  std::to_string(q) + " (give every rank the same command line and config file)");
    throw sph::ParameterError("the MPI ranks disagree about their parameters (rank " + std::to_string(q) + " has more)");
  }
}

// The first signal asks the running harness to checkpoint and stop; a second one ends the process.
extern "C" void on_interrupt_signal(int signal) {
  sph::request_interrupt();
  std::signal(signal, SIG_DFL);
}

// Catches Ctrl-C and SIGTERM for the lifetime of a run that can checkpoint.
class InterruptSignals {
 public:
  explicit InterruptSignals(bool active) : active_(active) {
    sph::clear_interrupt();
    if (!active_) return;
    previous_int_ = std::signal(SIGINT, on_interrupt_signal);
    previous_term_ = std::signal(SIGTERM, on_interrupt_signal);
  }
  ~InterruptSignals() {
    if (!active_) return;
    std::signal(SIGINT, previous_int_);
    std::signal(SIGTERM, previous_term_);
  }
  InterruptSignals(const InterruptSignals&) = delete;
  InterruptSignals& operator=(const InterruptSignals&) = delete;

 private:
  bool active_;
  void (*previous_int_)(int) = SIG_DFL;
  void (*previous_term_)(int) = SIG_DFL;
};

}  // namespace

SceneRunResult run_scene(const std::string& scene_name, const CommonOptions& options,
                         const std::vector<std::string>& extra) {
  SceneRunResult result;
  const SceneEntry* entry = find_scene(scene_name);
  if (!entry) throw sph::ParameterError("unknown scene '" + scene_name + "' (see 'cardiosph list')");

  // 1. Parameters: defaults, config file, --resolution/--end-time, --set, extra, then the chosen
  // presets on what those left alone; then checks.
  auto scene = entry->make();
  const bool resuming = !options.resume.empty();
  const bool interrupt_asked = !std::isnan(options.interrupt_at);
  const bool wants_checkpoints = resuming || options.checkpoint_interval > 0 || interrupt_asked;
  if (wants_checkpoints && !scene->checkpoints()) {
    std::string can;
    for (const auto& other : scene_registry())
      if (other.make()->checkpoints()) can += (can.empty() ? "" : ", ") + other.name;
    throw sph::ParameterError("scene '" + scene_name + "' does not save its whole state, so it cannot be checkpointed or resumed "
                              "(--checkpoint-interval, --interrupt-at, --resume); scenes that can: " + can);
  }
  const sph::Communicator& world = sph::Communicator::world();
  // A serial build started by mpirun would run the whole scene once per process into one folder.
  for (const char* variable : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* ranks = std::getenv(variable); ranks && std::atoi(ranks) > 1 && !sph::Communicator::built_with_mpi())
      throw sph::ParameterError(std::string("started on ") + ranks + " MPI ranks, but this build has no MPI (configure with "
                                "OpenMPI and Zoltan: libopenmpi-dev openmpi-bin libtrilinos-zoltan-dev)");
  if (world.size() > 1) {
    if (!scene->distributes()) {
      std::string can;
      for (const auto& other : scene_registry())
        if (other.make()->distributes()) can += (can.empty() ? "" : ", ") + other.name;
      throw sph::ParameterError("scene '" + scene_name + "' runs on one rank only, not on the " + std::to_string(world.size()) +
                                " ranks of this mpirun; scenes that run distributed: " + can);
    }
  }
  if (!(options.checkpoint_interval >= 0) || !std::isfinite(options.checkpoint_interval))
    throw sph::ParameterError("option '--checkpoint-interval' = " + exact(options.checkpoint_interval) + ": must be >= 0 (simulated time)");
  if (interrupt_asked && !(options.interrupt_at >= 0 && std::isfinite(options.interrupt_at)))
    throw sph::ParameterError("option '--interrupt-at' = " + exact(options.interrupt_at) + ": must be a simulated time >= 0");
  std::shared_ptr<sph::Checkpoint> checkpoint;
  fs::path resume_output;
  if (resuming) {
    if (!options.config.empty() || !options.assignments.empty() || !options.resolution.empty() || !options.end_time.empty() ||
        !extra.empty() || !options.output.empty())
      throw sph::ParameterError("--resume continues a run with its own parameters and folder; --config, --set, --resolution, "
                                "--end-time, --output and scene options cannot be given with it");
    // Each rank resumes from its own part (libsph/io/checkpoint.hpp), on the rank count that wrote them.
    if (const int written = sph::checkpoint_ranks(options.resume); fs::exists(options.resume / sph::checkpoint_file_name) &&
                                                                   written != world.size())
      throw sph::ParameterError("the checkpoint in '" + options.resume.string() + "' was written by " + std::to_string(written) +
                                " MPI rank" + (written == 1 ? "" : "s") + " and this run has " + std::to_string(world.size()) +
                                ": resume it on as many (" + (written == 1 ? std::string("without mpirun") : "mpirun -np " + std::to_string(written)) +
                                "); another rank count would need the particles distributed anew from the gathered state, "
                                "which --resume does not do");
    const fs::path file = options.resume / sph::checkpoint_file_of_rank(world.rank());
    checkpoint = std::make_shared<sph::Checkpoint>(sph::read_checkpoint(file));
    if (checkpoint->scene != scene_name)
      throw sph::ParameterError("checkpoint '" + file.string() + "' is of scene '" + checkpoint->scene + "', not '" + scene_name +
                                "' (resume it with 'cardiosph " + checkpoint->scene + " --resume " + options.resume.string() + "')");
    resume_output = options.resume.lexically_normal();
    if (resume_output.filename().empty()) resume_output = resume_output.parent_path();
    if (resume_output.extension() == ".partial") resume_output.replace_extension();
  }
  sph::Parameters parameters;
  scene->declare(parameters);
  if (checkpoint)
    for (const auto& a : saved_assignments(*checkpoint, options.resume / sph::checkpoint_file_name)) parameters.set_assignment(a, "checkpoint");
  if (!options.config.empty()) parameters.load_file(options.config);
  if (!options.resolution.empty()) parameters.set("resolution", options.resolution, "--resolution");
  if (!options.end_time.empty()) parameters.set("end_time", options.end_time, "--end-time");
  for (const auto& a : options.assignments) parameters.set_assignment(a, "--set");
  for (const auto& a : extra) parameters.set_assignment(a, "--sweep");
  parameters.apply_presets();
  parameters.check();
  scene->check();
  const fs::path output = resuming ? resume_output : options.output.empty() ? fs::path("output") / scene_name : options.output;
  check_ranks_agree(parameters, output, options.output_pieces);
  if (options.threads < 0) throw sph::ParameterError("option '--threads' = " + std::to_string(options.threads) + ": must be >= 0");
  if (options.check_only) return result;
  if (options.print_parameters_only) {
    std::cout << "parameters of " << scene_name << ":\n" << parameters.describe();
    return result;
  }

  if (!resuming) check_output_folder(output);
  result.output = output;
  if (!options.quiet) std::cout << "cardiosph " << scene_name << ", parameters:\n" << parameters.describe() << std::flush;

  // 2. Run into a staging folder (resuming: a copy of the interrupted run's folder).
  // Rank 0 alone touches the folders; the others only compute (libsph/io/run_harness.hpp).
  const fs::path staging = fs::path(output.string() + (resuming ? ".resume" : ".partial"));
  if (world.is_root()) {
    fs::remove_all(staging);
    if (resuming) {
      fs::copy(options.resume, staging, fs::copy_options::recursive);
      fs::remove(staging / "report.json");
    } else {
      fs::create_directories(staging);
    }
  }
  sph::ThreadLimit thread_limit(static_cast<std::size_t>(options.threads));
  sph::write_distributed_output_in_pieces(options.output_pieces);
  RunContext ctx{staging, options.quiet, {}};
  ctx.report.scene = scene_name;
  ctx.report.parameters = parameters.to_json();
  if (scene->checkpoints())
    ctx.checkpoint = {true, options.checkpoint_interval,
                      interrupt_asked ? options.interrupt_at : std::numeric_limits<double>::infinity(), checkpoint,
                      scene_name, ctx.report.parameters.dump()};
  InterruptSignals signals(scene->checkpoints());
  if (checkpoint && !options.quiet)
    std::cout << "resuming " << scene_name << " from its checkpoint at simulated time " << checkpoint->time << "\n" << std::flush;
  ctx.report.threads = sph::active_thread_count();
  ctx.report.ranks = static_cast<std::size_t>(world.size());
  const auto start = std::chrono::steady_clock::now();
  try {
    scene->run(ctx);
  } catch (const sph::RunInterrupted& interrupted) {
    ctx.report.status = "interrupted";
    ctx.report.message = "stopped on request at simulated time " + exact(interrupted.time()) + "; continue with '" +
                         (world.size() > 1 ? "mpirun -np " + std::to_string(world.size()) + " " : std::string()) + "cardiosph " +
                         scene_name + " --resume " + output.string() + "'";
    result.exit_code = exit_interrupted;
    std::cerr << "cardiosph " << scene_name << ": " << ctx.report.message << '\n';
  } catch (const sph::ParameterError&) {
    if (world.is_root()) fs::remove_all(staging);
    throw;
  } catch (const std::invalid_argument& error) {
    // Input the scene could only reject while building (e.g. a geometry): nothing is kept.
    if (world.is_root()) fs::remove_all(staging);
    throw sph::ParameterError(error.what());
  } catch (const std::exception& error) {
    ctx.report.status = "failed";
    ctx.report.message = error.what();
    result.exit_code = exit_run_failed;
    std::cerr << "cardiosph " << scene_name << ": run failed: " << error.what() << '\n';
  }
  ctx.report.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.report = ctx.report;
  if (!world.is_root()) return result;
  // A completed run leaves nothing to resume; a failed or interrupted one keeps its last checkpoint.
  if (result.exit_code == exit_ok)
    for (int rank = 0; rank < world.size(); ++rank) fs::remove(staging / sph::checkpoint_file_of_rank(rank));
  ctx.report.write(staging / "report.json");
  replace_folder(staging, output);
  if (resuming && fs::exists(options.resume) && !fs::equivalent(options.resume, output)) fs::remove_all(options.resume);
  result.report = ctx.report;
  return result;
}

}  // namespace cardiosph
