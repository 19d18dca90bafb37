// The command line and the run contract: bad input (unknown key or option, out-of-range values,
// missing or broken config, a tensor that is not positive definite) exits with code 2, names the
// problem and leaves no output folder; a good run writes report.json with the contract's keys.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli_for_test.hpp"
#include "temporary_folder.hpp"

namespace {

namespace fs = std::filesystem;

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    scratch_ = std::make_unique<test::TemporaryFolder>("cli");
    folder_ = scratch_->path();
  }
  void TearDown() override { scratch_.reset(); }

  int run(std::vector<std::string> args) {
    const auto r = test::run_cli(std::move(args));
    stdout_ = r.out;
    stderr_ = r.err;
    return r.code;
  }
  // Runs a bad input and checks exit code 2, the message, and that nothing was written.
  void expect_rejected(std::vector<std::string> args, const std::string& message_part) {
    const fs::path out = folder_ / "out";
    args.push_back("--output");
    args.push_back(out.string());
    EXPECT_EQ(run(args), 2) << stderr_;
    EXPECT_NE(stderr_.find(message_part), std::string::npos) << "stderr: " << stderr_;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(out.string() + ".partial"));
  }
  fs::path write(const std::string& name, const std::string& content) {
    std::ofstream(folder_ / name) << content;
    return folder_ / name;
  }

  std::unique_ptr<test::TemporaryFolder> scratch_;
  fs::path folder_;
  std::string stdout_, stderr_;
};

TEST_F(Cli, InvertedTetrahedronIsRejectedWithItsElement) {
  // A unit cube of five tetrahedra in openCARP form, the second one inverted.
  write("cube.pts", "8\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 1\n1 0 1\n0 1 1\n1 1 1\n");
  const auto elem = write("cube.elem", "5\nTt 0 1 2 4 1\nTt 3 1 2 7 1\nTt 1 4 5 7 1\nTt 2 6 4 7 1\nTt 1 2 4 7 1\n");
  expect_rejected({"particles", "--set", "mesh=" + elem.string(), "--set", "cache=none"}, "element 1 (vertices 3 1 2 7) is inverted");
  EXPECT_NE(stderr_.find("cube.elem"), std::string::npos) << stderr_;
}

TEST_F(Cli, UnknownMeshUnitsAreRejected) {
  expect_rejected({"particles", "--set", "units=furlong"}, "'units' (from --set) = 'furlong': must be one of um, mm, cm, m");
}
TEST_F(Cli, HeartNodeStimulusNeedsATetrahedralMesh) {
  expect_rejected({"heart", "--set", "stimulus_site=nodes", "--set", "stimulus_nodes=" + write("a.vtx", "1\n0\n").string()},
                  "needs a tetrahedral 'mesh'");
}

TEST_F(Cli, ImpossibleCheckpointOptionsAreRejected) {
  expect_rejected({"heart", "--checkpoint-interval", "-1"}, "option '--checkpoint-interval' = -1: must be >= 0");
  expect_rejected({"heart", "--interrupt-at", "-2"}, "option '--interrupt-at' = -2: must be a simulated time >= 0");
  expect_rejected({"homogeneous-deformation", "--checkpoint-interval", "1"}, "scene 'homogeneous-deformation' does not save its whole state");
  EXPECT_EQ(run({"heart", "--resume", (folder_ / "nowhere").string()}), 2);
  EXPECT_NE(stderr_.find("nowhere/checkpoint.bin' does not exist"), std::string::npos) << stderr_;
  EXPECT_FALSE(fs::exists(folder_ / "nowhere.resume"));
}

TEST_F(Cli, ListShowsTheScenes) {
  EXPECT_EQ(run({"list"}), 0);
  EXPECT_NE(stdout_.find("diffusion-aniso"), std::string::npos);
}

TEST_F(Cli, UnknownKeyIsRejected) { expect_rejected({"diffusion", "--set", "diffusivty=1"}, "unknown parameter 'diffusivty'"); }
TEST_F(Cli, MalformedAssignmentIsRejected) { expect_rejected({"diffusion", "--set", "diffusivity"}, "key=value"); }
TEST_F(Cli, UnknownOptionIsRejected) { expect_rejected({"diffusion", "--bogus"}, "bogus"); }
TEST_F(Cli, UnknownSceneIsRejected) { expect_rejected({"study", "no-such-scene", "--sweep", "resolution=1,2"}, "unknown scene"); }
TEST_F(Cli, ZeroResolutionIsRejected) { expect_rejected({"diffusion", "--resolution", "0"}, "'resolution'"); }
TEST_F(Cli, NegativeResolutionIsRejected) { expect_rejected({"diffusion-aniso", "--resolution", "-5"}, "must be > 0"); }
TEST_F(Cli, ImpossibleShockTubesAreRejected) {
  expect_rejected({"sod-shock-tube", "--set", "gamma=1"}, "parameter 'gamma' (from --set) = 1: must be in (1, 10]");
  expect_rejected({"sod-shock-tube", "--set", "tube_half_length=0.3"}, "parameter 'tube_half_length' = 0.300000 is too short");
  expect_rejected({"sod-shock-tube", "--set", "rows=4"}, "parameter 'rows' = 4 is narrower than the kernel support");
}
TEST_F(Cli, ImpossibleImpactParametersAreRejected) {
  expect_rejected({"evrard-collapse", "--set", "theta=0"}, "parameter 'theta' (from --set) = 0: must be in (0, 1]");
  expect_rejected({"evrard-collapse", "--set", "theta=1.5"}, "parameter 'theta' (from --set) = 1.5: must be in (0, 1]");
  expect_rejected({"impact", "--set", "weibull_k=0"}, "parameter 'weibull_k' (from --set) = 0: must be > 0");
  expect_rejected({"taylor-bar", "--set", "poisson_ratio=0.5"}, "parameter 'poisson_ratio' (from --set) = 0.5");
  expect_rejected({"rubber-rings", "--set", "inner_radius=0.05"}, "parameter 'inner_radius' = 0.050000 must be below 'outer_radius'");
}
TEST_F(Cli, NonIntegerResolutionIsRejected) { expect_rejected({"diffusion", "--resolution", "12.5"}, "not an integer"); }
TEST_F(Cli, ZeroEndTimeIsRejected) { expect_rejected({"diffusion", "--end-time", "0"}, "'end_time'"); }
TEST_F(Cli, NegativeEndTimeIsRejected) { expect_rejected({"diffusion", "--end-time", "-1"}, "'end_time'"); }
TEST_F(Cli, NotANumberIsRejected) { expect_rejected({"diffusion", "--end-time", "soon"}, "is not a number"); }
TEST_F(Cli, NegativeDiffusivityIsRejected) { expect_rejected({"diffusion", "--set", "diffusivity=-1e-4"}, "'diffusivity'"); }
TEST_F(Cli, ZeroDiffusivityIsRejected) { expect_rejected({"diffusion", "--set", "diffusivity=0"}, "'diffusivity'"); }
TEST_F(Cli, NegativeAnisotropicDiffusivityIsRejected) {
  expect_rejected({"diffusion-aniso", "--set", "diffusivity_longitudinal=-1"}, "'diffusivity_longitudinal'");
}
TEST_F(Cli, TensorThatIsNotPositiveDefiniteIsRejected) {
  expect_rejected({"diffusion-aniso", "--set", "diffusivity_transverse=0"}, "not positive definite");
}
// Fluid scenes: bad input is refused before anything is written.
TEST_F(Cli, SoundSpeedAboveMachPointThreeIsRefused) {
  expect_rejected({"dambreak", "--set", "sound_speed=5"}, "parameter 'sound_speed' = 5");
}
TEST_F(Cli, NegativeViscosityIsRejected) { expect_rejected({"dambreak", "--set", "viscosity=-0.1"}, "'viscosity'"); }
TEST_F(Cli, NegativeFluidDensityIsRejected) { expect_rejected({"dambreak", "--set", "density=-1"}, "'density'"); }
TEST_F(Cli, WaterColumnLargerThanTheTankIsRejected) {
  expect_rejected({"dambreak", "--set", "water_width=6"}, "does not fit in the tank");
}
TEST_F(Cli, SpacingLargerThanTheTankIsRejected) {
  expect_rejected({"hydrostatic-tank", "--set", "tank_width=0.1", "--resolution", "4"}, "'tank_width'");
}
TEST_F(Cli, UnknownFluidSchemeIsRejected) {
  expect_rejected({"taylor-green", "--set", "fluid_scheme=sph"}, "must be one of");
}
// A preset fills the parameters that the config file and the command line left alone; an explicit
// setting wins whatever its place on the command line.
TEST_F(Cli, PresetFillsWhatTheUserLeftAlone) {
  ASSERT_EQ(run({"myocardium-cube", "--set", "end_time=1.1", "--preset", "sphinxsys", "--parameters"}), 0) << stderr_;
  for (const char* line : {"end_time = 1.1 ", "max_tension = -15 ", "kernel = wendland_c2 ", "damping_rate = 0 "})
    EXPECT_NE(stdout_.find(line), std::string::npos) << line << " missing from:\n" << stdout_;
  ASSERT_EQ(run({"myocardium-cube", "--parameters"}), 0) << stderr_;
  EXPECT_NE(stdout_.find("max_tension = 5 "), std::string::npos) << stdout_;
  const auto config = write("cube.toml", "preset = \"sphinxsys\"\nmax_tension = -3\n");
  ASSERT_EQ(run({"myocardium-cube", "--config", config.string(), "--parameters"}), 0) << stderr_;
  EXPECT_NE(stdout_.find("max_tension = -3 "), std::string::npos) << stdout_;
  EXPECT_NE(stdout_.find("end_time = 1.2 "), std::string::npos) << stdout_;
}
TEST_F(Cli, HeartPresetWithoutItsMeshIsRejected) {
  const fs::path missing = folder_ / "no_shared_meshes";
  ::setenv("CARDIOSPH_SHARED_MESHES", missing.string().c_str(), 1);
  expect_rejected({"heart", "--preset", "sphinxsys"}, (missing / "biventricular_heart.stl").string());
  ::unsetenv("CARDIOSPH_SHARED_MESHES");
}
TEST_F(Cli, UnreadableRestitutionCouplingIsRejected) {
  expect_rejected({"cable", "--set", "restitution_couplings=400,soon"}, "'restitution_couplings'");
}
TEST_F(Cli, CouplingShorterThanThePulseIsRejected) {
  expect_rejected({"cable", "--set", "pacing=s1s2", "--set", "s2_coupling=1"}, "'s2_coupling'");
}
TEST_F(Cli, StimulusThatSelectsNoParticleIsRejected) {
  expect_rejected({"cable", "--set", "stimulus_length=0.1"}, "selects no particle");
}
TEST_F(Cli, MalformedElectrodeIsRejected) {
  expect_rejected({"cable", "--set", "ecg=electrodes", "--set", "ecg_electrodes=far:20,1"}, "'ecg_electrodes'");
}
TEST_F(Cli, ElectrodeInsideTheTissueIsRejected) {
  expect_rejected({"cable", "--set", "ecg=electrodes", "--set", "ecg_electrodes=in:5,0.25,0.25", "--set", "pacing=train",
                   "--set", "pacing_period=10", "--set", "stimulus_duration=1"},
                  "electrode 'in'");
}
TEST_F(Cli, UnknownChoiceIsRejected) { expect_rejected({"diffusion", "--set", "kernel=gauss"}, "must be one of"); }
TEST_F(Cli, MissingConfigIsRejected) {
  expect_rejected({"diffusion", "--config", (folder_ / "missing.toml").string()}, "cannot be read");
}
TEST_F(Cli, UnreadableConfigIsRejected) {
  fs::create_directories(folder_ / "folder.toml");
  expect_rejected({"diffusion", "--config", (folder_ / "folder.toml").string()}, "folder.toml");
}
TEST_F(Cli, BrokenTomlIsRejected) {
  expect_rejected({"diffusion", "--config", write("broken.toml", "diffusivity = = 3\n").string()}, "not valid TOML");
}
TEST_F(Cli, BrokenJsonIsRejected) {
  expect_rejected({"diffusion", "--config", write("broken.json", "{\"diffusivity\": }").string()}, "not valid JSON");
}
TEST_F(Cli, UnknownKeyInConfigIsRejected) {
  expect_rejected({"diffusion", "--config", write("c.toml", "[numerics]\ncfl = 0.5\n").string()},
                  "unknown parameter 'numerics.cfl'");
}
TEST_F(Cli, OutOfRangeValueInConfigIsRejected) {
  expect_rejected({"diffusion", "--config", write("c.json", "{\"diffusion_cfl\": 1.5}").string()}, "c.json");
}
TEST_F(Cli, ForeignOutputFolderIsNotOverwritten) {
  const fs::path out = folder_ / "mine";
  fs::create_directories(out);
  write("mine/notes.txt", "keep me");
  EXPECT_EQ(run({"diffusion", "--output", out.string(), "--resolution", "10"}), 2);
  EXPECT_TRUE(fs::exists(out / "notes.txt"));
}

TEST_F(Cli, RunWritesTheContractFiles) {
  const fs::path config = write("c.toml", "diffusivity = 2e-4\ndiffusion_integrator = \"forward_euler\"\n");
  const fs::path out = folder_ / "run";
  ASSERT_EQ(run({"diffusion", "--output", out.string(), "--config", config.string(), "--resolution", "20", "--end-time",
                 "2", "--set", "output_interval=1", "--threads", "2", "--quiet"}),
            0)
      << stderr_;
  nlohmann::json report = nlohmann::json::parse(std::ifstream(out / "report.json"));
  for (const char* key : {"scene", "status", "wall_time_s", "simulated_time", "steps", "particles", "parameters",
                          "results", "errors", "reference"})
    EXPECT_TRUE(report.contains(key)) << key;
  EXPECT_EQ(report["status"], "completed");
  EXPECT_EQ(report["parameters"]["diffusivity"], 2e-4);
  EXPECT_EQ(report["parameters"]["resolution"], 20);
  EXPECT_EQ(report["particles"]["tissue"], 20 * 4);
  EXPECT_TRUE(fs::exists(out / "tissue.pvd"));
  EXPECT_TRUE(fs::exists(out / "tissue_00002.vtu"));  // t = 0, 1, 2
  EXPECT_TRUE(fs::exists(out / "observers.csv"));
  EXPECT_FALSE(fs::exists(out.string() + ".partial"));
  // A second run into the same folder replaces the earlier one.
  EXPECT_EQ(run({"diffusion", "--output", out.string(), "--resolution", "10", "--end-time", "1", "--quiet"}), 0);
  EXPECT_FALSE(fs::exists(out / "tissue_00002.vtu"));
}

TEST_F(Cli, StudyWritesTableAndOrders) {
  const fs::path out = folder_ / "study";
  ASSERT_EQ(run({"study", "diffusion", "--sweep", "resolution=20,40", "--output", out.string(), "--quiet"}), 0) << stderr_;
  EXPECT_TRUE(fs::exists(out / "study.csv"));
  EXPECT_TRUE(fs::exists(out / "resolution-20" / "report.json"));
  EXPECT_NE(stdout_.find("observed order"), std::string::npos);
  std::ifstream csv(out / "study.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header, "resolution,particles,steps,threads,wall_time_s,l2_relative,max_abs");
}

TEST_F(Cli, BadSweepIsRejected) { expect_rejected({"study", "diffusion", "--sweep", "resolution=10"}, "at least two"); }
TEST_F(Cli, BadSweepValueIsRejectedBeforeAnyRun) {
  expect_rejected({"study", "diffusion", "--sweep", "resolution=10,-3"}, "'resolution'");
}

// --- particles: bad meshes exit 2 naming the problem, with nothing written ------------------------

// ASCII STL of triangles given as 9 numbers each.
std::string ascii_stl(const std::vector<std::array<double, 9>>& triangles) {
  std::string s = "solid test\n";
  for (const auto& t : triangles) {
    s += "facet normal 0 0 0\nouter loop\n";
    for (int k = 0; k < 3; ++k)
      s += "vertex " + std::to_string(t[3 * k]) + " " + std::to_string(t[3 * k + 1]) + " " + std::to_string(t[3 * k + 2]) + "\n";
    s += "endloop\nendfacet\n";
  }
  return s + "endsolid test\n";
}

// The 12 outward triangles of the box [o, o + size]^3.
std::vector<std::array<double, 9>> box_triangles(double o, double size) {
  const double a = o, b = o + size;
  const double v[8][3] = {{a, a, a}, {b, a, a}, {b, b, a}, {a, b, a}, {a, a, b}, {b, a, b}, {b, b, b}, {a, b, b}};
  const int f[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                        {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  std::vector<std::array<double, 9>> t;
  for (const auto& face : f) {
    std::array<double, 9> tri{};
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) tri[3 * k + d] = v[face[k]][d];
    t.push_back(tri);
  }
  return t;
}

TEST_F(Cli, ParticlesRejectsAFeatureThinnerThanTheSpacing) {
  // A 10 mm plate 0.8 mm thick at dp 1 mm: one layer of particles, a flat neighbourhood.
  auto t = box_triangles(0, 10);
  for (auto& triangle : t)
    for (int k = 0; k < 3; ++k) triangle[3 * k + 2] *= 0.08;
  expect_rejected({"particles", write("plate.stl", ascii_stl(t)).string(), "--dp", "1", "--set", "cache=none"},
                  "lie in features thinner than the spacing");
  EXPECT_NE(stderr_.find("a spacing of 0.2"), std::string::npos) << stderr_;
}

TEST_F(Cli, ParticlesRejectsAnOpenBox) {
  auto t = box_triangles(0, 10);
  t.pop_back();
  t.pop_back();
  expect_rejected({"particles", write("open.stl", ascii_stl(t)).string(), "--dp", "1", "--set", "cache=none"}, "border edges");
}
TEST_F(Cli, ParticlesRejectsInvertedNormals) {
  auto t = box_triangles(0, 10);
  for (auto& tri : t) std::swap_ranges(tri.begin(), tri.begin() + 3, tri.begin() + 3);
  expect_rejected({"particles", write("inverted.stl", ascii_stl(t)).string(), "--dp", "1", "--set", "cache=none"}, "negative");
}
TEST_F(Cli, ParticlesRejectsOverlappingShells) {
  auto t = box_triangles(0, 10);
  const auto u = box_triangles(5, 10);
  t.insert(t.end(), u.begin(), u.end());
  expect_rejected({"particles", write("overlap.stl", ascii_stl(t)).string(), "--dp", "1", "--set", "cache=none"}, "self-intersecting");
}
TEST_F(Cli, ParticlesRejectsAnEmptyFile) {
  expect_rejected({"particles", write("empty.stl", "").string(), "--dp", "1", "--set", "cache=none"}, "empty");
}
TEST_F(Cli, ParticlesRejectsATruncatedBinaryStl) {
  std::string bytes(80, ' ');
  const std::uint32_t n = 12;
  bytes.append(reinterpret_cast<const char*>(&n), 4);
  bytes.append(50 * 5, '\0');  // 5 of the 12 announced triangles
  expect_rejected({"particles", write("truncated.stl", bytes).string(), "--dp", "1", "--set", "cache=none"}, "truncated");
}
TEST_F(Cli, ParticlesRejectsANonMeshFile) {
  expect_rejected({"particles", write("notes.obj", "these are my notes, not a mesh\n").string(), "--dp", "1", "--set", "cache=none"},
                  "notes.obj");
}
TEST_F(Cli, ParticlesRejectsAMissingMesh) {
  expect_rejected({"particles", (folder_ / "nowhere.stl").string(), "--dp", "1"}, "no such file");
}

// A renamed parameter keeps its old name, with a warning that names both.
TEST_F(Cli, AnOldParameterNameStillWorksAndWarns) {
  const fs::path mesh = write("box.stl", ascii_stl(box_triangles(0, 10)));
  ASSERT_EQ(run({"particles", mesh.string(), "--dp", "2", "--set", "fibres=uniform", "--set", "fiber_check=none", "--set", "cache=none", "--quiet",
                 "--output", (folder_ / "out").string()}),
            0)
      << stderr_;
  EXPECT_NE(stderr_.find("parameter 'fiber_check' (from --set) is now called 'fibre_check'"), std::string::npos) << stderr_;
}

TEST_F(Cli, ParticlesOfABoxWithUniformFibres) {
  const fs::path mesh = write("box.stl", ascii_stl(box_triangles(0, 10)));
  const fs::path out = folder_ / "out";
  ASSERT_EQ(run({"particles", mesh.string(), "--dp", "1", "--set", "fibres=uniform", "--set", "cache=none", "--quiet",
                 "--output", out.string()}),
            0)
      << stderr_;
  std::ifstream in(out / "report.json");
  const auto report = nlohmann::json::parse(in);
  EXPECT_EQ(report["results"]["particles"], 1000);
  EXPECT_LT(std::abs(report["results"]["volume_relative_error"].get<double>()), 1e-9);
  EXPECT_TRUE(fs::exists(out / "particles.pvd"));
  EXPECT_FALSE(report["results"].contains("fibre_angle_mad_deg"));
}

// --- heart: bad input exits 2 naming the problem, with nothing written ---------------------------

TEST_F(Cli, HeartRejectsAMissingMesh) {
  expect_rejected({"heart", (folder_ / "nowhere.stl").string()}, "no such file");
}
TEST_F(Cli, HeartRejectsAnUnknownPreset) { expect_rejected({"heart", "--preset", "ultra"}, "preset"); }
TEST_F(Cli, HeartRejectsAMalformedStimulusPoint) {
  expect_rejected({"heart", "--set", "stimulus_site=point", "--set", "stimulus_point=1,2"}, "stimulus_point");
}
TEST_F(Cli, HeartRejectsAMeshWithoutVentricles) {
  // A closed box: no cavity, so no endocardium to stimulate or to measure.
  const fs::path mesh = write("box.stl", ascii_stl(box_triangles(0, 10)));
  expect_rejected({"heart", mesh.string(), "--dp", "2", "--set", "cache=none", "--set", "relaxation_steps=0"}, "no endocardium");
}

TEST_F(Cli, HeartRejectsAnImpossibleCirculation) {
  expect_rejected({"heart", "--set", "circulation_systemic_arterial_compliance=-1"}, "circulation_systemic_arterial_compliance");
  expect_rejected({"heart", "--set", "circulation_aortic_resistance=0"}, "circulation_aortic_resistance");
}
TEST_F(Cli, HeartRejectsABadReferenceRun) {
  expect_rejected({"heart", "--set", "reference_run=" + (folder_ / "nowhere").string()}, "cannot read");
  expect_rejected({"heart", "--set", "reference_run=" + write("bad.json", "{\"results\": 3").string()}, "is not a report");
  expect_rejected({"heart", "--set", "reference_run=" + write("empty.json", "{\"results\": {\"beats\": []}}").string()},
                  "holds no beat");
  expect_rejected({"heart", "--set", "cavity_pressure=constant", "--set",
                   "reference_run=" + write("one.json", "{\"results\": {\"beats\": [{}]}}").string()},
                  "needs cavity_pressure = circulation");
}
TEST_F(Cli, HeartRejectsTheLandTensionWithoutCalcium) {
  expect_rejected({"heart", "--set", "cell_model=aliev_panfilov"}, "tension_model");
}
TEST_F(Cli, HeartRejectsTheCirculationOnAMeshWithoutAnRvCavity) {
  // The shipped LV ellipsoid: one endocardium, so no RV volume for the closed loop.
  const fs::path meshes = fs::path(CARDIOSPH_SOURCE_DIR) / "meshes";
  expect_rejected({"heart", (meshes / "lv_ellipsoid.stl").string(), "--dp", "2", "--set", "cache=none", "--set",
                   "epi_surface=" + (meshes / "lv_ellipsoid_epi.stl").string(), "--set",
                   "lv_surface=" + (meshes / "lv_ellipsoid_lv_endo.stl").string(), "--set",
                   "base_surface=" + (meshes / "lv_ellipsoid_base.stl").string()},
                  "RV endocardium");
}

}  // namespace

