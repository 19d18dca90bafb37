// Distributed runs (libsph/core/distribution.hpp) write the bytes of a one-rank run: the diffusion
// scenes on 2, 3 and 4 MPI ranks, the Niederer slab on 2, the Aliev-Panfilov depolarization on 3,
// the myocardium cube (TLSPH) on 2 and 3, the dam break (a fluid migrating between ranks) on 2 and 3
// and the coarse heart (electromechanics, cavities, circulation, ECG) on 2 and 3, against the same scene without mpirun, every .vtu,
// .csv and .pvd file compared byte for byte and the report's results and errors compared as
// numbers; a heart interrupted on 2 ranks resumes from its ranks' checkpoints to the same bytes; a
// solid's numerical failure on 2 ranks names the particle of one rank. A scene that does
// not distribute, and ranks that disagree about their parameters, are refused under mpirun with
// exit code 2 and nothing written.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>

#include "run_scene_for_test.hpp"
#include "temporary_folder.hpp"

namespace {

namespace fs = std::filesystem;

#if defined(CARDIOSPH_MPIEXEC) && defined(CARDIOSPH_BINARY)

/// Runs the binary (under mpirun with `ranks` > 0, directly with 0); returns the exit code, with
/// stderr in `err`.
int run(int ranks, const std::string& arguments, const fs::path& err) {
  std::string command;
  if (ranks > 0)
    command = std::string(CARDIOSPH_MPIEXEC) + " --allow-run-as-root --oversubscribe -np " + std::to_string(ranks) + " ";
  command += std::string(CARDIOSPH_BINARY) + " " + arguments + " --quiet --threads 1 > /dev/null 2> " + err.string();
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::map<std::string, std::string> files_of(const fs::path& folder) {
  std::map<std::string, std::string> files;
  for (const auto& f : fs::directory_iterator(folder)) {
    const auto extension = f.path().extension();
    if (extension == ".vtu" || extension == ".csv" || extension == ".pvd") files[f.path().filename().string()] = test::bytes_of(f.path());
  }
  return files;
}

/// Every .vtu, .csv and .pvd of the one-rank folder is in `other`, byte for byte, and no more;
/// returns the bytes compared.
std::size_t expect_same_files(const fs::path& one, const fs::path& other, int ranks) {
  const auto reference = files_of(one), files = files_of(other);
  EXPECT_GE(reference.size(), 2u);
  EXPECT_EQ(files.size(), reference.size());
  std::size_t bytes = 0;
  for (const auto& [name, content] : reference) {
    const auto found = files.find(name);
    if (found == files.end()) {
      ADD_FAILURE() << name << " is missing on " << ranks << " ranks";
      continue;
    }
    EXPECT_TRUE(content == found->second) << name << " differs between 1 and " << ranks << " ranks";
    bytes += content.size();
  }
  return bytes;
}

void expect_same_as_one_rank(const std::string& scene_arguments, std::initializer_list<int> rank_counts) {
  const test::TemporaryFolder folder("distributed");
  const fs::path one = folder.path() / "one", err = folder.path() / "err.txt";
  ASSERT_EQ(run(0, scene_arguments + " --output " + one.string(), err), 0) << test::bytes_of(err);
  const std::size_t n_files = files_of(one).size();
  const auto reference_report = nlohmann::json::parse(test::bytes_of(one / "report.json"));
  ASSERT_GE(n_files, 3u);
  for (const int ranks : rank_counts) {
    const fs::path out = folder.path() / ("ranks" + std::to_string(ranks));
    ASSERT_EQ(run(ranks, scene_arguments + " --output " + out.string(), err), 0) << test::bytes_of(err);
    const std::size_t bytes = expect_same_files(one, out, ranks);
    const auto report = nlohmann::json::parse(test::bytes_of(out / "report.json"));
    EXPECT_EQ(report["ranks"], ranks);
    EXPECT_EQ(test::physics_only(report["results"]).dump(), test::physics_only(reference_report["results"]).dump());
    // (a report without errors, e.g. the heart without a reference run, has no "errors" key)
    auto errors_of = [](const nlohmann::json& r) { return r.contains("errors") ? r.at("errors").dump() : std::string("none"); };
    EXPECT_EQ(errors_of(report), errors_of(reference_report));
    EXPECT_EQ(report["particles"].dump(), reference_report["particles"].dump());
    std::printf("[ measured ] %s on %d ranks: %zu files (%zu bytes) identical to one rank; errors %s\n",
                scene_arguments.c_str(), ranks, n_files, bytes, errors_of(report).c_str());
  }
}

TEST(DistributedRuns, DiffusionOnTwoAndThreeRanksWritesTheBytesOfOneRank) {
  expect_same_as_one_rank("diffusion --set resolution=150", {2, 3});
}

TEST(DistributedRuns, AnisotropicDiffusionOnFourRanksWritesTheBytesOfOneRank) {
  expect_same_as_one_rank("diffusion-aniso --set resolution=60", {4});
}

TEST(DistributedRuns, NiedererSlabOnTwoRanksWritesTheBytesOfOneRank) {
  // Monodomain: ten Tusscher-Panfilov cells (owned particles, potentials of the ghosts from their
  // owners after each reaction half-step) and the distributed diffusion; dx = 0.5 mm, 3,360 particles.
  expect_same_as_one_rank("niederer-slab --set resolution=6 --set apd_percent=0", {2});
}

TEST(DistributedRuns, DepolarizationOnThreeRanksWritesTheBytesOfOneRank) {
  // Aliev-Panfilov (dimensionless, 2D), the SPHinXsys depolarization case at 40 x 40 particles.
  expect_same_as_one_rank("depolarization --set resolution=40", {3});
}

TEST(DistributedRuns, MyocardiumCubeOnTwoRanksWritesTheBytesOfOneRank) {
  // TLSPH with active stress (Holzapfel-Ogden, prescribed tension, sliding holder): ghosts keep their
  // reference neighbours; positions and F, P B0 exchanged each step; 1,200 particles.
  expect_same_as_one_rank("myocardium-cube --set resolution=10 --set end_time=0.6 --set ramp_time=0.3 --set output_interval=0.3", {2});
}

TEST(DistributedRuns, MyocardiumCubeWithPairViscosityOnThreeRanksWritesTheBytesOfOneRank) {
  // The SPHinXsys settings: pair viscosity (the ghosts' start velocities exchanged too), no hourglass
  // control, the small-strain time step.
  expect_same_as_one_rank("myocardium-cube --set preset=sphinxsys --set resolution=10 --set end_time=0.3 --set ramp_time=0.3", {3});
}

TEST(DistributedRuns, DamBreakOnTwoAndThreeRanksWritesTheBytesOfOneRank) {
  // A weakly-compressible fluid with a free surface: the particles migrate between the ranks'
  // regions at every advection step, the regions are cut anew every 20 steps, the ghosts' velocity
  // and density rate are exchanged at every acoustic step; the wall probe and the snapshots read the
  // gathered body. 800 water particles, 1.5 time units. (sort_interval = 0: a one-rank run then
  // keeps its particles in the global-id order in which a distributed body is gathered and written;
  // re-sorting changes no result, tests/test_determinism_scenes.cpp.)
  expect_same_as_one_rank("dambreak --set resolution=20 --set end_time=1.5 --set output_interval=0.5 --set sort_interval=0", {2, 3});
}

TEST(DistributedRuns, DamBreakIn3DOnTwoRanksWritesTheBytesOfOneRank) {
  // The same fluid in 3D: 512 water particles, 10,200 wall particles held whole on every rank.
  expect_same_as_one_rank("dambreak-3d --set resolution=8 --set end_time=0.5 --set output_interval=0.25 --set sort_interval=0", {2});
}

TEST(DistributedRuns, CoarseHeartOnTwoAndThreeRanksWritesTheBytesOfOneRank) {
  // Every heart feature: ten Tusscher-Panfilov cells (quiescent blocks kept whole on a rank), Land
  // tension, TLSPH with pericardial and base springs, both cavities (their surfaces gathered by
  // every rank) coupled to the closed-loop circulation, the 12-lead pseudo-ECG, observers, the
  // activation map; 3,788 particles at dp 3 mm, geometry built by every rank (cache = none).
  expect_same_as_one_rank("heart --preset coarse --set cache=none --set preload_time=5 --set pressure_ramp_time=5 "
                          "--set output_interval=10 --set sample_interval=1 --end-time 30",
                          {2, 3});
}

TEST(DistributedRuns, AHeartInterruptedOnTwoRanksResumesToTheBytesOfAnUninterruptedRun) {
  // Each rank writes its part of the state (checkpoint.bin, checkpoint.rank1.bin) and resumes from
  // it; another rank count is refused with the count that wrote the checkpoint.
  const test::TemporaryFolder folder("distributed");
  const fs::path whole = folder.path() / "whole", cut = folder.path() / "cut", err = folder.path() / "err.txt";
  const std::string heart = "heart --preset coarse --set cache=none --set preload_time=5 --set pressure_ramp_time=5 "
                            "--set output_interval=10 --set sample_interval=1 --end-time 30";
  ASSERT_EQ(run(2, heart + " --output " + whole.string(), err), 0) << test::bytes_of(err);
  ASSERT_EQ(run(2, heart + " --interrupt-at 15 --output " + cut.string(), err), 3) << test::bytes_of(err);
  EXPECT_TRUE(fs::exists(cut / "checkpoint.bin"));
  EXPECT_TRUE(fs::exists(cut / "checkpoint.rank1.bin"));
  EXPECT_EQ(run(3, "heart --resume " + cut.string(), err), 2);
  const std::string message = test::bytes_of(err);
  EXPECT_NE(message.find("was written by 2 MPI ranks and this run has 3: resume it on as many (mpirun -np 2)"), std::string::npos)
      << message;
  ASSERT_EQ(run(2, "heart --resume " + cut.string(), err), 0) << test::bytes_of(err);
  const std::size_t bytes = expect_same_files(whole, cut, 2);
  EXPECT_FALSE(fs::exists(cut / "checkpoint.bin"));
  EXPECT_FALSE(fs::exists(cut / "checkpoint.rank1.bin"));
  std::printf("[ measured ] the heart on 2 ranks, interrupted at 15 ms and resumed: %zu bytes identical to the uninterrupted run\n", bytes);
}

TEST(DistributedRuns, ASolidFailureNamesTheParticleOfOneRankAndWritesItsLastGoodState) {
  // A time step far above the stable one inverts the cube: every rank stops at the same step, the
  // message names the particle (global id) and time of a one-rank run, and the last good state
  // written is the same.
  const test::TemporaryFolder folder("distributed");
  const std::string arguments = "myocardium-cube --set resolution=10 --set end_time=0.6 --set ramp_time=0.3 --set fixed_time_step=0.01";
  const fs::path one = folder.path() / "one", two = folder.path() / "two";
  const fs::path err_one = folder.path() / "err1.txt", err_two = folder.path() / "err2.txt";
  ASSERT_EQ(run(0, arguments + " --output " + one.string(), err_one), 1) << test::bytes_of(err_one);
  ASSERT_EQ(run(2, arguments + " --output " + two.string(), err_two), 1) << test::bytes_of(err_two);
  auto failure_line = [](const std::string& text) {
    const auto at = text.find("numerical failure");
    return at == std::string::npos ? std::string() : text.substr(at, text.find('\n', at) - at);
  };
  const std::string message = failure_line(test::bytes_of(err_one));
  ASSERT_NE(message.find("particle"), std::string::npos) << test::bytes_of(err_one);
  EXPECT_EQ(failure_line(test::bytes_of(err_two)), message);
  expect_same_files(one, two, 2);
  std::printf("[ measured ] on 1 and 2 ranks: %s\n", message.c_str());
}

TEST(DistributedRuns, OutputInPiecesListsEveryRanksParticlesInOnePvtu) {
  // --output-pieces: every rank writes its owned particles (VTK's parallel XML writer); the .pvd
  // lists one .pvtu per frame, which lists one piece per rank; the pieces hold every particle once
  // and the time series are those of one rank.
  const test::TemporaryFolder folder("distributed");
  const std::string arguments = "myocardium-cube --set resolution=10 --set end_time=0.6 --set ramp_time=0.3 --set output_interval=0.3";
  const fs::path one = folder.path() / "one", out = folder.path() / "pieces", err = folder.path() / "err.txt";
  ASSERT_EQ(run(0, arguments + " --output " + one.string(), err), 0) << test::bytes_of(err);
  ASSERT_EQ(run(2, arguments + " --output-pieces --output " + out.string(), err), 0) << test::bytes_of(err);
  const std::string pvd = test::bytes_of(out / "cube.pvd");
  EXPECT_NE(pvd.find("file=\"cube_00002.pvtu\""), std::string::npos) << pvd;
  const auto count = [](const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
  };
  for (const char* frame : {"cube_00000", "cube_00002"}) {
    const std::string pvtu = test::bytes_of(out / (std::string(frame) + ".pvtu"));
    EXPECT_EQ(count(pvtu, "<Piece Source="), 2u) << pvtu;
    EXPECT_NE(pvtu.find("Name=\"global_id\""), std::string::npos);
    std::size_t points = 0;
    for (int rank = 0; rank < 2; ++rank) {
      const std::string piece = test::bytes_of(out / frame / (std::string(frame) + "_" + std::to_string(rank) + ".vtu"));
      const auto at = piece.find("NumberOfPoints=\"");
      ASSERT_NE(at, std::string::npos);
      points += std::stoul(piece.substr(at + 16));
    }
    EXPECT_EQ(points, 1200u) << frame;  // 10 x 10 x 12 particles (cube and holder)
  }
  for (const char* series : {"observers.csv", "cube_energy.csv"})
    EXPECT_TRUE(test::bytes_of(one / series) == test::bytes_of(out / series)) << series;
  std::printf("[ measured ] 2 ranks in pieces: 3 frames of 2 pieces, 1,200 particles each; time series identical to one rank\n");
}

TEST(DistributedRuns, RanksThatDisagreeAboutAParameterStopWithItsName) {
  // Two command lines under one mpirun (MPMD): the ranks compare their parameters before anything
  // is written; a rank that alone finds its input bad ends the run with its own message.
  const test::TemporaryFolder folder("distributed");
  const fs::path out = folder.path() / "disagree", err = folder.path() / "err.txt";
  auto mixed = [&](const std::string& first, const std::string& second) {
    const std::string binary = CARDIOSPH_BINARY, common = " --quiet --threads 1 --output " + out.string();
    const std::string command = std::string(CARDIOSPH_MPIEXEC) + " --allow-run-as-root --oversubscribe -np 1 " + binary + " " + first +
                                common + " : -np 1 " + binary + " " + second + common + " > /dev/null 2> " + err.string();
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  EXPECT_EQ(mixed("diffusion --set resolution=40", "diffusion --set resolution=50"), 2);
  std::string message = test::bytes_of(err);
  EXPECT_NE(message.find("the MPI ranks disagree about parameter 'resolution': 40 on rank 0, 50 on rank 1"), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(out.string() + ".partial"));
  EXPECT_EQ(mixed("diffusion --set resolution=40", "diffusion --set resolution=41"), 2);
  message = test::bytes_of(err);
  EXPECT_NE(message.find("(rank 1) cardiosph: parameter 'box_height' must be a whole number"), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(out.string() + ".partial"));
}

TEST(DistributedRuns, AFluidOnSeveralRanksRefusesCheckpoints) {
  // Its particles migrate between the ranks, a layout that a resumed run could not restore.
  const test::TemporaryFolder folder("distributed");
  const fs::path out = folder.path() / "dambreak", err = folder.path() / "err.txt";
  EXPECT_EQ(run(2, "dambreak --set resolution=20 --end-time 0.5 --checkpoint-interval 0.1 --output " + out.string(), err), 2);
  const std::string message = test::bytes_of(err);
  EXPECT_NE(message.find("particles migrate between the ranks (fluids); run on one rank to checkpoint"), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(out.string() + ".partial"));
}

TEST(DistributedRuns, ASceneThatDoesNotDistributeIsRefused) {
  const test::TemporaryFolder folder("distributed");
  const fs::path out = folder.path() / "cantilever", err = folder.path() / "err.txt";
  EXPECT_EQ(run(2, "cantilever --output " + out.string(), err), 2);
  const std::string message = test::bytes_of(err);
  EXPECT_NE(message.find("runs on one rank only"), std::string::npos) << message;
  EXPECT_NE(message.find("diffusion"), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(out.string() + ".partial"));
}

#else

TEST(DistributedRuns, NeedAnMpiBuild) {
  GTEST_SKIP() << "this build has no MPI (configure with OpenMPI and Zoltan: libopenmpi-dev openmpi-bin libtrilinos-zoltan-dev)";
}

#endif

}  // namespace
