// The active myocardium cube (the SPHinXsys muscle-activation case, Zhang et al. 2021, CMAME
// 381:113847): a unit cube of myocardium, fibres along x, on a holder of thickness 0.16 behind
// x = 0 whose particles keep their x (they slide in y and z). Isotropic Holzapfel-Ogden term
// a = 0.059, b = 8.023 with the volumetric penalty K = 450, rho = 1 (nondimensional units). The
// active tension is prescribed: T_a(X, t) = T_max X / L min(t / t_ramp, 1), growing linearly along x
// and in time up to t_ramp = 1, then held (SPHinXsys writes it with the opposite sign, -15 x t,
// stretching the cube; T_max > 0 here contracts it along the fibre). A light velocity damping lets
// the held state settle; at the end the net nodal force is compared with the force of the active
// stress alone (results.equilibrium_residual), and the free corners at x = 1 are observed.
#include <cmath>

#include "apps/scenes/electromechanics/em_scenes.hpp"
#include "apps/scenes/solid/solid_run.hpp"
#include "libsph/core/distribution.hpp"
#include "libsph/core/point_probes.hpp"
#include "geometry/lattice.hpp"
#include "libsph/core/parallel.hpp"

namespace cardiosph {
namespace {

using sph::Real;
using Vec3 = sph::Vec<3>;

enum class Preset { standard, sphinxsys };

struct MyocardiumCubeParameters {
  Preset preset = Preset::standard;
  long resolution = 25;        ///< particles across the unit cube
  double end_time = 3;
  double max_tension = 5;      ///< T_max at x = L
  double ramp_time = 1;
  double holder_length = 0.16;
  double a = 0.059, b = 8.023;
  double bulk_modulus = 450;
  double density = 1;
  double damping_rate = 4;     ///< [1/time]
  SolidSceneNumerics numerics;
};

class MyocardiumCubeScene final : public Scene {
 public:
  MyocardiumCubeScene() { p_.numerics.discretisation.output_interval = 0.1; }

  void declare(sph::Parameters& p) override {
    // The SPHinXsys case test_3d_muscle_activation (../shared/PARITY.md): its kernel (Wendland C2,
    // h = 1.15 dp), its tension -15 X min(t, 1) (stretching), no damping, its solid scheme (no
    // hourglass control, pair viscosity 0.25, the acoustic step of the small-strain modulus), end
    // time 1.2, no particle output between the first and last state.
    p.add_preset<Preset>("preset", p_.preset,
                         {{"default", Preset::standard},
                          {"sphinxsys", Preset::sphinxsys,
                           {{"resolution", "25"},
                            {"end_time", "1.2"},
                            {"max_tension", "-15"},
                            {"ramp_time", "1"},
                            {"damping_rate", "0"},
                            {"kernel", "wendland_c2"},
                            {"smoothing_length_ratio", "1.15"},
                            {"acoustic_cfl", "0.6"},
                            {"hourglass_coefficient", "0"},
                            {"artificial_viscosity", "0.25"},
                            {"tangent_time_step", "false"},
                            {"output_interval", "0"}}}},
                         "default: this scene's settings; sphinxsys: the SPHinXsys muscle-activation case");
    p.add("resolution", p_.resolution, "-", "particles across the unit cube", sph::Range::closed(3, 200));
    p.add("end_time", p_.end_time, "-", "simulated time", sph::Range::positive());
    p.add("max_tension", p_.max_tension, "-", "T_max: active tension at x = 1 once ramped (> 0 contracts)", sph::Range::any());
    p.add("ramp_time", p_.ramp_time, "-", "time over which the tension grows linearly", sph::Range::positive());
    p.add("holder_length", p_.holder_length, "-", "thickness of the sliding holder behind x = 0 (rounded up to whole spacings)",
          sph::Range::positive());
    p.add("a", p_.a, "-", "Holzapfel-Ogden isotropic stiffness a", sph::Range::positive());
    p.add("b", p_.b, "-", "Holzapfel-Ogden isotropic exponent b", sph::Range::positive());
    p.add("bulk_modulus", p_.bulk_modulus, "-", "K of the volumetric penalty", sph::Range::positive());
    p.add("density", p_.density, "-", "rho0", sph::Range::positive());
    p.add("damping_rate", p_.damping_rate, "1/time", "velocity damping c (settles the held state)", sph::Range::non_negative());
    declare_solid_numerics(p, p_.numerics, "-");
  }

  void check() const override {
    if (p_.ramp_time > p_.end_time) throw sph::ParameterError("parameter 'ramp_time' must not exceed 'end_time'");
  }

  bool checkpoints() const override { return true; }  // nothing kept outside the body
  bool distributes() const override { return true; }
  void run(RunContext& ctx) override {
    const Real dp = Real(1) / Real(p_.resolution);
    const Real h = Real(p_.numerics.discretisation.smoothing_length_ratio) * dp;
    const long holder_layers = std::max(1L, long(std::ceil(p_.holder_length / double(dp) - 1e-9)));
    auto body = geometry::lattice_box<3>("cube", Vec3(-Real(holder_layers) * dp, 0, 0), Vec3(1, 1, 1), dp);
    const auto kernel = sph::make_kernel<3>(p_.numerics.discretisation.kernel);
    // The corner probes lie on the whole body (reference configuration); a distributed run then
    // keeps this rank's part with one support of ghosts.
    const std::vector<Vec3> corners{{1, 0, 0}, {1, 1, 0}, {1, 0, 1}, {1, 1, 1}};
    const sph::PointProbes<3> corner_probes(corners, body.position, body.volume, kernel, h);
    sph::distribute(body, std::visit([h]<class K>(const K&) { return K::support_radius(h); }, kernel));
    const auto relation = sph::build_inner_relation<3>(body, kernel, h);

    sph::HolzapfelOgden<3> law;
    law.a = Real(p_.a);
    law.b = Real(p_.b);
    law.bulk_modulus = Real(p_.bulk_modulus);
    sph::ElasticSolid<3>::Settings settings;
    settings.material = law;
    settings.density = Real(p_.density);
    settings.damping_rate = Real(p_.damping_rate);
    settings.fibre = Vec3::UnitX();
    settings.sheet = Vec3::UnitY();
    settings.active_stress = true;
    settings.numerics = p_.numerics.solid;
    sph::ElasticSolid<3> solid(body, relation, settings);
    solid.slide(select_particles<3>(body, [](const Vec3& X) { return X[0] < 0; }), 0);

    // T_a(X, t) = T_max X max(0, min(t / t_ramp, 1)), zero in the holder; set before each step.
    const auto X = body.field(solid.reference_position_field());
    auto T = body.field(solid.active_tension_field());
    auto set_tension = [&](double t) {
      const double ramp = std::clamp(t / p_.ramp_time, 0.0, 1.0);
      sph::parallel_for(T.size(), [&](std::size_t i) { T[i] = X[i][0] > 0 ? Real(p_.max_tension * X[i][0] * ramp) : Real(0); });
    };

    std::vector<std::string> header;
    for (int c = 0; c < 4; ++c)
      for (const char* q : {"ux", "uy", "uz"}) header.push_back("corner" + std::to_string(c) + "_" + q);
    auto corner_displacements = [&] {
      auto u = material_point_positions<3>(corner_probes, solid);
      for (std::size_t c = 0; c < corners.size(); ++c) u[c] -= corners[c];
      return u;
    };

    SolidRunPlan plan("myocardium-cube", p_.end_time, p_.numerics.discretisation.output_interval);
    plan.observer_columns = header;
    plan.observers = [&](const sph::StepInfo&) {
      std::vector<double> row;
      for (const auto& u : corner_displacements()) row.insert(row.end(), {u[0], u[1], u[2]});
      return row;
    };
    // The tension of the step [t, t + dt] is taken at its midpoint, where the stress is evaluated.
    plan.before_step = [&](sph::Real t, sph::Real dt) { set_tension(double(t + dt / 2)); };
    run_solid<3>(solid, relation, plan, ctx);

    set_tension(p_.end_time);
    const auto residual = solid.equilibrium_residual(Real(p_.end_time));
    const auto u = corner_displacements();
    auto& r = ctx.report;
    r.results["particle_spacing"] = dp;
    r.results["holder_layers"] = holder_layers;
    r.results["corner_displacement"] = {u[3][0], u[3][1], u[3][2]};  // the corner (1, 1, 1)
    double spread = 0;
    for (const auto& v : u) spread = std::max<double>(spread, (v.cwiseAbs() - u[3].cwiseAbs()).norm());
    r.results["corner_symmetry_difference"] = spread;
    r.results["equilibrium_residual"] = residual.active > 0 ? residual.net / residual.active : 0.0;
    r.results["residual_force_norm"] = residual.net;
    r.results["active_force_norm"] = residual.active;
    r.errors["equilibrium_residual"] = residual.active > 0 ? residual.net / residual.active : 0.0;
    r.reference = "converged solution of this scene over resolutions (validation test); equilibrium: net nodal force / "
                  "active-stress force at the end";
  }

 private:
  MyocardiumCubeParameters p_;
};

}  // namespace

std::unique_ptr<Scene> make_myocardium_cube_scene() { return std::make_unique<MyocardiumCubeScene>(); }

}  // namespace cardiosph
