// Checkpoints: the file format refuses anything but a complete file of its own version; the state
// archive names a missing or misfitting record; a time stepper and a particle set saved between
// steps and loaded into freshly built ones continue bitwise as the uninterrupted run.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "libsph/core/particles.hpp"
#include "libsph/core/state_archive.hpp"
#include "libsph/core/time_stepper.hpp"
#include "libsph/io/checkpoint.hpp"
#include "libsph/io/parameters.hpp"

namespace {

using sph::Real;

sph::Checkpoint example() {
  sph::Checkpoint c{"heart", R"({"dp": 3.0})", 11.1, {}};
  c.records["stepper/time"] = std::string("\x01\x02\x03\x04\x05\x06\x07\x08", 8);
  c.records["body/heart/position"] = std::string(96, 'x');
  c.records["empty"] = "";
  return c;
}

// The message of the ParameterError that parsing `bytes` throws, or "" when it parses.
std::string parse_error(const std::string& bytes) {
  try {
    sph::parse_checkpoint(bytes, "test.bin");
  } catch (const sph::ParameterError& error) {
    return error.what();
  }
  return "";
}

TEST(Checkpoint, RoundTripKeepsEveryRecord) {
  const auto c = example();
  const auto back = sph::parse_checkpoint(sph::serialise_checkpoint(c), "test.bin");
  EXPECT_EQ(back.scene, c.scene);
  EXPECT_EQ(back.parameters, c.parameters);
  EXPECT_EQ(back.time, c.time);
  EXPECT_EQ(back.records, c.records);
}

TEST(Checkpoint, EveryTruncationIsRefusedByName) {
  const std::string bytes = sph::serialise_checkpoint(example());
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    const std::string message = parse_error(bytes.substr(0, n));
    ASSERT_FALSE(message.empty()) << "a checkpoint cut to " << n << " of " << bytes.size() << " bytes was accepted";
    EXPECT_NE(message.find("test.bin"), std::string::npos) << message;
  }
  EXPECT_NE(parse_error(bytes.substr(0, bytes.size() - 20)).find("truncated"), std::string::npos);
  EXPECT_NE(parse_error(bytes + "x").find("after its end"), std::string::npos);
}

TEST(Checkpoint, AnotherFormatVersionIsRefused) {
  std::string bytes = sph::serialise_checkpoint(example());
  const std::uint32_t version = sph::checkpoint_format_version + 1;
  std::memcpy(bytes.data() + 21, &version, sizeof(version));  // after the 21-byte magic
  EXPECT_NE(parse_error(bytes).find("has format version 2; this build reads version 1"), std::string::npos) << parse_error(bytes);
}

TEST(Checkpoint, AChangedByteIsFoundByTheHash) {
  std::string bytes = sph::serialise_checkpoint(example());
  bytes[bytes.size() - 20] ^= 1;  // inside the last record
  EXPECT_NE(parse_error(bytes).find("hash does not match"), std::string::npos) << parse_error(bytes);
  EXPECT_NE(parse_error("not a checkpoint at all").find("is not a cardiosph checkpoint"), std::string::npos);
}

TEST(Checkpoint, AMissingFileIsNamed) {
  try {
    sph::read_checkpoint("/nonexistent/checkpoint.bin");
    FAIL() << "no error";
  } catch (const sph::ParameterError& error) {
    EXPECT_NE(std::string(error.what()).find("/nonexistent/checkpoint.bin' does not exist"), std::string::npos) << error.what();
  }
}

TEST(StateArchive, MissingAndMisfittingRecordsAreNamed) {
  sph::StateRecords records;
  double x = 1.5;
  std::vector<float> v{1, 2, 3};
  sph::StateArchive save(records, sph::StateArchive::Mode::save, "solid");
  save.io("x", x);
  save.io("v", v);
  EXPECT_EQ(records.count("solid/x"), 1u);
  sph::StateArchive load(records, sph::StateArchive::Mode::load, "solid");
  double y = 0;
  load.io("x", y);
  EXPECT_EQ(y, 1.5);
  std::vector<float> w;
  load.io("v", w);
  EXPECT_EQ(w, v);
  float f = 0;
  EXPECT_THROW(load.io("x", f), sph::StateError);  // 8 bytes into a float
  try {
    load.io("missing", y);
    FAIL() << "no error";
  } catch (const sph::StateError& error) {
    EXPECT_NE(std::string(error.what()).find("'solid/missing'"), std::string::npos) << error.what();
  }
  std::vector<double> d;
  EXPECT_THROW(load.io("v", d), sph::StateError);  // 12 bytes are not whole doubles
}

TEST(StateArchive, ParticleSetKeepsEveryField) {
  sph::ParticleSet<2> a("plate", {sph::Vec<2>(0, 0), sph::Vec<2>(1, 0), sph::Vec<2>(0, 1)}, {1, 2, 3});
  const auto s = a.register_field<Real>("pressure", Real(4));
  const auto m = a.register_field<sph::Mat<2>>("F", sph::Mat<2>::Identity());
  const auto k = a.register_field<int>("label", 7);
  a.field(s)[1] = Real(0.25);
  a.field(m)[2](0, 1) = Real(0.5);
  sph::StateRecords records;
  sph::StateArchive save(records, sph::StateArchive::Mode::save);
  a.checkpoint(save);

  sph::ParticleSet<2> b("plate", {sph::Vec<2>(9, 9), sph::Vec<2>(9, 9), sph::Vec<2>(9, 9)}, {0, 0, 0});
  const auto bs = b.register_field<Real>("pressure");
  const auto bm = b.register_field<sph::Mat<2>>("F");
  const auto bk = b.register_field<int>("label");
  sph::StateArchive load(records, sph::StateArchive::Mode::load);
  b.checkpoint(load);
  EXPECT_EQ(b.position, a.position);
  EXPECT_EQ(b.volume, a.volume);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(b.field(bs)[i], a.field(s)[i]);
    EXPECT_EQ(b.field(bm)[i], a.field(m)[i]);
    EXPECT_EQ(b.field(bk)[i], a.field(k)[i]);
  }
  // A field of another length than the positions is refused.
  records["pressure"].resize(2 * sizeof(Real));
  sph::ParticleSet<2> c("plate", {sph::Vec<2>(0, 0), sph::Vec<2>(1, 0), sph::Vec<2>(0, 1)}, {1, 2, 3});
  c.register_field<Real>("pressure");
  c.register_field<sph::Mat<2>>("F");
  c.register_field<int>("label");
  sph::StateArchive again(records, sph::StateArchive::Mode::load);
  EXPECT_THROW(c.checkpoint(again), sph::StateError);
}

// x' = -x^2 + sin(t) by forward Euler with a state-dependent stable step, a hit-exactly event that
// kicks x and a sampling callback; interrupted at t = 0.73, saved, loaded into a freshly built stepper.
struct Toy {
  Real x = 1;
  std::vector<Real> samples;
  sph::TimeStepper stepper{0, 2};
  Toy() {
    stepper.add_stage(sph::make_stage("ode", [this] { return Real(0.05) / (1 + x * x); },
                                      [this](Real t, Real dt) { x += dt * (-x * x + std::sin(t)); }));
    stepper.add_event("kick", {0.3, true, false, true}, [this](const sph::StepInfo&) { x += Real(0.1); });
    stepper.add_periodic_callback(0.07, [this](const sph::StepInfo& s) { samples.push_back(x + s.time); }, false);
  }
  void checkpoint(sph::StateArchive& a) {
    auto part = a.part("stepper");
    stepper.checkpoint(part);
    a.io("x", x);
    a.io("samples", samples);
  }
};

TEST(TimeStepperCheckpoint, ResumedRunIsBitwiseTheUninterruptedOne) {
  Toy full;
  const std::size_t steps = full.stepper.run();

  Toy first;
  first.stepper.set_interruption_check([](const sph::StepInfo& s) { return s.time >= Real(0.73); });
  first.stepper.run();
  ASSERT_TRUE(first.stepper.interrupted());
  sph::StateRecords records;
  sph::StateArchive save(records, sph::StateArchive::Mode::save);
  first.checkpoint(save);

  Toy second;
  sph::StateArchive load(records, sph::StateArchive::Mode::load);
  second.checkpoint(load);
  EXPECT_EQ(second.stepper.run(), steps);
  EXPECT_FALSE(second.stepper.interrupted());
  EXPECT_EQ(std::memcmp(&second.x, &full.x, sizeof(Real)), 0) << second.x << " vs " << full.x;
  ASSERT_EQ(second.samples.size(), full.samples.size());
  for (std::size_t k = 0; k < full.samples.size(); ++k) EXPECT_EQ(second.samples[k], full.samples[k]) << k;
}

}  // namespace
