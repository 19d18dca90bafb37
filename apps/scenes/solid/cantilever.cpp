// The passive myocardium cantilever and the twisting column (3D, SI units).
#include <cmath>
#include <vector>

#include "apps/scenes/solid/solid_scenes.hpp"
#include "geometry/lattice.hpp"
#include "libsph/core/point_probes.hpp"

namespace cardiosph {
namespace {

using sph::Real;
using Vec3 = sph::Vec<3>;

void declare_elastic_constants(sph::Parameters& p, double& density, double& young, double& poisson) {
  p.add("density", density, "kg/m^3", "reference density", sph::Range::positive());
  p.add("young_modulus", young, "Pa", "Young's modulus E", sph::Range::positive());
  p.add("poisson_ratio", poisson, "-", "Poisson's ratio (sets the bulk modulus K = E / (3 (1 - 2 nu)))",
        {-1, 0.5, true, true});
}

class CantileverScene final : public Scene {
 public:
  explicit CantileverScene(CantileverParameters p) : p_(std::move(p)) {}

  void declare(sph::Parameters& p) override {
    p.add("resolution", p_.resolution, "-", "particles across the thickness", sph::Range::closed(2, 200));
    p.add("end_time", p_.end_time, "s", "simulated time", sph::Range::positive());
    p.add("length", p_.length, "m", "free length", sph::Range::positive());
    p.add("thickness", p_.thickness, "m", "side of the square section", sph::Range::positive());
    p.add("holder_length", p_.holder_length, "m", "length of the clamped holder", sph::Range::positive());
    declare_elastic_constants(p, p_.density, p_.young_modulus, p_.poisson_ratio);
    p.add("exponent", p_.exponent, "-", "b of the isotropic exponential law W = a/(2b) (exp(b (I1 - 3)) - 1) - a ln J + U(J)",
          sph::Range::positive());
    p.add("kick_y", p_.kick_y, "m/s", "initial y velocity of the free part", sph::Range::any());
    p.add("kick_z", p_.kick_z, "m/s", "initial z velocity of the free part", sph::Range::any());
    declare_solid_numerics(p, p_.numerics, "s");
  }

  void check() const override {
    const double dp = p_.thickness / static_cast<double>(p_.resolution);
    check_whole_spacings(p_.length, dp, "length");
    check_whole_spacings(p_.holder_length, dp, "holder_length");
  }

  bool checkpoints() const override { return true; }
  void run(RunContext& ctx) override {
    const Real T = static_cast<Real>(p_.thickness), L = static_cast<Real>(p_.length);
    const Real dp = T / static_cast<Real>(p_.resolution);
    const Real h = static_cast<Real>(p_.numerics.discretisation.smoothing_length_ratio) * dp;
    auto body = geometry::lattice_box<3>("beam", Vec3(-static_cast<Real>(p_.holder_length), 0, 0), Vec3(L, T, T), dp);
    const auto kernel = sph::make_kernel<3>(p_.numerics.discretisation.kernel);
    const auto relation = sph::build_inner_relation<3>(body.position, kernel, h);

    // Isotropic exponential law: the Holzapfel-Ogden law with only its isotropic term,
    // a = E / (2 (1 + nu)) (the small-strain shear modulus), K = E / (3 (1 - 2 nu)).
    const Real E = static_cast<Real>(p_.young_modulus), nu = static_cast<Real>(p_.poisson_ratio);
    sph::HolzapfelOgden<3> law;
    law.a = E / (2 * (1 + nu));
    law.b = static_cast<Real>(p_.exponent);
    law.bulk_modulus = sph::bulk_modulus_of(E, nu);
    sph::ElasticSolid<3>::Settings settings;
    settings.material = law;
    settings.density = static_cast<Real>(p_.density);
    settings.numerics = p_.numerics.solid;
    sph::ElasticSolid<3> solid(body, relation, settings);
    solid.clamp(select_particles<3>(body, [](const Vec3& X) { return X[0] < 0; }));
    auto v = body.field(solid.velocity_field());
    const Vec3 kick(0, static_cast<Real>(p_.kick_y), static_cast<Real>(p_.kick_z));
    for (std::size_t i = 0; i < body.n_particles(); ++i)
      if (body.position[i][0] > 0) v[i] = kick;

    const Vec3 tip_point(L, T / 2, T / 2);
    const sph::PointProbes<3> tip_probe({tip_point}, body.position, body.volume, kernel, h);  // reference configuration
    auto tip_position = [&] { return material_point_positions<3>(tip_probe, solid)[0]; };
    sph::RunRecord record;
    double& max_deflection = record.value("max_deflection");
    SolidRunPlan plan("cantilever", p_.end_time, p_.numerics.discretisation.output_interval);
    plan.observer_columns = {"tip_x", "tip_y", "tip_z"};
    plan.observers = [&](const sph::StepInfo&) {
      const Vec3 tip = tip_position();
      max_deflection = std::max(max_deflection, double((tip - tip_point).tail<2>().norm()));
      return std::vector<double>{tip[0], tip[1], tip[2]};
    };
    plan.keep("record", record);
    const auto summary = run_solid<3>(solid, relation, plan, ctx);
    const Vec3 tip = tip_position();
    auto& report = ctx.report;
    report.results["particle_spacing"] = dp;
    report.results["tip_max_deflection_m"] = max_deflection;
    report.results["tip_final_y_m"] = tip[1];
    report.results["tip_final_z_m"] = tip[2];
    report.results["energy_drift_relative"] = summary.max_energy_drift;
  }

 private:
  CantileverParameters p_;
};

class TwistingColumnScene final : public Scene {
 public:
  explicit TwistingColumnScene(TwistingColumnParameters p) : p_(std::move(p)) {}

  void declare(sph::Parameters& p) override {
    p.add("resolution", p_.resolution, "-", "particles across the width", sph::Range::closed(2, 200));
    p.add("end_time", p_.end_time, "s", "simulated time", sph::Range::positive());
    p.add("height", p_.height, "m", "column height above the clamped base", sph::Range::positive());
    p.add("width", p_.width, "m", "side of the square section", sph::Range::positive());
    declare_elastic_constants(p, p_.density, p_.young_modulus, p_.poisson_ratio);
    p.add("angular_velocity", p_.angular_velocity, "rad/s", "omega0: initial twist rate omega0 sin(pi z / (2 height))",
          sph::Range::any());
    declare_solid_numerics(p, p_.numerics, "s");
  }

  void check() const override {
    check_whole_spacings(p_.height, p_.width / static_cast<double>(p_.resolution), "height");
  }

  bool checkpoints() const override { return true; }
  void run(RunContext& ctx) override {
    const Real W = static_cast<Real>(p_.width), H = static_cast<Real>(p_.height);
    const Real dp = W / static_cast<Real>(p_.resolution);
    const Real h = static_cast<Real>(p_.numerics.discretisation.smoothing_length_ratio) * dp;
    // Three clamped layers below z = 0 hold the base.
    auto body = geometry::lattice_box<3>("column", Vec3(-W / 2, -W / 2, -3 * dp), Vec3(W / 2, W / 2, H), dp);
    const auto kernel = sph::make_kernel<3>(p_.numerics.discretisation.kernel);
    const auto relation = sph::build_inner_relation<3>(body.position, kernel, h);
    Real lambda, mu;
    sph::lame_constants(static_cast<Real>(p_.young_modulus), static_cast<Real>(p_.poisson_ratio), lambda, mu);
    sph::ElasticSolid<3>::Settings settings;
    settings.material = sph::NeoHookean<3>{lambda, mu};
    settings.density = static_cast<Real>(p_.density);
    settings.numerics = p_.numerics.solid;
    sph::ElasticSolid<3> solid(body, relation, settings);
    solid.clamp(select_particles<3>(body, [](const Vec3& X) { return X[2] < 0; }));
    // Initial velocity: rigid rotation about the column axis at a rate growing with height
    // (the twisting column of Aguirre, Gil, Bonet & Arranz Carreno 2014, JCP 259:672).
    auto v = body.field(solid.velocity_field());
    for (std::size_t i = 0; i < body.n_particles(); ++i) {
      const Vec3& X = body.position[i];
      if (X[2] <= 0) continue;
      const Real omega = static_cast<Real>(p_.angular_velocity) * std::sin(sph::pi * X[2] / (2 * H));
      v[i] = omega * Vec3(-X[1], X[0], 0);
    }
    // Twist of the top layer: the mean rotation about z of its particles (unwrapped in time).
    const auto top = select_particles<3>(body, [&](const Vec3& X) { return X[2] > H - dp; });
    const auto X0 = body.field(solid.reference_position_field());
    sph::RunRecord record;
    double &twist = record.value("twist"), &max_twist = record.value("max_twist"), &max_measure = record.value("max_measure");
    auto top_rotation = [&] {
      double cross = 0, dot = 0;
      for (const auto i : top) {
        const Vec3& x = body.position[i];
        cross += X0[i][0] * x[1] - X0[i][1] * x[0];
        dot += X0[i][0] * x[0] + X0[i][1] * x[1];
      }
      return std::atan2(cross, dot);
    };
    SolidRunPlan plan("twisting-column", p_.end_time, p_.numerics.discretisation.output_interval);
    plan.every_step = [&](const sph::StepInfo&) {
      const double angle = top_rotation();
      twist += std::remainder(angle - std::remainder(twist, 2 * M_PI), 2 * M_PI);
      max_twist = std::max(max_twist, std::abs(twist));
    };
    plan.observer_columns = {"top_twist_deg", "hourglass_measure"};
    plan.observers = [&](const sph::StepInfo&) {
      const double measure = solid.hourglass_measure();
      max_measure = std::max(max_measure, measure);
      return std::vector<double>{twist * 180 / M_PI, measure};
    };
    plan.keep("record", record);
    const auto summary = run_solid<3>(solid, relation, plan, ctx);
    auto& report = ctx.report;
    report.results["particle_spacing"] = dp;
    report.results["max_twist_deg"] = max_twist * 180 / M_PI;
    report.results["hourglass_measure_max"] = max_measure;
    report.results["hourglass_measure_final"] = solid.hourglass_measure();
    report.results["energy_drift_relative"] = summary.max_energy_drift;
  }

 private:
  TwistingColumnParameters p_;
};

}  // namespace

std::unique_ptr<Scene> make_cantilever_scene(CantileverParameters parameters) {
  return std::make_unique<CantileverScene>(std::move(parameters));
}

std::unique_ptr<Scene> make_twisting_column_scene(TwistingColumnParameters parameters) {
  return std::make_unique<TwistingColumnScene>(std::move(parameters));
}

}  // namespace cardiosph
