// Distributed runs (libsph/core/distribution.hpp) write the bytes of a one-rank run: the diffusion
// scenes on 2, 3 and 4 MPI ranks the Niederer slab on 2 and the Aliev-Panfilov depolarization on 3, against the same scene without mpirun, every .vtu, .csv and .pvd
// file compared byte for byte and the report's results and errors compared as numbers. A scene
// that does not distribute is refused under mpirun with exit code 2 and nothing written.
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

void expect_same_as_one_rank(const std::string& scene_arguments, std::initializer_list<int> rank_counts) {
  const test::TemporaryFolder folder("distributed");
  const fs::path one = folder.path() / "one", err = folder.path() / "err.txt";
  ASSERT_EQ(run(0, scene_arguments + " --output " + one.string(), err), 0) << test::bytes_of(err);
  const auto reference = files_of(one);
  const auto reference_report = nlohmann::json::parse(test::bytes_of(one / "report.json"));
  ASSERT_GE(reference.size(), 3u);
  for (const int ranks : rank_counts) {
    const fs::path out = folder.path() / ("ranks" + std::to_string(ranks));
    ASSERT_EQ(run(ranks, scene_arguments + " --output " + out.string(), err), 0) << test::bytes_of(err);
    const auto files = files_of(out);
    EXPECT_EQ(files.size(), reference.size());
    std::size_t bytes = 0;
    for (const auto& [name, content] : reference) {
      const auto other = files.find(name);
      ASSERT_NE(other, files.end()) << name << " is missing on " << ranks << " ranks";
      EXPECT_TRUE(content == other->second) << name << " differs between 1 and " << ranks << " ranks";
      bytes += content.size();
    }
    const auto report = nlohmann::json::parse(test::bytes_of(out / "report.json"));
    EXPECT_EQ(report["ranks"], ranks);
    EXPECT_EQ(test::physics_only(report["results"]).dump(), test::physics_only(reference_report["results"]).dump());
    EXPECT_EQ(report["errors"].dump(), reference_report["errors"].dump());
    EXPECT_EQ(report["particles"].dump(), reference_report["particles"].dump());
    std::printf("[ measured ] %s on %d ranks: %zu files (%zu bytes) identical to one rank; errors %s\n",
                scene_arguments.c_str(), ranks, files.size(), bytes, report["errors"].dump().c_str());
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
