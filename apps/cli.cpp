#include "libsph/core/communicator.hpp"
#include "apps/cli.hpp"

#include <iostream>
#include <map>

#include <CLI/CLI.hpp>

#include "apps/mesh_command.hpp"
#include "apps/run_scene.hpp"
#include "apps/study.hpp"

namespace cardiosph {
namespace {

void add_common_options(CLI::App& command, CommonOptions& o) {
  command.add_option("--output", o.output, "output folder (default: output/<scene>)");
  command.add_option("--config", o.config, "parameter file (.toml or .json)");
  command.add_option("--set", o.assignments, "set a parameter: --set key=value (repeatable)")->allow_extra_args(false);
  command.add_option("--resolution", o.resolution, "the scene's resolution (same as --set resolution=...)");
  command.add_option("--end-time", o.end_time, "simulated end time (same as --set end_time=...)");
  command.add_option("--threads", o.threads, "worker threads (0: all cores)");
  command.add_flag("--quiet", o.quiet, "no parameter listing and no progress");
  command.add_flag("--output-pieces", o.output_pieces,
                   "under mpirun: every rank writes its particles as a piece of each frame (.pvtu) instead of rank 0 "
                   "gathering and writing the whole body");
  command.add_flag("--parameters", o.print_parameters_only, "list the parameters with their values, units and ranges, and stop");
}

}  // namespace

int run_cli(int argc, const char* const* argv) {
  CLI::App app{"cardiosph: smoothed particle hydrodynamics for cardiac electromechanics"};
  app.name("cardiosph");
  app.require_subcommand(1);

  auto* list = app.add_subcommand("list", "list the scenes");
  CommonOptions options;
  std::vector<std::pair<std::string, CLI::App*>> scene_commands;
  // Scene parameters that also have a positional argument or an option of their own.
  std::map<std::string, std::string> shortcut_values;
  for (const auto& scene : scene_registry()) {
    auto* command = app.add_subcommand(scene.name, scene.summary);
    add_common_options(*command, options);
    for (const auto& key : scene.positional)
      command->add_option(key, shortcut_values[scene.name + "/" + key], "same as --set " + key + "=...");
    for (const auto& key : scene.shortcuts)
      command->add_option("--" + key, shortcut_values[scene.name + "/" + key], "same as --set " + key + "=...");
    command->add_option("--checkpoint-interval", options.checkpoint_interval,
                        "write <output>/checkpoint.bin every this much simulated time (scenes that can checkpoint: see docs/reliability.md)");
    command->add_option("--interrupt-at", options.interrupt_at,
                        "stop with a checkpoint at the first step at or after this simulated time, as Ctrl-C or SIGTERM do");
    command->add_option("--resume", options.resume,
                        "continue the interrupted run in folder DIR from its checkpoint.bin, with its parameters")
        ->option_text("DIR");
    scene_commands.emplace_back(scene.name, command);
  }
  std::string mesh_kind;
  std::filesystem::path mesh_out = "meshes";
  double mesh_edge = 0;
  auto* mesh = app.add_subcommand("mesh", "write an analytic heart mesh (lv-ellipsoid, biventricular) as STL/OBJ files");
  mesh->add_option("kind", mesh_kind, "lv-ellipsoid or biventricular")->required();
  mesh->add_option("--out", mesh_out, "output folder (default: meshes)");
  mesh->add_option("--edge", mesh_edge, "target triangle edge length in mm (default 0.5 for the LV, 1.5 for the biventricular heart)");
  mesh->add_flag("--quiet", options.quiet, "print nothing");
  std::string study_scene, sweep, compare;
  auto* study = app.add_subcommand("study", "run a scene at several settings; error against wall time");
  study->add_option("scene", study_scene, "scene to study")->required();
  study->add_option("--sweep", sweep, "key=value1,value2,... (e.g. resolution=25,50,100)")->required();
  study->add_option("--compare", compare,
                    "key=a,b,...: the sweep once for each value, one curve each (e.g. deformation_gradient=corrected,quadratic)");
  add_common_options(*study, options);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    const int code = app.exit(error);
    return code == 0 ? exit_ok : exit_bad_input;
  }

  try {
    if (list->parsed()) {
      std::size_t width = 0;
      for (const auto& s : scene_registry()) width = std::max(width, s.name.size());
      for (const auto& s : scene_registry())
        std::cout << "  " << s.name << std::string(width + 2 - s.name.size(), ' ') << s.summary << '\n';
      return exit_ok;
    }
    if ((study->parsed() || mesh->parsed()) && sph::Communicator::world().size() > 1)
      throw sph::ParameterError("'study' and 'mesh' run on one rank; start them without mpirun");
    if (study->parsed()) return run_study(study_scene, sweep, compare, options);
    if (mesh->parsed()) return run_mesh_command(mesh_kind, mesh_out, mesh_edge, options.quiet);
    for (const auto& [name, command] : scene_commands) {
      if (!command->parsed()) continue;
      for (const auto& [key, value] : shortcut_values)
        if (!value.empty() && key.rfind(name + "/", 0) == 0)
          options.assignments.insert(options.assignments.begin(), key.substr(name.size() + 1) + "=" + value);
      const auto result = run_scene(name, options);
      if (options.print_parameters_only) return exit_ok;
      if (result.exit_code == exit_ok && !options.quiet) {
        std::cout << "\n" << name << " " << result.report.status << " in " << result.report.wall_time_s << " s, "
                  << result.report.steps << " steps\n";
        for (auto it = result.report.results.json().begin(); it != result.report.results.json().end(); ++it)
          std::cout << "  results." << it.key() << " = " << it.value() << '\n';
        for (auto it = result.report.errors.json().begin(); it != result.report.errors.json().end(); ++it)
          std::cout << "  errors." << it.key() << " = " << it.value() << '\n';
      }
      if (result.exit_code == exit_interrupted)
        std::cout << "interrupted; continue with: "
                  << (sph::Communicator::world().size() > 1 ? "mpirun -np " + std::to_string(sph::Communicator::world().size()) + " " : "")
                  << "cardiosph " << name << " --resume " << result.output.string() << '\n';
      std::cout << "results in " << std::filesystem::absolute(result.output).string() << " (report.json";
      if (std::filesystem::is_directory(result.output))
        for (const auto& file : std::filesystem::directory_iterator(result.output)) {
          const auto extension = file.path().extension();
          if (extension == ".csv" || extension == ".pvd" || extension == ".png") std::cout << ", " << file.path().filename().string();
        }
      std::cout << "; open the .pvd files in ParaView)\n";
      return result.exit_code;
    }
  } catch (const sph::ParameterError& error) {
    std::cerr << "cardiosph: " << error.what() << '\n';
    return exit_bad_input;
  } catch (const std::exception& error) {
    std::cerr << "cardiosph: " << error.what() << '\n';
    return exit_run_failed;
  }
  return exit_bad_input;
}

}  // namespace cardiosph
