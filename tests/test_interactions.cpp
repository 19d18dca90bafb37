// Two systems in one simulation: two blocks that exchange heat through one contact interaction,
// stepped with nested stages (the faster-diffusing block sub-cycles inside each step of the other,
// and the slower one sees its average over the sub-steps, so the exchange conserves the amount),
// against the exact solution of two semi-infinite media in contact (Carslaw & Jaeger 1959,
// Conduction of Heat in Solids, sec. 2.15): with C = 1 on the left and 0 on the right at t = 0 and
// equal capacities, the interface sits at C_i = sqrt(D_l) / (sqrt(D_l) + sqrt(D_r)) and
//   C = 1 - (1 - C_i) erfc(-x / (2 sqrt(D_l t)))   (x < 0),    C = C_i erfc(x / (2 sqrt(D_r t)))   (x > 0).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "geometry/lattice.hpp"
#include "libsph/core/interaction.hpp"
#include "libsph/core/neighbour_relation.hpp"
#include "libsph/core/parallel.hpp"
#include "libsph/core/time_stepper.hpp"
#include "libsph/diffusion/diffusion_contact.hpp"
#include "libsph/diffusion/diffusion_system.hpp"
#include "tests/precision.hpp"

namespace {

using sph::Real;
using Vec2 = sph::Vec<2>;

constexpr Real dp = Real(0.01), h = Real(1.3) * dp, height = Real(0.2), interface = Real(0.5);

struct Block {
  sph::ParticleSet<2> body;
  sph::InnerRelation<2> relation;
  sph::ScalarDiffusionSystem<2> diffusion;
  Block(const std::string& name, Real x0, Real x1, Real diffusivity, Real initial, const sph::AnyKernel<2>& kernel)
      : body(geometry::lattice_box<2>(name, Vec2(x0, 0), Vec2(x1, height), dp)),
        relation(sph::build_inner_relation<2>(body.position, kernel, h)),
        diffusion(body, relation, settings(diffusivity)) {
    auto C = body.field(diffusion.value_field());
    for (auto& c : C) c = initial;
  }
  static sph::ScalarDiffusionSystem<2>::Settings settings(Real diffusivity) {
    sph::ScalarDiffusionSystem<2>::Settings s;
    s.diffusion_tensor = {diffusivity * sph::Mat<2>::Identity()};
    s.numerics.correction = sph::DiffusionCorrection::none;  // required by the contact exchange
    s.numerics.integrator = sph::DiffusionIntegrator::forward_euler;
    return s;
  }
  /// A stage at this block's stable step.
  sph::Stage stage(const std::string& name) {
    return sph::Stage{name, [this] { return diffusion.stable_time_step(); }, {}};
  }
  /// The coupled step of this block: own operator, exchange with the other system, update.
  template <class Other>
  void add_phases(sph::Stage& stage, const Other& other, const sph::ContactRelation<2>& contact) {
    stage.then("operator", [this](Real, Real) { diffusion.evaluate_rate(); })
        .then("exchange", sph::coupling(diffusion, other, contact))
        .then("update", [this](Real t, Real dt) { diffusion.update(t, dt); });
  }
  double amount() const {
    double total = 0;
    const auto C = body.field(diffusion.value_field());
    for (std::size_t i = 0; i < C.size(); ++i) total += double(body.volume[i]) * C[i];
    return total;
  }
};

double exact(double x, double t, double D_left, double D_right) {
  const double interface_value = std::sqrt(D_left) / (std::sqrt(D_left) + std::sqrt(D_right));
  const double s = x - interface;
  if (s < 0) return 1 - (1 - interface_value) * std::erfc(-s / (2 * std::sqrt(D_left * t)));
  return interface_value * std::erfc(s / (2 * std::sqrt(D_right * t)));
}

/// The two blocks with the right one sub-cycling inside each step of the left one, run to end_time.
struct TwoBlockRun {
  Block left, right;
  sph::ContactRelation<2> left_from_right, right_from_left;
  std::size_t left_steps = 0, right_steps = 0;
  double initial_amount = 0;

  TwoBlockRun(Real D_left, Real D_right, Real end_time, const sph::AnyKernel<2>& kernel)
      : left("left", 0, interface, D_left, 1, kernel),
        right("right", interface, 1, D_right, 0, kernel),
        left_from_right(sph::build_contact_relation<2>(left.body.position, right.body.position, kernel, h)),
        right_from_left(sph::build_contact_relation<2>(right.body.position, left.body.position, kernel, h)) {
    initial_amount = left.amount() + right.amount();
    // The right block diffuses four times faster, so its stable step is a quarter of the left's:
    // it sub-cycles inside each step of the left block against the left held at the step's start,
    // then the left block takes its step against the right's average over those sub-steps.
    sph::SubStepAverage<2> right_average(right.diffusion);
    sph::Stage fast = right.stage("right");
    fast.then("average", [&](Real, Real ds) {  // the state a forward-Euler sub-step starts from
      right_average.add(ds);
      ++right_steps;
    });
    right.add_phases(fast, left.diffusion, right_from_left);
    sph::Stage step = left.stage("left");
    step.then("reset average", [&](Real, Real) { right_average.reset(); })
        .sub_cycle(std::move(fast))
        .then("finish average", [&](Real, Real) { right_average.finish(); });
    left.add_phases(step, right_average, left_from_right);
    sph::TimeStepper stepper(0, end_time);
    stepper.add_stage(std::move(step));
    left_steps = stepper.run();
  }
};

TEST(Interactions, TwoBlocksInContactWithNestedStagesMatchTheCompositeMediumSolution) {
  const Real D_left = Real(1e-4), D_right = Real(4e-4), end_time = 20;
  const TwoBlockRun run(D_left, D_right, end_time, sph::make_kernel<2>("wendland_c2"));
  const Block& left = run.left;
  const Block& right = run.right;
  const std::size_t left_steps = run.left_steps, right_steps = run.right_steps;
  const double initial_amount = run.initial_amount;

  // Error on the rows farther than one kernel support (2h) from the walls y = 0 and y = height,
  // where the uncorrected operator sees a truncated support.
  double error2 = 0, exact2 = 0, interface_error = 0;
  for (const Block* block : {&left, &right}) {
    const auto C = block->body.field(block->diffusion.value_field());
    for (std::size_t i = 0; i < C.size(); ++i) {
      const Vec2& x = block->body.position[i];
      if (x[1] < 2 * h || x[1] > height - 2 * h) continue;
      const double e = exact(x[0], end_time, D_left, D_right);
      error2 += (C[i] - e) * (C[i] - e);
      exact2 += e * e;
      if (std::abs(x[0] - interface) < dp) interface_error = std::max(interface_error, std::abs(C[i] - e));
    }
  }
  const double l2 = std::sqrt(error2 / exact2);
  const double amount_change = (left.amount() + right.amount() - initial_amount) / initial_amount;
  std::printf("two blocks: %zu + %zu particles, %zu left steps, %zu right sub-steps, L2 relative error %.3e, "
              "interface error %.3e, amount change %.2e\n",
              left.body.n_particles(), right.body.n_particles(), left_steps, right_steps, l2, interface_error,
              amount_change);
  EXPECT_GE(right_steps, 3 * left_steps);  // really sub-cycled
  EXPECT_LT(l2, 1e-2);                     // bound: 1 % in L2 on the interior rows
  EXPECT_LT(interface_error, 1e-2);        // the interface value C_i = 1/3 to 0.01
  EXPECT_LT(std::abs(amount_change), test::bound(1e-12, 1e-5));  // conservative multi-rate exchange
}

TEST(Interactions, NestedCoupledRunIsBitwiseTheSameOnOneAndTwoThreads) {
  const auto kernel = sph::make_kernel<2>("wendland_c2");
  auto fields = [&](std::size_t threads) {
    sph::ThreadLimit limit(threads);
    const TwoBlockRun run(Real(1e-4), Real(4e-4), Real(2), kernel);
    const auto L = run.left.body.field(run.left.diffusion.value_field());
    const auto R = run.right.body.field(run.right.diffusion.value_field());
    std::vector<Real> all(L.begin(), L.end());
    all.insert(all.end(), R.begin(), R.end());
    return all;
  };
  EXPECT_EQ(fields(1), fields(2));
}

TEST(Interactions, TwoBlocksOfEqualDiffusivityDiffuseAsOneBody) {
  // Split along x = 0.5, two bodies coupled by the exchange step exactly as one body without
  // correction does (same pairs, same coefficients; only the order of the sums differs).
  const Real D = Real(2e-4);
  const auto kernel = sph::make_kernel<2>("wendland_c2");
  Block left("left", 0, interface, D, 1, kernel), right("right", interface, 1, D, 0, kernel);
  Block whole("whole", 0, 1, D, 0, kernel);
  {
    auto C = whole.body.field(whole.diffusion.value_field());
    for (std::size_t i = 0; i < C.size(); ++i) C[i] = whole.body.position[i][0] < interface ? 1 : 0;
  }
  const auto left_from_right = sph::build_contact_relation<2>(left.body.position, right.body.position, kernel, h);
  const auto right_from_left = sph::build_contact_relation<2>(right.body.position, left.body.position, kernel, h);
  // Phases across both systems: both operators from the same state, both exchanges, both updates.
  const Real dt = whole.diffusion.stable_time_step();
  sph::Stage coupled{"coupled", [dt] { return dt; }, {}};
  coupled.then("operators", [&](Real, Real) { left.diffusion.evaluate_rate(), right.diffusion.evaluate_rate(); })
      .then("left from right", sph::coupling(left.diffusion, right.diffusion, left_from_right))
      .then("right from left", sph::coupling(right.diffusion, left.diffusion, right_from_left))
      .then("updates", [&](Real t, Real step) { left.diffusion.update(t, step), right.diffusion.update(t, step); });
  sph::TimeStepper two(0, 2);
  two.add_stage(std::move(coupled));
  sph::TimeStepper one(0, 2);
  one.add_stage(sph::make_stage("whole", [dt] { return dt; }, [&](Real t, Real step) { whole.diffusion.advance(t, step); }));
  EXPECT_EQ(two.run(), one.run());

  // Particles of the whole box at the same positions as the two blocks' (lattice cell centres).
  double max_difference = 0;
  const auto C_whole = whole.body.field(whole.diffusion.value_field());
  for (const Block* block : {&left, &right}) {
    const auto C = block->body.field(block->diffusion.value_field());
    for (std::size_t i = 0; i < C.size(); ++i)
      for (std::size_t k = 0; k < C_whole.size(); ++k)
        if ((whole.body.position[k] - block->body.position[i]).norm() < dp / 4)
          max_difference = std::max(max_difference, double(std::abs(C[i] - C_whole[k])));
  }
  std::printf("two blocks against one body: max difference %.2e\n", max_difference);
  EXPECT_LT(max_difference, test::bound(1e-12, 1e-5));
  // Equal volumes make a_ij = a_ji: the exchange conserves the amount to round-off.
  EXPECT_NEAR(left.amount() + right.amount(), 0.5 * 0.2, test::bound(1e-12, 1e-5));
}

}  // namespace
