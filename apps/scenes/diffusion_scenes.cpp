#include "apps/scenes/diffusion_scenes.hpp"

#include <cmath>
#include <functional>
#include <sstream>

#include "geometry/lattice.hpp"
#include "libsph/core/distribution.hpp"
#include "libsph/core/kernels.hpp"
#include "libsph/core/neighbour_relation.hpp"
#include "libsph/core/parallel.hpp"
#include "libsph/core/time_stepper.hpp"
#include "libsph/diffusion/diffusion_operator.hpp"
#include "libsph/diffusion/diffusion_system.hpp"
#include "libsph/core/point_probes.hpp"
#include "libsph/io/run_harness.hpp"

namespace cardiosph {
namespace {

using sph::Real;
using Vec2 = sph::Vec<2>;
using Mat2 = sph::Mat<2>;

void declare_numerics(sph::Parameters& p, DiffusionNumerics& n) {
  declare_parameters(p, n.discretisation, "s");
  sph::declare_parameters(p, n.diffusion);
}

/// What distinguishes the two scenes; the run itself is shared.
struct DiffusionProblem {
  std::string scene;
  Vec2 lower, upper;
  long resolution;
  double end_time;
  Mat2 diffusion_tensor;
  DiffusionNumerics numerics;
  std::function<double(const Vec2& x, Real dp)> initial;  ///< C at t = 0 for the particle at x
  std::function<double(const Vec2& x, double t)> exact;   ///< exact C for t > 0
  std::vector<Vec2> probes;
  std::string reference;
};

void run_diffusion_problem(const DiffusionProblem& problem, RunContext& ctx) {
  const Real dp = (problem.upper[0] - problem.lower[0]) / static_cast<Real>(problem.resolution);
  const Real h = static_cast<Real>(problem.numerics.discretisation.smoothing_length_ratio) * dp;

  // Particles and initial state. Every rank builds the whole body; a distributed run keeps this
  // rank's part with its ghosts (libsph/core/distribution.hpp). The probes are laid on the whole body.
  auto body = geometry::lattice_box<2>("tissue", problem.lower, problem.upper, dp);
  const auto kernel = sph::make_kernel<2>(problem.numerics.discretisation.kernel);
  const sph::PointProbes<2> probes(problem.probes, body.position, body.volume, kernel, h);
  sph::distribute(body, std::visit([h]<class K>(const K&) { return K::support_radius(h); }, kernel));
  const auto relation = sph::build_inner_relation<2>(body, kernel, h);

  typename sph::ScalarDiffusionSystem<2>::Settings settings;
  settings.field_name = "concentration";
  settings.diffusion_tensor = {problem.diffusion_tensor};
  settings.numerics = problem.numerics.diffusion;
  sph::ScalarDiffusionSystem<2> diffusion(body, relation, settings);
  auto C = body.field(diffusion.value_field());
  for (std::size_t i = 0; i < body.n_particles(); ++i) C[i] = static_cast<Real>(problem.initial(body.position[i], dp));
  const auto exact_handle = body.register_field<Real>("exact_concentration", 0);
  auto C_exact = body.field(exact_handle);

  auto total_amount = [&] { return sph::global_sum(body, [&](std::size_t i) { return double(body.volume[i] * C[i]); }); };
  const double initial_amount = total_amount();

  // Time loop: one stage; observers every 1/100 of the run, particles at the output interval.
  sph::TimeStepper stepper(0, static_cast<Real>(problem.end_time));
  stepper.add_stage(sph::make_stage("diffusion", [&] { return diffusion.stable_time_step(); },
                                    [&](Real t, Real dt) { diffusion.advance(t, dt); }));
  // Checkpoints hold the body and the run: the diffusion system keeps nothing else that changes.
  sph::RunHarness run(stepper, ctx.report, {ctx.output_dir, problem.scene, ctx.quiet, ctx.checkpoint});
  run.add_body(body, static_cast<Real>(problem.numerics.discretisation.output_interval), [&](double t) {
    for (std::size_t i = 0; i < body.n_particles(); ++i)
      C_exact[i] = static_cast<Real>(t > 0 ? problem.exact(body.position[i], t) : problem.initial(body.position[i], dp));
  });
  run.add_relation("tissue", relation);

  // Observers: C at the probe points by the linear moving-least-squares fit (libsph/core/point_probes.hpp).
  std::vector<std::string> columns;
  std::vector<Real> whole_C;
  for (std::size_t p = 0; p < problem.probes.size(); ++p) {
    std::ostringstream name;
    name << "P" << p << "(" << problem.probes[p][0] << ";" << problem.probes[p][1] << ")";
    columns.push_back(name.str() + "_concentration");
    columns.push_back(name.str() + "_exact");
  }
  run.add_time_series("observers.csv", columns, static_cast<Real>(problem.end_time / 100), [&](const sph::StepInfo& s) {
    std::vector<double> row;
    const auto C_all = sph::gather_all(body, std::span<const Real>(C), whole_C);
    for (std::size_t p = 0; p < probes.size(); ++p) {
      row.push_back(probes.sample(p, C_all));
      row.push_back(s.time > 0 ? problem.exact(problem.probes[p], s.time) : problem.initial(problem.probes[p], dp));
    }
    return row;
  });
  run.run();

  // Error against the exact solution at the end time, over the whole body.
  std::vector<Vec2> whole_x;
  std::vector<Real> whole_V;
  const auto x_all = sph::gather_all(body, std::span<const Vec2>(body.position), whole_x);
  const auto V_all = sph::gather_all(body, std::span<const Real>(body.volume), whole_V);
  const auto C_all = sph::gather_all(body, std::span<const Real>(C), whole_C);
  double error2 = 0, exact2 = 0, max_abs = 0;
  for (std::size_t i = 0; i < x_all.size(); ++i) {
    const double exact = problem.exact(x_all[i], problem.end_time);
    const double difference = C_all[i] - exact;
    error2 += V_all[i] * difference * difference;
    exact2 += V_all[i] * exact * exact;
    max_abs = std::max(max_abs, std::abs(difference));
  }
  auto& report = ctx.report;
  report.results["particle_spacing"] = dp;
  report.results["time_step"] = diffusion.stable_time_step();
  report.results["amount_change_relative"] = (total_amount() - initial_amount) / initial_amount;
  report.errors["l2_relative"] = std::sqrt(error2 / exact2);
  report.errors["max_abs"] = max_abs;
  report.reference = problem.reference;
}

class DiffusionBandScene final : public Scene {
 public:
  explicit DiffusionBandScene(DiffusionBandParameters p) : p_(std::move(p)) {}
  void declare(sph::Parameters& p) override {
    p.add("resolution", p_.resolution, "-", "particles across the box length", sph::Range::positive());
    p.add("end_time", p_.end_time, "s", "simulated time", sph::Range::positive());
    p.add("box_length", p_.box_length, "m", "box extent along x", sph::Range::positive());
    p.add("box_height", p_.box_height, "m", "box extent along y", sph::Range::positive());
    p.add("band_start", p_.band_start, "m", "lower x of the initial band", sph::Range::non_negative());
    p.add("band_end", p_.band_end, "m", "upper x of the initial band", sph::Range::positive());
    p.add("diffusivity", p_.diffusivity, "m^2/s", "isotropic diffusion coefficient D", sph::Range::positive());
    declare_numerics(p, p_.numerics);
  }
  void check() const override {
    if (!(p_.band_start < p_.band_end && p_.band_end < p_.box_length))
      throw sph::ParameterError("parameters 'band_start' and 'band_end' must satisfy 0 <= band_start < band_end < box_length");
    const double dp = p_.box_length / static_cast<double>(p_.resolution);
    const double rows = p_.box_height / dp;
    if (std::abs(rows - std::round(rows)) > 1e-9 * rows || std::round(rows) < 1)
      throw sph::ParameterError("parameter 'box_height' must be a whole number of particle spacings (box_length / resolution)");
  }
  bool checkpoints() const override { return true; }
  bool distributes() const override { return true; }
  void run(RunContext& ctx) override {
    const double a = p_.band_start, b = p_.band_end, D = p_.diffusivity;
    DiffusionProblem problem;
    problem.scene = "diffusion";
    problem.lower = Vec2(0, 0);
    problem.upper = Vec2(p_.box_length, p_.box_height);
    problem.resolution = p_.resolution;
    problem.end_time = p_.end_time;
    problem.diffusion_tensor = static_cast<Real>(D) * Mat2::Identity();
    problem.numerics = p_.numerics;
    // The particle takes the average of the step over its cell, so the initial amount is exact.
    problem.initial = [a, b](const Vec2& x, Real dp) {
      const double lo = std::max<double>(x[0] - dp / 2, a), hi = std::min<double>(x[0] + dp / 2, b);
      return std::max(0.0, hi - lo) / dp;
    };
    problem.exact = [a, b, D](const Vec2& x, double t) {
      const double s = 2 * std::sqrt(D * t);
      return 0.5 * (std::erf((x[0] - a) / s) - std::erf((x[0] - b) / s));
    };
    const double y = p_.box_height / 2;
    problem.probes = {Vec2(0.5 * (a + b), y), Vec2(b, y), Vec2(b + 0.5 * (b - a), y)};
    problem.reference = "analytic: 1/2 [erf((x-a)/(2 sqrt(D t))) - erf((x-b)/(2 sqrt(D t)))] (band in an unbounded domain)";
    run_diffusion_problem(problem, ctx);
    ctx.report.results["diffusion_length"] = std::sqrt(D * p_.end_time);
  }

 private:
  DiffusionBandParameters p_;
};

class DiffusionGaussianScene final : public Scene {
 public:
  explicit DiffusionGaussianScene(DiffusionGaussianParameters p) : p_(std::move(p)) {}
  void declare(sph::Parameters& p) override {
    p.add("resolution", p_.resolution, "-", "particles across the box", sph::Range::positive());
    p.add("end_time", p_.end_time, "s", "simulated time", sph::Range::positive());
    p.add("box_size", p_.box_size, "m", "side of the square box", sph::Range::positive());
    p.add("initial_width", p_.initial_width, "m", "standard deviation sigma0 of the initial Gaussian", sph::Range::positive());
    p.add("diffusivity_longitudinal", p_.diffusivity_longitudinal, "m^2/s", "diffusion coefficient along the direction",
          sph::Range::non_negative());
    p.add("diffusivity_transverse", p_.diffusivity_transverse, "m^2/s", "diffusion coefficient across the direction",
          sph::Range::non_negative());
    p.add("direction_angle_deg", p_.direction_angle_deg, "deg", "angle of the direction from the x axis",
          sph::Range::closed(-360, 360));
    declare_numerics(p, p_.numerics);
  }
  Mat2 tensor() const {
    const double angle = p_.direction_angle_deg * M_PI / 180;
    return sph::transversely_isotropic_tensor<2>(static_cast<Real>(p_.diffusivity_longitudinal),
                                                 static_cast<Real>(p_.diffusivity_transverse),
                                                 Vec2(std::cos(angle), std::sin(angle)));
  }
  void check() const override {
    try {
      sph::check_diffusion_tensor<2>(tensor(), "parameters 'diffusivity_longitudinal', 'diffusivity_transverse'");
    } catch (const std::invalid_argument& error) {
      throw sph::ParameterError(error.what());
    }
  }
  bool checkpoints() const override { return true; }
  bool distributes() const override { return true; }
  void run(RunContext& ctx) override {
    const double s0 = p_.initial_width;
    const Vec2 centre = Vec2::Constant(static_cast<Real>(p_.box_size / 2));
    const Eigen::Matrix2d D = tensor().cast<double>();
    DiffusionProblem problem;
    problem.scene = "diffusion-aniso";
    problem.lower = Vec2(0, 0);
    problem.upper = Vec2::Constant(static_cast<Real>(p_.box_size));
    problem.resolution = p_.resolution;
    problem.end_time = p_.end_time;
    problem.diffusion_tensor = tensor();
    problem.numerics = p_.numerics;
    auto gaussian = [s0, centre, D](const Vec2& x, double t) {
      const Eigen::Matrix2d sigma = s0 * s0 * Eigen::Matrix2d::Identity() + 2 * t * D;
      const Eigen::Vector2d r = (x - centre).cast<double>();
      return s0 * s0 / std::sqrt(sigma.determinant()) * std::exp(-0.5 * r.dot(sigma.inverse() * r));
    };
    problem.initial = [gaussian](const Vec2& x, Real) { return gaussian(x, 0); };
    problem.exact = gaussian;
    const double angle = p_.direction_angle_deg * M_PI / 180;
    const Vec2 along(std::cos(angle), std::sin(angle)), across(-std::sin(angle), std::cos(angle));
    problem.probes = {centre, centre + static_cast<Real>(2 * s0) * along, centre + static_cast<Real>(2 * s0) * across};
    problem.reference = "analytic: Gaussian with covariance sigma0^2 I + 2 D t (unbounded domain)";
    run_diffusion_problem(problem, ctx);
  }

 private:
  DiffusionGaussianParameters p_;
};

}  // namespace

std::unique_ptr<Scene> make_diffusion_band_scene(DiffusionBandParameters parameters) {
  return std::make_unique<DiffusionBandScene>(std::move(parameters));
}

std::unique_ptr<Scene> make_diffusion_gaussian_scene(DiffusionGaussianParameters parameters) {
  return std::make_unique<DiffusionGaussianScene>(std::move(parameters));
}

}  // namespace cardiosph
