#include <cmath>
#include <vector>

#include "apps/scenes/solid/solid_scenes.hpp"
#include "geometry/lattice.hpp"

namespace cardiosph {
namespace {

using sph::Real;
using Vec2 = sph::Vec<2>;

class OscillatingBeamScene final : public Scene {
 public:
  explicit OscillatingBeamScene(OscillatingBeamParameters p) : p_(std::move(p)) {}

  void declare(sph::Parameters& p) override {
    p.add("resolution", p_.resolution, "-", "particles across the thickness H", sph::Range::closed(2, 1000));
    p.add("end_time", p_.end_time, "s", "simulated time", sph::Range::positive());
    p.add("length", p_.length, "m", "free length L", sph::Range::positive());
    p.add("thickness", p_.thickness, "m", "thickness H", sph::Range::positive());
    p.add("clamp_length", p_.clamp_length, "m", "length of the clamped part", sph::Range::positive());
    p.add("density", p_.density, "kg/m^3", "reference density", sph::Range::positive());
    p.add("young_modulus", p_.young_modulus, "Pa", "Young's modulus E", sph::Range::positive());
    p.add("poisson_ratio", p_.poisson_ratio, "-", "Poisson's ratio", {-1, 0.5, true, true});
    p.add("mode", p_.mode, "-", "bending mode excited and measured: 1 (k L = 1.8751) or 2 (k L = 4.6941)", sph::Range::closed(1, 2));
    p.add("velocity_factor", p_.velocity_factor, "-", "vf: initial tip speed over c0 = sqrt(K / rho)", sph::Range::any());
    p.add_choice("material", p_.material, {"neo_hookean", "saint_venant_kirchhoff"}, "constitutive law");
    declare_clamp(p, p_.clamp);
    declare_solid_numerics(p, p_.numerics, "s");
  }

  void check() const override {
    const double dp = p_.thickness / static_cast<double>(p_.resolution);
    check_whole_spacings(p_.length, dp, "length");
    check_whole_spacings(p_.clamp_length, dp, "clamp_length");
  }

  /// k L of the clamped-free beam's bending mode: the roots of 1 + cos(kL) cosh(kL) = 0.
  double mode_wavenumber() const { return p_.mode == 1 ? 1.8751 : 4.6941; }

  /// Thin-plate (plane-strain) angular frequency of the mode, Gray et al. 2001 (first mode).
  double reference_omega() const {
    const double k = mode_wavenumber();
    return std::sqrt(p_.young_modulus * p_.thickness * p_.thickness * std::pow(k, 4) /
                     (12 * p_.density * (1 - p_.poisson_ratio * p_.poisson_ratio) * std::pow(p_.length, 4)));
  }

  bool checkpoints() const override { return true; }
  void run(RunContext& ctx) override {
    const Real dp = static_cast<Real>(p_.thickness / static_cast<double>(p_.resolution));
    const Real h = static_cast<Real>(p_.numerics.discretisation.smoothing_length_ratio) * dp;
    const Real L = static_cast<Real>(p_.length), H = static_cast<Real>(p_.thickness);
    auto body = geometry::lattice_box<2>("plate", Vec2(-static_cast<Real>(p_.clamp_length), -H / 2), Vec2(L, H / 2), dp);
    const auto kernel = sph::make_kernel<2>(p_.numerics.discretisation.kernel);
    const auto relation = sph::build_inner_relation<2>(body.position, kernel, h);

    sph::ElasticSolid<2>::Settings settings;
    Real lambda, mu;
    sph::lame_constants(static_cast<Real>(p_.young_modulus), static_cast<Real>(p_.poisson_ratio), lambda, mu);
    if (p_.material == "neo_hookean") settings.material = sph::NeoHookean<2>{lambda, mu};
    else settings.material = sph::SaintVenantKirchhoff<2>{lambda, mu};
    settings.density = static_cast<Real>(p_.density);
    settings.numerics = p_.numerics.solid;
    sph::ElasticSolid<2> solid(body, relation, settings);
    hold_face_x0<2>(solid, p_.clamp);

    // Initial velocity of the bending mode (Gray et al. 2001, eq. 37, for the first), x scaled by L.
    const double k = mode_wavenumber();
    const double M = std::sin(k) + std::sinh(k), N = std::cos(k) + std::cosh(k);
    const double Q = 2 * (std::cos(k) * std::sinh(k) - std::sin(k) * std::cosh(k));
    const double c0 = std::sqrt(sph::bulk_modulus_of(Real(p_.young_modulus), Real(p_.poisson_ratio)) / p_.density);
    auto v = body.field(solid.velocity_field());
    for (std::size_t i = 0; i < body.n_particles(); ++i) {
      const double x = body.position[i][0] / p_.length;
      if (x <= 0) continue;
      const double shape = (M * (std::cos(k * x) - std::cosh(k * x)) - N * (std::sin(k * x) - std::sinh(k * x))) / Q;
      v[i] = Vec2(0, static_cast<Real>(p_.velocity_factor * c0 * shape));
    }

    // Tip deflection: the mean vertical displacement of the last column, every step.
    const auto tip = select_particles<2>(body, [&](const Vec2& X) { return X[0] > L - dp; });
    auto tip_deflection = [&] {
      double sum = 0;
      for (const auto i : tip) sum += body.position[i][1] - body.field(solid.reference_position_field())[i][1];
      return sum / static_cast<double>(tip.size());
    };
    sph::RunRecord record;
    std::vector<double>& crossings = record.series("crossings");  // times where the tip deflection changes sign
    double &previous_time = record.value("previous_time"), &previous_deflection = record.value("previous_deflection"),
           &amplitude = record.value("amplitude");

    SolidRunPlan plan("oscillating-beam", p_.end_time, p_.numerics.discretisation.output_interval);
    plan.observer_columns = {"tip_deflection"};
    plan.observers = [&](const sph::StepInfo&) { return std::vector<double>{tip_deflection()}; };
    plan.every_step = [&](const sph::StepInfo& s) {
      const double d = tip_deflection();
      amplitude = std::max(amplitude, std::abs(d));
      if (previous_time > 0 && (d > 0) != (previous_deflection > 0))
        crossings.push_back(previous_time + (s.time - previous_time) * previous_deflection / (previous_deflection - d));
      previous_time = s.time;
      previous_deflection = d;
    };
    plan.keep("record", record);
    const auto summary = run_solid<2>(solid, relation, plan, ctx);

    const double reference_period = 2 * M_PI / reference_omega();
    auto& report = ctx.report;
    report.results["reference_period_s"] = reference_period;
    report.results["amplitude_m"] = amplitude;
    report.results["energy_drift_relative"] = summary.max_energy_drift;
    report.results["particle_spacing"] = dp;
    report.results["half_periods_measured"] = crossings.size() > 1 ? double(crossings.size() - 1) : 0.0;
    report.reference = p_.mode == 1 ? "thin-plate first mode, omega^2 = E H^2 k^4 / (12 rho (1 - nu^2) L^4), k L = 1.875 (Gray et al. 2001)"
                                    : "thin-plate second mode, omega^2 = E H^2 k^4 / (12 rho (1 - nu^2) L^4), k L = 4.694";
    if (crossings.size() >= 2) {
      const double period = 2 * (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
      report.results["period_s"] = period;
      report.errors["period_relative"] = std::abs(period - reference_period) / reference_period;
    } else {
      throw std::runtime_error("oscillating-beam: fewer than two zero crossings of the tip; run longer (end_time)");
    }
  }

 private:
  OscillatingBeamParameters p_;
};

}  // namespace

std::unique_ptr<Scene> make_oscillating_beam_scene(OscillatingBeamParameters parameters) {
  return std::make_unique<OscillatingBeamScene>(std::move(parameters));
}

}  // namespace cardiosph
