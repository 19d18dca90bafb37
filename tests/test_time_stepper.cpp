// The time stepper: exact event times, the end time hit exactly, callbacks at start and end,
// steps evened out before events, nested stages, events, and time-step collapse stops the run.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "libsph/core/time_stepper.hpp"
#include "tests/precision.hpp"

namespace {

using sph::Real;

TEST(TimeStepper, HitsOutputTimesAndTheEndExactly) {
  sph::TimeStepper stepper(0, 1);
  Real advanced = 0;
  std::vector<Real> steps;
  stepper.add_stage(sph::make_stage("s", [] { return Real(0.03); }, [&](Real, Real dt) { advanced += dt; steps.push_back(dt); }));
  std::vector<Real> outputs;
  stepper.add_periodic_callback(0.25, [&](const sph::StepInfo& s) { outputs.push_back(s.time); });
  const auto n = stepper.run();
  ASSERT_EQ(outputs.size(), 5u);
  for (int k = 0; k < 5; ++k) EXPECT_EQ(outputs[k], 0.25 * k);  // exact, not accumulated
  EXPECT_NEAR(advanced, 1.0, test::bound(1e-14, 1e-6));
  EXPECT_EQ(n, steps.size());
  EXPECT_EQ(n, 4u * 9u);  // ceil(0.25 / 0.03) = 9 equal steps per output interval
  for (Real dt : steps) EXPECT_LE(dt, 0.03);
  for (Real dt : steps) EXPECT_NEAR(dt, 0.25 / 9, test::bound(1e-15, 1e-7));
}

TEST(TimeStepper, SamplingCallbacksDoNotShortenSteps) {
  sph::TimeStepper stepper(0, 1);
  std::size_t sampled = 0;
  stepper.add_stage(sph::make_stage("s", [] { return Real(0.3); }, [](Real, Real) {}));
  stepper.add_periodic_callback(0.1, [&](const sph::StepInfo&) { ++sampled; }, false);
  EXPECT_EQ(stepper.run(), 4u);  // ceil(1 / 0.3) steps of 0.25
  EXPECT_EQ(sampled, 5u);        // start, after each step
}

TEST(TimeStepper, FinalStateIsSeenWhenTheIntervalDoesNotDivideTheRun) {
  sph::TimeStepper stepper(0, 1);
  stepper.add_stage(sph::make_stage("s", [] { return Real(0.01); }, [](Real, Real) {}));
  std::vector<Real> outputs;
  stepper.add_periodic_callback(0.3, [&](const sph::StepInfo& s) { outputs.push_back(s.time); });
  stepper.run();
  ASSERT_EQ(outputs.size(), 5u);  // 0, 0.3, 0.6, 0.9 and the end
  EXPECT_EQ(outputs.back(), 1.0);
}

TEST(TimeStepper, StopsAfterTheStepThatAsksAndShowsTheFinalState) {
  sph::TimeStepper stepper(0, 10);
  Real t_reached = 0;
  stepper.add_stage(sph::make_stage("s", [] { return Real(0.5); }, [&](Real t, Real dt) { t_reached = t + dt; }));
  stepper.add_step_callback([&](const sph::StepInfo& s) {
    if (s.time >= 2) stepper.stop_after_this_step();
  });
  std::vector<Real> outputs;
  stepper.add_periodic_callback(5, [&](const sph::StepInfo& s) { outputs.push_back(s.time); });
  EXPECT_EQ(stepper.run(), 4u);
  EXPECT_EQ(t_reached, 2);
  EXPECT_EQ(stepper.end_time(), 2);
  EXPECT_EQ(outputs, (std::vector<Real>{0, 2}));  // the start and the state where the run stopped
}

TEST(TimeStepper, NestedStageTakesEqualSubStepsInsideEachStep) {
  sph::TimeStepper stepper(0, 1);
  std::size_t macro = 0, sub = 0;
  Real sub_time = 0;
  sph::Stage slow{"slow", [] { return Real(0.1); }, {}};
  slow.then("slow work", [&](Real, Real) { ++macro; })
      .sub_cycle(sph::make_stage("fast", [] { return Real(0.03); }, [&](Real, Real dt) { ++sub; sub_time += dt; }));
  stepper.add_stage(std::move(slow));
  stepper.run();
  EXPECT_EQ(macro, 10u);
  EXPECT_EQ(sub, 40u);  // ceil(0.1 / 0.03) = 4 per macro step
  EXPECT_NEAR(sub_time, 1.0, test::bound(1e-14, 1e-6));
}

TEST(TimeStepper, StepQuantumKeepsStepsWholeMultiplesUpToEvents) {
  // A coupling stage of whole EP steps (quantum 0.1) that is stable for 0.35: up to each output at
  // multiples of 1 it takes steps of 3 quanta and then the 1 quantum left (not ten evened steps of
  // 0.0833 each), and its nested stage of step 0.1 takes exactly 3 or 1 sub-steps of 0.1.
  sph::TimeStepper stepper(0, 2);
  std::vector<Real> steps;
  std::size_t sub = 0;
  sph::Stage coupled{"coupled", [] { return Real(0.35); }, {}, Real(0.1)};
  coupled.then("record", [&](Real, Real dt) { steps.push_back(dt); })
      .sub_cycle(sph::make_stage("ep", [] { return Real(0.1) * (1 + Real(1e-9)); }, [&](Real, Real dt) {
        ++sub;
        EXPECT_NEAR(dt, 0.1, test::bound(1e-12, 1e-6));
      }));
  stepper.add_stage(std::move(coupled));
  stepper.add_periodic_callback(1, [](const sph::StepInfo&) {});
  stepper.run();
  ASSERT_EQ(steps.size(), 8u);  // per output interval: 0.3, 0.3, 0.3, 0.1
  for (std::size_t k = 0; k < steps.size(); ++k) EXPECT_NEAR(steps[k], k % 4 == 3 ? 0.1 : 0.3, test::bound(1e-12, 1e-6));
  EXPECT_EQ(sub, 20u);
}

TEST(TimeStepper, NestedStageReevaluatesItsStepBeforeEverySubStep) {
  // The inner stable step halves after its first sub-step: the remaining part of the outer step
  // is then covered in equal sub-steps of the new size, ending exactly at the outer step's end.
  sph::TimeStepper stepper(0, 1);
  Real inner_stable = 0.25;
  std::vector<std::pair<Real, Real>> sub_steps;
  sph::Stage outer{"outer", [] { return Real(1); }, {}};
  outer.sub_cycle(sph::make_stage("inner", [&] { return inner_stable; }, [&](Real t, Real dt) {
    sub_steps.emplace_back(t, dt);
    inner_stable = 0.125;
  }));
  stepper.add_stage(std::move(outer));
  stepper.run();
  ASSERT_EQ(sub_steps.size(), 7u);  // one of 0.25, then 0.75 / 0.125 = 6
  EXPECT_EQ(sub_steps[0].second, 0.25);
  for (std::size_t k = 1; k < 7; ++k) EXPECT_NEAR(sub_steps[k].second, 0.125, test::bound(1e-15, 1e-7));
  EXPECT_NEAR(sub_steps.back().first + sub_steps.back().second, 1.0, test::bound(1e-15, 1e-7));
}

TEST(TimeStepper, ThreeLevelsNestAndEveryLevelCoversItsParentStep) {
  // Dual-criteria shape: advection 0.1 holds acoustic 0.04 (3 per advection step), each holding
  // solid 0.01 (0.1/3 / 0.01 -> 4 per acoustic step).
  sph::TimeStepper stepper(0, 0.5);
  std::size_t advection = 0, acoustic = 0, solid = 0;
  Real solid_time = 0;
  sph::Stage solid_stage = sph::make_stage("solid", [] { return Real(0.01); }, [&](Real, Real dt) {
    ++solid;
    solid_time += dt;
  });
  sph::Stage acoustic_stage{"acoustic", [] { return Real(0.04); }, {}};
  acoustic_stage.then("first half", [&](Real, Real) { ++acoustic; }).sub_cycle(std::move(solid_stage));
  sph::Stage advection_stage{"advection", [] { return Real(0.1); }, {}};
  advection_stage.then("neighbours", [&](Real, Real) { ++advection; }).sub_cycle(std::move(acoustic_stage));
  stepper.add_stage(std::move(advection_stage));
  EXPECT_EQ(stepper.run(), 5u);
  EXPECT_EQ(advection, 5u);
  EXPECT_EQ(acoustic, 15u);
  EXPECT_EQ(solid, 60u);
  EXPECT_NEAR(solid_time, 0.5, test::bound(1e-14, 1e-6));
}

TEST(TimeStepper, EventsCanSkipTheStartAndTheEnd) {
  sph::TimeStepper stepper(0, 1);
  stepper.add_stage(sph::make_stage("s", [] { return Real(0.1); }, [](Real, Real) {}));
  std::vector<Real> times;
  stepper.add_event("update", {0.3, false, false, false}, [&](const sph::StepInfo& s) { times.push_back(s.time); });
  stepper.run();
  ASSERT_EQ(times.size(), 3u);  // the first steps at or after 0.3, 0.6 and 0.9; not at 0 or 1
  EXPECT_NEAR(times[0], 0.3, test::bound(1e-12, 1e-6));
  EXPECT_NEAR(times[1], 0.6, test::bound(1e-12, 1e-6));
  EXPECT_NEAR(times[2], 0.9, test::bound(1e-12, 1e-6));
}

TEST(TimeStepper, TimeStepCollapseStopsTheRun) {
  sph::TimeStepper stepper(0, 1);
  int calls = 0;
  stepper.add_stage(sph::make_stage("collapsing", [&] { return calls++ < 3 ? Real(0.1) : Real(0); }, [](Real, Real) {}));
  try {
    stepper.run();
    FAIL() << "collapse not detected";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("time-step collapse in stage 'collapsing'"), std::string::npos);
  }
}

}  // namespace

// Slots: a system's stage leaves named places between its phases; couplings filled into them run
// there, in the order they were added, also inside a nested stage and after the stage was handed to
// the stepper; an unknown slot is refused by name.
TEST(TimeStepperSlots, FilledSlotsRunInPlaceAndInOrder) {
  std::vector<std::string> log;
  auto note = [&log](std::string what) { return [&log, what](Real, Real) { log.push_back(what); }; };
  sph::Stage inner{"inner", {}, {}};
  inner.then("inner a", note("inner a")).slot("inner slot").then("inner b", note("inner b"));
  sph::Stage outer{"outer", [] { return Real(1); }, {}};
  outer.then("first", note("first")).slot("loads").sub_cycle(std::move(inner)).then("last", note("last"));
  outer.fill("loads", "load 1", note("load 1")).fill("loads", "load 2", note("load 2"));
  EXPECT_TRUE(outer.has_slot("inner slot"));
  EXPECT_FALSE(outer.has_slot("nowhere"));
  EXPECT_THROW(outer.fill("nowhere", "x", note("x")), std::invalid_argument);
  sph::TimeStepper stepper(0, 1);
  stepper.add_stage(std::move(outer));
  stepper.fill("inner slot", "coupling", note("coupling"));
  EXPECT_THROW(stepper.fill("nowhere", "x", note("x")), std::invalid_argument);
  stepper.run();
  const std::vector<std::string> expected{"first", "load 1", "load 2", "inner a", "coupling", "inner b", "last"};
  EXPECT_EQ(log, expected);
}

// An empty slot does nothing: the stage runs as if it were not there.
TEST(TimeStepperSlots, EmptySlotRunsNothing) {
  int calls = 0;
  sph::Stage stage{"s", [] { return Real(0.25); }, {}};
  stage.slot("empty").then("count", [&calls](Real, Real) { ++calls; }).slot("also empty");
  sph::TimeStepper stepper(0, 1);
  stepper.add_stage(std::move(stage));
  EXPECT_EQ(stepper.run(), 4u);
  EXPECT_EQ(calls, 4);
}
