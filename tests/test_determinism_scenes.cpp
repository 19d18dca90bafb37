// Every scene family, run briefly at coarse resolution with 1 and with 2 threads, writes the same
// bytes: each .vtu state (every output field), each .csv time series and the results of
// report.json other than timings and memory. Families: diffusion, solid, cell model and tissue
// electrophysiology, electromechanics (with its geometry stage), geometry, fluid, fluid-structure,
// impact.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <sstream>

#include "apps/scenes/scene.hpp"
#include "libsph/core/parallel.hpp"
#include "libsph/io/parameters.hpp"
#include "run_scene_for_test.hpp"
#include "temporary_folder.hpp"

namespace {

namespace fs = std::filesystem;

struct Outputs {
  std::map<std::string, std::string> files;  ///< name -> bytes (.vtu, .csv)
  nlohmann::json results;
};


Outputs run(const std::string& scene_name, const std::vector<std::string>& assignments, std::size_t threads) {
  const auto* entry = cardiosph::find_scene(scene_name);
  EXPECT_NE(entry, nullptr) << scene_name;
  auto scene = entry->make();
  sph::Parameters parameters;
  test::set_parameters(*scene, parameters, assignments);
  const test::TemporaryFolder folder(scene_name + "_" + std::to_string(threads));
  sph::ThreadLimit limit(threads);
  EXPECT_EQ(sph::active_thread_count(), threads);
  cardiosph::RunContext ctx;
  ctx.output_dir = folder.path();
  ctx.quiet = true;
  scene->check();
  scene->run(ctx);
  Outputs r;
  for (const auto& file : fs::directory_iterator(folder.path())) {
    const auto extension = file.path().extension();
    if (extension == ".vtu" || extension == ".csv") r.files[file.path().filename().string()] = test::bytes_of(file.path());
  }
  r.results = test::physics_only(ctx.report.results.json());
  return r;
}

struct Case {
  std::string scene;
  std::vector<std::string> assignments;
};

class SceneDeterminism : public ::testing::TestWithParam<Case> {};

TEST_P(SceneDeterminism, OneAndTwoThreadsWriteTheSameBytes) {
  const auto& c = GetParam();
  const Outputs one = run(c.scene, c.assignments, 1), two = run(c.scene, c.assignments, 2);
  ASSERT_FALSE(one.files.empty()) << c.scene << " wrote no .vtu or .csv";
  std::size_t vtu = 0, bytes = 0;
  for (const auto& [name, content] : one.files) {
    const auto other = two.files.find(name);
    ASSERT_NE(other, two.files.end()) << name << " is missing with 2 threads";
    EXPECT_TRUE(content == other->second) << c.scene << ": " << name << " differs between 1 and 2 threads";
    vtu += name.ends_with(".vtu");
    bytes += content.size();
  }
  EXPECT_EQ(one.files.size(), two.files.size());
  EXPECT_GE(vtu, 1u) << c.scene << " wrote no particle state";
  // As text: a result that is not a number (NaN, written as null) equals itself there.
  EXPECT_EQ(one.results.dump(), two.results.dump()) << c.scene << ": the report's results differ";
  std::printf("[ measured ] %s: %zu files (%zu .vtu, %zu bytes) identical with 1 and 2 threads\n", c.scene.c_str(),
              one.files.size(), vtu, bytes);
}

// A fluid's rows list their neighbours by position and its energies are exact sums, so where its
// particles sit in memory changes nothing: the dam break re-sorted along the cells at every
// advection step and never re-sorted writes the same time series and results (its particle files
// list the particles in memory order, so they are not compared; the distributed runs compare them,
// tests/test_distributed_scenes.cpp).
TEST(SceneDeterminism, ReSortingAFluidInMemoryChangesNoResult) {
  const Outputs every = run("dambreak", {"resolution=20", "end_time=0.9", "sort_interval=1"}, 2);
  const Outputs never = run("dambreak", {"resolution=20", "end_time=0.9", "sort_interval=0"}, 2);
  std::size_t csv = 0;
  for (const auto& [name, content] : never.files) {
    if (!name.ends_with(".csv")) continue;
    const auto other = every.files.find(name);
    ASSERT_NE(other, every.files.end()) << name;
    EXPECT_TRUE(content == other->second) << name << " differs when the particles are re-sorted";
    ++csv;
  }
  EXPECT_GE(csv, 3u);
  EXPECT_EQ(every.results.dump(), never.results.dump());
  std::printf("[ measured ] dambreak re-sorted at each of %s advection steps and never: %zu time series and the results identical\n",
              every.results["advection_steps"].dump().c_str(), csv);
}

// Short runs: enough steps for every operator of the family to act (neighbour rebuilds, stimuli,
// contact, the fluid-structure coupling), each a few seconds.
INSTANTIATE_TEST_SUITE_P(
    Families, SceneDeterminism,
    ::testing::Values(Case{"diffusion-aniso", {"resolution=24", "end_time=0.5"}},
                      Case{"oscillating-beam", {"resolution=4", "end_time=0.6"}},
                      Case{"depolarization", {"end_time=2"}},
                      Case{"cable", {"pacing=train", "pacing_count=1", "end_time=30"}},
                      Case{"particles", {"dp=1.5", "relaxation_steps=20"}},
                      Case{"heart", {"preset=coarse", "end_time=3", "output_interval=1"}},
                      Case{"dambreak", {"resolution=20", "end_time=1"}},
                      Case{"hydrostatic-plate", {"end_time=0.02"}},
                      Case{"sod-shock-tube", {"resolution=100", "end_time=0.1"}},
                      Case{"rubber-rings", {"resolution=4", "end_time=6e-5"}},
                      Case{"taylor-bar", {"resolution=2", "end_time=1.5e-5"}},
                      Case{"evrard-collapse", {"particles=600", "end_time=0.3"}},
                      Case{"impact", {"resolution=5", "end_time=8e-6"}},
                      Case{"sedov-blast", {"resolution=40", "end_time=0.02"}}),
    [](const ::testing::TestParamInfo<Case>& param) {
      std::string name = param.param.scene;
      std::replace(name.begin(), name.end(), '-', '_');
      return name;
    });

}  // namespace
