// A unit cube of Holzapfel-Ogden myocardium (fibres along x, sheets along y; Holzapfel & Ogden
// 2009 constants, kPa) driven through four homogeneous deformations by prescribing
// x = c + F(t) (X - c) on a boundary layer; the free interior must follow with the Cauchy stress of
// the law at the final F:
//   fibre_stretch  F = diag(l, l^-1/2, l^-1/2)     sheet_stretch  F = diag(l^-1/2, l, l^-1/2)
//   shear_fs       F = I + g f (x) s               shear_sf       F = I + g s (x) f
// The deformation is ramped smoothly, s(t) = t/T - sin(2 pi t / T) / (2 pi), and held, with
// velocity damping, so that the interior is at rest at the end.
#include <cmath>

#include "apps/scenes/solid/solid_scenes.hpp"
#include "geometry/lattice.hpp"
#include "libsph/io/time_series.hpp"

namespace cardiosph {
namespace {

using sph::Real;
using Vec3 = sph::Vec<3>;
using Mat3 = sph::Mat<3>;

/// F at ramp fraction s and its derivative with respect to s.
struct Mode {
  std::string name;
  std::function<Mat3(double)> F;
  std::function<Mat3(double)> dF;
};

std::vector<Mode> modes(double stretch, double shear) {
  auto uniaxial = [stretch](int axis) {
    return Mode{axis == 0 ? "fibre_stretch" : "sheet_stretch",
                [=](double s) {
                  const double l = 1 + s * (stretch - 1);
                  Mat3 F = Mat3::Identity() / static_cast<Real>(std::sqrt(l));
                  F(axis, axis) = static_cast<Real>(l);
                  return F;
                },
                [=](double s) {
                  const double l = 1 + s * (stretch - 1);
                  Mat3 dF = Mat3::Identity() * static_cast<Real>(-0.5 * std::pow(l, -1.5) * (stretch - 1));
                  dF(axis, axis) = static_cast<Real>(stretch - 1);
                  return dF;
                }};
  };
  auto simple_shear = [shear](const std::string& name, int row, int column) {
    Mat3 direction = Mat3::Zero();
    direction(row, column) = 1;
    return Mode{name, [=](double s) { return Mat3(Mat3::Identity() + static_cast<Real>(s * shear) * direction); },
                [=](double) { return Mat3(static_cast<Real>(shear) * direction); }};
  };
  return {uniaxial(0), uniaxial(1), simple_shear("shear_fs", 0, 1), simple_shear("shear_sf", 1, 0)};
}

class HomogeneousDeformationScene final : public Scene {
 public:
  explicit HomogeneousDeformationScene(HomogeneousDeformationParameters p) : p_(std::move(p)) {}

  void declare(sph::Parameters& p) override {
    p.add("resolution", p_.resolution, "-", "particles across the unit cube", sph::Range::closed(4, 200));
    p.add("end_time", p_.end_time, "ms", "simulated time of each mode", sph::Range::positive());
    p.add("ramp_time", p_.ramp_time, "ms", "duration of the smooth ramp to the final deformation", sph::Range::positive());
    p.add("stretch", p_.stretch, "-", "final stretch of the isochoric uniaxial modes", sph::Range::closed(0.5, 2));
    p.add("shear", p_.shear, "-", "final amount of the simple shears", sph::Range::closed(-1, 1));
    p.add("bulk_modulus", p_.bulk_modulus, "kPa", "K of the volumetric penalty", sph::Range::positive());
    p.add("density", p_.density, "mg/mm^3", "reference density", sph::Range::positive());
    p.add("damping_rate", p_.damping_rate, "1/ms", "velocity damping rate", sph::Range::non_negative());
    p.add("boundary_layers", p_.boundary_layers, "supports", "thickness of the driven layer in kernel supports (2h)",
          sph::Range::positive());
    declare_solid_numerics(p, p_.numerics, "ms");
  }

  void check() const override {
    if (p_.ramp_time > p_.end_time) throw sph::ParameterError("parameter 'ramp_time' must not exceed 'end_time'");
    const double support = 2 * p_.numerics.discretisation.smoothing_length_ratio / static_cast<double>(p_.resolution);
    if ((p_.boundary_layers + 1) * support >= 0.5)
      throw sph::ParameterError("parameters 'resolution' and 'boundary_layers' leave no measured interior: need (boundary_layers + 1) * 2h < 0.5");
  }

  void run(RunContext& ctx) override {
    const Real dp = Real(1) / static_cast<Real>(p_.resolution);
    const Real h = static_cast<Real>(p_.numerics.discretisation.smoothing_length_ratio) * dp;
    const auto kernel = sph::make_kernel<3>(p_.numerics.discretisation.kernel);
    const Real driven_depth = static_cast<Real>(p_.boundary_layers) * 2 * h;
    const Real measured_depth = driven_depth + 2 * h;
    auto depth = [](const Vec3& X) { return std::min(X.minCoeff(), 1 - X.maxCoeff()); };
    const Vec3 centre = Vec3::Constant(Real(0.5));
    const double T = p_.ramp_time;
    auto ramp = [T](double t) { return t < T ? t / T - std::sin(2 * M_PI * t / T) / (2 * M_PI) : 1.0; };
    auto ramp_rate = [T](double t) { return t < T ? (1 - std::cos(2 * M_PI * t / T)) / T : 0.0; };
    const auto law = sph::holzapfel_ogden_2009_kpa<3>(static_cast<Real>(p_.bulk_modulus));

    sph::TimeSeriesCsv table(ctx.output_dir / "stress.csv",
                             {"mode", "sigma_xx", "sigma_yy", "sigma_zz", "sigma_xy", "exact_xx", "exact_yy", "exact_zz", "exact_xy", "error_relative"});
    double worst = 0;
    std::size_t steps = 0;
    int mode_index = 0;
    for (const auto& mode : modes(p_.stretch, p_.shear)) {
      auto body = geometry::lattice_box<3>(mode.name, Vec3::Zero(), Vec3::Ones(), dp);
      const auto relation = sph::build_inner_relation<3>(body.position, kernel, h);
      sph::ElasticSolid<3>::Settings settings;
      settings.material = law;
      settings.density = static_cast<Real>(p_.density);
      settings.damping_rate = static_cast<Real>(p_.damping_rate);
      settings.numerics = p_.numerics.solid;
      sph::ElasticSolid<3> solid(body, relation, settings);
      solid.prescribe_motion(
          select_particles<3>(body, [&](const Vec3& X) { return depth(X) < driven_depth; }),
          [&](const Vec3& X, Real t) { return Vec3(centre + mode.F(ramp(t)) * (X - centre)); },
          [&](const Vec3& X, Real t) { return Vec3(ramp_rate(t) * (mode.dF(ramp(t)) * (X - centre))); });

      SolidRunPlan plan("homogeneous-deformation " + mode.name, p_.end_time, p_.numerics.discretisation.output_interval);
      steps += run_solid<3>(solid, relation, plan, ctx).steps;

      // Interior stress against the law at the final F, sigma = J^-1 F S F^T.
      solid.update_output_fields();
      const Mat3 F = mode.F(1);
      const Mat3 exact = sph::cauchy_stress<3>(law, F, Vec3::UnitX().eval(), Vec3::UnitY().eval());
      double mode_error = 0;
      Mat3 sum = Mat3::Zero();
      std::size_t count = 0;
      const auto X = body.field(solid.reference_position_field());
      for (std::size_t i = 0; i < body.n_particles(); ++i) {
        if (depth(X[i]) < measured_depth) continue;
        const Mat3 sigma = solid.cauchy_stress_of(i);
        mode_error = std::max(mode_error, double((sigma - exact).norm() / exact.norm()));
        sum += sigma;
        ++count;
      }
      const Mat3 mean = sum / static_cast<Real>(count);
      table.record({double(mode_index++), mean(0, 0), mean(1, 1), mean(2, 2), mean(0, 1), exact(0, 0), exact(1, 1),
                    exact(2, 2), exact(0, 1), mode_error});
      ctx.report.errors["stress_relative_" + mode.name] = mode_error;
      ctx.report.results["measured_particles"] = count;
      worst = std::max(worst, mode_error);
    }
    ctx.report.steps = steps;
    ctx.report.simulated_time = 4 * p_.end_time;
    ctx.report.errors["stress_relative"] = worst;
    ctx.report.results["particle_spacing_mm"] = dp;
    ctx.report.reference = "closed-form Cauchy stress of the Holzapfel-Ogden law at the imposed homogeneous F "
                           "(max over interior particles of |sigma - sigma_exact| / |sigma_exact|; stress.csv: modes 0-3 = "
                           "fibre_stretch, sheet_stretch, shear_fs, shear_sf)";
  }

 private:
  HomogeneousDeformationParameters p_;
};

}  // namespace

std::unique_ptr<Scene> make_homogeneous_deformation_scene(HomogeneousDeformationParameters parameters) {
  return std::make_unique<HomogeneousDeformationScene>(std::move(parameters));
}

}  // namespace cardiosph
