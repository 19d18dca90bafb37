// Checkpoint and restart of the heart (geometry, mechanics, monodomain, Land tension, closed-loop
// circulation, pseudo-ECG): a run interrupted at t (by --interrupt-at or by SIGTERM) and resumed
// writes, byte for byte, every file of the uninterrupted run and the same physics in report.json;
// periodic checkpoints do not change a run; a checkpoint of another scene, of another format
// version, truncated or damaged is refused with exit code 2 and the interrupted run left untouched.
// Every other scene that checkpoints is interrupted and resumed the same way (SceneCheckpoint), and
// no scene may claim checkpoints without such a test.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <algorithm>
#include <map>
#include <set>
#include <thread>

#include "apps/scenes/scene.hpp"
#include "cli_for_test.hpp"
#include "libsph/io/checkpoint.hpp"
#include "run_scene_for_test.hpp"
#include "temporary_folder.hpp"

namespace {

namespace fs = std::filesystem;

// A short heart: the circulation starts at 5 ms, the stimulus at 5 ms, outputs every 4 ms.
std::vector<std::string> heart_arguments(const fs::path& cache, const fs::path& output) {
  return {"heart", "--preset", "coarse", "--set", "preload_time=5", "--set", "pressure_ramp_time=5", "--set", "output_interval=4",
          "--set", "sample_interval=1", "--set", "cache=" + cache.string(), "--end-time", "20", "--quiet", "--threads", "2",
          "--output", output.string()};
}

test::CliRun run(std::vector<std::string> args) { return test::run_cli(std::move(args)); }

// Every file of a run folder but report.json and the checkpoint, by name.
std::map<std::string, std::string> files_of(const fs::path& folder) {
  std::map<std::string, std::string> files;
  for (const auto& f : fs::directory_iterator(folder)) {
    const auto name = f.path().filename().string();
    if (name != "report.json" && name != sph::checkpoint_file_name) files[name] = test::bytes_of(f.path());
  }
  return files;
}
std::map<std::string, std::string> all_files_of(const fs::path& folder) {
  std::map<std::string, std::string> files;
  for (const auto& f : fs::directory_iterator(folder)) files[f.path().filename().string()] = test::bytes_of(f.path());
  return files;
}

nlohmann::json report_of(const fs::path& folder) { return nlohmann::json::parse(test::bytes_of(folder / "report.json")); }

void expect_same_run(const fs::path& expected, const fs::path& actual) {
  const auto a = files_of(expected), b = files_of(actual);
  ASSERT_EQ(a.size(), b.size());
  std::size_t bytes = 0;
  for (const auto& [name, content] : a) {
    ASSERT_TRUE(b.count(name)) << name << " is missing";
    EXPECT_TRUE(content == b.at(name)) << name << " differs";
    bytes += content.size();
  }
  const auto ra = report_of(expected), rb = report_of(actual);
  EXPECT_EQ(test::physics_only(ra["results"]), test::physics_only(rb["results"]));
  EXPECT_EQ(ra["steps"], rb["steps"]);
  EXPECT_EQ(ra["simulated_time"], rb["simulated_time"]);
  std::cout << "  " << a.size() << " files, " << bytes << " bytes, identical\n";
}

class HeartCheckpoint : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    folder_ = new test::TemporaryFolder("heart_checkpoint");
    const auto r = run(heart_arguments(cache(), full()));
    ASSERT_EQ(r.code, 0) << r.err;
  }
  static void TearDownTestSuite() {
    delete folder_;
    folder_ = nullptr;
  }
  static fs::path cache() { return folder_->path() / "cache"; }
  static fs::path full() { return folder_->path() / "full"; }
  fs::path path(const std::string& name) const { return folder_->path() / name; }
  // An interrupted run at 11 ms, for the refusals.
  fs::path interrupted(const std::string& name) {
    auto args = heart_arguments(cache(), path(name));
    args.insert(args.end(), {"--interrupt-at", "11"});
    const auto r = run(args);
    EXPECT_EQ(r.code, 3) << r.err;
    return path(name);
  }

  static test::TemporaryFolder* folder_;
};
test::TemporaryFolder* HeartCheckpoint::folder_ = nullptr;

TEST_F(HeartCheckpoint, InterruptedAndResumedRunIsTheUninterruptedOne) {
  const auto out = interrupted("part");
  const auto report = report_of(out);
  EXPECT_EQ(report["status"], "interrupted");
  EXPECT_NE(report["message"].get<std::string>().find("--resume"), std::string::npos) << report["message"];
  ASSERT_TRUE(fs::exists(out / sph::checkpoint_file_name));
  const auto checkpoint = sph::read_checkpoint(out / sph::checkpoint_file_name);
  std::cout << "  checkpoint at t = " << checkpoint.time << " ms: " << checkpoint.records.size() << " records, "
            << fs::file_size(out / sph::checkpoint_file_name) << " bytes\n";
  EXPECT_GE(checkpoint.time, 11.0);
  EXPECT_LT(checkpoint.time, 12.0);

  const auto r = run({"heart", "--resume", out.string(), "--quiet", "--threads", "2"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(report_of(out)["status"], "completed");
  EXPECT_FALSE(fs::exists(out / sph::checkpoint_file_name)) << "a completed run keeps no checkpoint";
  EXPECT_FALSE(fs::exists(out.string() + ".resume"));
  expect_same_run(full(), out);
}

TEST_F(HeartCheckpoint, PeriodicCheckpointsDoNotChangeTheRun) {
  auto args = heart_arguments(cache(), path("periodic"));
  args.insert(args.end(), {"--checkpoint-interval", "4"});
  const auto r = run(args);
  ASSERT_EQ(r.code, 0) << r.err;
  expect_same_run(full(), path("periodic"));
}

#ifdef CARDIOSPH_BINARY
TEST_F(HeartCheckpoint, SigtermWritesACheckpointThatResumes) {
  const fs::path out = path("signalled");
  const auto args = heart_arguments(cache(), out);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    std::vector<const char*> argv{CARDIOSPH_BINARY};
    for (const auto& a : args) argv.push_back(a.c_str());
    argv.push_back(nullptr);
    const int devnull = ::open("/dev/null", O_WRONLY);
    ::dup2(devnull, 1);
    ::dup2(devnull, 2);
    ::execv(CARDIOSPH_BINARY, const_cast<char* const*>(argv.data()));
    ::_exit(127);
  }
  // Signal once the time loop runs (the third state is written at 8 ms, after the circulation has started).
  const fs::path marker = fs::path(out.string() + ".partial") / "heart_00002.vtu";
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (!fs::exists(marker) && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ASSERT_TRUE(fs::exists(marker));
  ::kill(child, SIGTERM);
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_EQ(WEXITSTATUS(status), 3) << "the run ended before the signal, or did not stop on it";
  const auto time = sph::read_checkpoint(out / sph::checkpoint_file_name).time;
  std::cout << "  SIGTERM: checkpoint at t = " << time << " ms\n";
  const auto r = run({"heart", "--resume", out.string(), "--quiet"});
  ASSERT_EQ(r.code, 0) << r.err;
  expect_same_run(full(), out);
}
#endif

TEST_F(HeartCheckpoint, ForeignTruncatedOrDamagedCheckpointsAreRefused) {
  const auto out = interrupted("refused");
  const fs::path file = out / sph::checkpoint_file_name;
  const std::string good = test::bytes_of(file);
  auto expect_refused = [&](const std::string& bytes, const std::string& message, const std::string& scene = "heart") {
    std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
    const auto before = all_files_of(out);
    const auto r = run({scene, "--resume", out.string(), "--quiet"});
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    EXPECT_TRUE(all_files_of(out) == before) << "the interrupted run was changed";
    EXPECT_FALSE(fs::exists(out.string() + ".resume"));
  };
  expect_refused(good.substr(0, good.size() / 2), "is truncated");
  std::string damaged = good;
  damaged[good.size() / 2] ^= 0x10;
  expect_refused(damaged, "hash does not match");
  std::string version = good;
  const std::uint32_t next = sph::checkpoint_format_version + 1;
  std::memcpy(version.data() + 21, &next, sizeof(next));
  expect_refused(version, "has format version");
  auto foreign = sph::parse_checkpoint(good, "good");
  foreign.scene = "land-lv";
  expect_refused(sph::serialise_checkpoint(foreign), "is of scene 'land-lv', not 'heart'");
  // A scene that cannot checkpoint, and parameters given with --resume.
  expect_refused(good, "cannot be checkpointed or resumed", "homogeneous-deformation");
  std::ofstream(file, std::ios::binary | std::ios::trunc) << good;
  const auto r = run({"heart", "--resume", out.string(), "--set", "dp=2"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("cannot be given with it"), std::string::npos) << r.err;
  // A checkpoint whose records do not fit the run (a record removed): refused, folder untouched.
  auto short_of_a_record = sph::parse_checkpoint(good, "good");
  short_of_a_record.records.erase(short_of_a_record.records.begin());
  expect_refused(sph::serialise_checkpoint(short_of_a_record), "does not fit this run");
}


// The other scenes that checkpoint: each run briefly, interrupted part-way (after at least one
// output state and, with sort_interval, before a re-sort that the resumed run must place at the
// same step), resumed, and compared with the uninterrupted run file by file.
struct ResumeCase {
  std::string scene;
  std::vector<std::string> assignments;
  std::string interrupt_at;
};

void PrintTo(const ResumeCase& c, std::ostream* os) { *os << c.scene; }

class SceneCheckpoint : public ::testing::TestWithParam<ResumeCase> {};

TEST_P(SceneCheckpoint, InterruptedAndResumedRunIsTheUninterruptedOne) {
  const auto& c = GetParam();
  const test::TemporaryFolder folder(c.scene + "_checkpoint");
  auto arguments = [&](const fs::path& output) {
    std::vector<std::string> args{c.scene, "--quiet", "--threads", "2", "--output", output.string()};
    for (const auto& a : c.assignments) args.insert(args.end(), {"--set", a});
    return args;
  };
  const auto full = folder.path() / "full", part = folder.path() / "part";
  const auto r_full = run(arguments(full));
  ASSERT_EQ(r_full.code, 0) << r_full.err;
  auto interrupted = arguments(part);
  interrupted.insert(interrupted.end(), {"--interrupt-at", c.interrupt_at});
  const auto r_part = run(interrupted);
  ASSERT_EQ(r_part.code, 3) << "not interrupted: " << r_part.err;
  const auto checkpoint = sph::read_checkpoint(part / sph::checkpoint_file_name);
  EXPECT_LT(checkpoint.time, report_of(full)["simulated_time"].get<double>());
  std::cout << "  " << c.scene << ": checkpoint at t = " << checkpoint.time << ", " << checkpoint.records.size() << " records, "
            << fs::file_size(part / sph::checkpoint_file_name) << " bytes\n";
  const auto r_resumed = run({c.scene, "--resume", part.string(), "--quiet", "--threads", "2"});
  ASSERT_EQ(r_resumed.code, 0) << r_resumed.err;
  expect_same_run(full, part);
}

const std::vector<ResumeCase>& resume_cases() {
  static const std::vector<ResumeCase> cases{
      ResumeCase{"diffusion", {"resolution=20", "end_time=0.5", "output_interval=0.1"}, "0.2"},
      ResumeCase{"diffusion-aniso", {"resolution=24", "end_time=0.5", "output_interval=0.1"}, "0.2"},
      ResumeCase{"dambreak", {"resolution=20", "end_time=1", "output_interval=0.25"}, "0.3"},
      ResumeCase{"dambreak-3d", {"resolution=8", "end_time=0.5", "output_interval=0.1", "sort_interval=10"}, "0.2"},
      ResumeCase{"hydrostatic-tank", {"resolution=10", "end_time=1", "output_interval=0.25", "sort_interval=10"}, "0.4"},
      ResumeCase{"lid-driven-cavity", {"resolution=20", "end_time=0.5", "output_interval=0.1", "sort_interval=10"}, "0.2"},
      ResumeCase{"poiseuille", {"resolution=10", "end_time=1", "output_interval=0.25", "sort_interval=10"}, "0.4"},
      ResumeCase{"taylor-green", {"resolution=20", "end_time=0.1", "output_interval=0.02", "sort_interval=5"}, "0.05"},
      ResumeCase{"cantilever", {"resolution=2", "end_time=0.05", "output_interval=0.01"}, "0.02"},
      ResumeCase{"twisting-column", {"resolution=3", "end_time=0.05", "output_interval=0.01"}, "0.02"},
      ResumeCase{"oscillating-beam", {"resolution=4", "end_time=0.6", "output_interval=0.1"}, "0.25"},
      // Quasi-static: interrupted between residual checks, before it converges (at about 67 ms).
      ResumeCase{"land-beam", {"resolution=3", "residual_check_interval=20", "residual_tolerance=0.1", "output_interval=20"}, "30"},
      ResumeCase{"myocardium-cube", {"resolution=4", "end_time=1", "output_interval=0.25"}, "0.4"},
      // The geometry stage without its cache: each of the three runs makes the LV anew.
      ResumeCase{"land-lv", {"dp=2", "cache=none", "end_time=20", "ramp_time=10", "output_interval=5"}, "8"},
      ResumeCase{"depolarization", {"resolution=20", "end_time=4", "output_interval=1"}, "1.5"},
      // Between the two beats, with the action potential maps, the beat records and a pseudo-ECG.
      ResumeCase{"cable",
                 {"pacing=train", "pacing_count=2", "pacing_period=400", "end_time=800", "output_interval=200", "ecg=electrodes",
                  "ecg_electrodes=A:12,0.25,0.25;B:-2,0.25,0.25"},
                 "500"},
      ResumeCase{"niederer-slab", {"resolution=3", "output_interval=10"}, "30"},
      // During the automatic S2, placed at 398 ms: the resumed run must place it again.
      ResumeCase{"spiral-wave", {"resolution=40", "size=20", "end_time=800", "output_interval=100"}, "399"},
      ResumeCase{"elastic-gate", {"resolution=1", "end_time=40", "output_interval=10", "sort_interval=10"}, "15"},
      ResumeCase{"hydrostatic-plate", {"resolution=2", "end_time=0.05", "output_interval=0.01", "sort_interval=10"}, "0.02"},
      ResumeCase{"turek-hron-fsi2", {"resolution=10", "end_time=3", "output_interval=1", "sort_interval=10"}, "1.3"},
      ResumeCase{"cylinder-flow", {"resolution=10", "end_time=3", "output_interval=1", "sort_interval=10"}, "1.3"},
      ResumeCase{"sod-shock-tube", {"resolution=100", "output_interval=0.05"}, "0.08"},
      // During the contact: the deviatoric stress is loaded.
      ResumeCase{"rubber-rings", {"resolution=4", "end_time=8e-5", "output_interval=4e-5"}, "5e-5"},
      // While the bar yields: the plastic strain is loaded.
      ResumeCase{"taylor-bar", {"resolution=2", "end_time=2e-5", "output_interval=1e-5"}, "1.2e-5"},
      // The energy extremes are state; gravity and the variable h are rebuilt from the fields.
      ResumeCase{"evrard-collapse", {"particles=600", "end_time=0.6", "output_interval=0.3"}, "0.4"},
      // While the damage grows: the flaws are drawn again from the seed.
      ResumeCase{"impact", {"resolution=5", "end_time=12e-6", "output_interval=6e-6"}, "8e-6"},
      ResumeCase{"sedov-blast", {"resolution=40", "end_time=0.03", "output_interval=0.015"}, "0.02"}};
  return cases;
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, SceneCheckpoint, ::testing::ValuesIn(resume_cases()),
    [](const ::testing::TestParamInfo<ResumeCase>& param) {
      std::string name = param.param.scene;
      std::replace(name.begin(), name.end(), '-', '_');
      return name;
    });

// A scene that says it checkpoints must have its resume test (above, or HeartCheckpoint).
TEST(SceneCheckpointCoverage, EverySceneThatCheckpointsIsResumedInATest) {
  std::set<std::string> tested{"heart"};
  for (const auto& c : resume_cases()) tested.insert(c.scene);
  std::size_t checkpointing = 0;
  for (const auto& entry : cardiosph::scene_registry()) {
    if (!entry.make()->checkpoints()) continue;
    ++checkpointing;
    EXPECT_TRUE(tested.count(entry.name)) << entry.name << " checkpoints but no test resumes it";
  }
  std::cout << "  " << checkpointing << " of " << cardiosph::scene_registry().size() << " scenes checkpoint\n";
}

}  // namespace
