// Pieces of the excitation-contraction coupling: the active tension ODE against its closed-form
// solution, the pulled-back conduction tensor against F^-1 D(F f0) F^-T, the active stress of the
// solid against T_a f (x) f, and the cavity volume of the LV ellipsoid against the closed form and
// under an affine motion.

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include <nlohmann/json.hpp>

#include "apps/scenes/electromechanics/heart_output.hpp"
#include "cardio/active_tension.hpp"
#include "cardio/cavity.hpp"
#include "cardio/electromechanics.hpp"
#include "cardio/heart_geometry.hpp"
#include "geometry/heart_meshes.hpp"
#include "geometry/lattice.hpp"
#include "libsph/core/neighbour_relation.hpp"

namespace {

using sph::Real;
using Vec3 = sph::Vec<3>;
using Mat3 = sph::Mat<3>;

sph::ParticleSet<3> one_particle_with_potential(Real V, sph::FieldHandle<Real>& handle) {
  sph::ParticleSet<3> set("cell", {Vec3::Zero()}, {Real(1)});
  handle = set.register_field<Real>("transmembrane_potential", V);
  return set;
}

TEST(ActiveTension, HeldPotentialFollowsTheExactExponentialApproachAtAnyStep) {
  sph::FieldHandle<Real> V;
  auto set = one_particle_with_potential(20, V);
  cardio::ActiveTensionSettings s;  // V_r = -80, k_a = 0.001 kPa/mV
  cardio::ActiveTension<3> tension(set, V, s);
  const double target = s.k_a * (20 - s.rest_potential), rate = s.rate(20);
  double t = 0;
  for (const double dt : {0.1, 5.0, 0.7, 20.0}) {
    tension.advance(Real(t), Real(dt));
    t += dt;
    const double exact = target * (1 - std::exp(-rate * t));
    EXPECT_NEAR(tension.tension()[0], exact, 1e-12 * target) << "t = " << t;
  }
  // Interpolation within the last step is linear between its ends.
  std::vector<Real> mid(1);
  tension.interpolate(Real(0.5), mid);
  const double before = target * (1 - std::exp(-rate * (t - 20))), after = tension.tension()[0];
  EXPECT_NEAR(mid[0], 0.5 * (before + after), 1e-12);
}

TEST(ActiveTension, StaysTensileBelowRestUnlessAllowed) {
  sph::FieldHandle<Real> V;
  auto set = one_particle_with_potential(-90, V);
  cardio::ActiveTensionSettings s;
  cardio::ActiveTension<3> tensile(set, V, s);
  tensile.advance(0, 50);
  EXPECT_EQ(tensile.tension()[0], 0);
  s.allow_negative = true;
  cardio::ActiveTension<3> signed_tension(set, V, s);
  signed_tension.advance(0, 50);
  EXPECT_LT(signed_tension.tension()[0], 0);
  // The switch is eps_0 at rest and eps_inf well above threshold.
  EXPECT_NEAR(s.rate(-200), s.eps_rest, 1e-12);
  EXPECT_NEAR(s.rate(0), s.eps_active, 1e-12);
  s.eps_rest = 0;
  EXPECT_THROW(s.check(), std::invalid_argument);
}

// The heart's errors against a reference run: absolute differences on the last beat both ran.
TEST(HeartReference, ErrorsAreTheDifferencesOnTheLastCommonBeat) {
  auto beat = [](double ef, double peak, double edp) {
    return nlohmann::json{{"ejection_fraction", ef}, {"peak_pressure_kPa", peak}, {"edp_kPa", edp}};
  };
  sph::RunReport r;
  r.results["beats"] = nlohmann::json::array({{{"lv", beat(0.50, 14, 1.0)}, {"rv", beat(0.40, 3, 0.4)}},
                                              {{"lv", beat(0.60, 16, 1.2)}, {"rv", beat(0.45, 3.5, 0.5)}}});
  // The reference ran three beats: the second one is compared.
  const nlohmann::json reference = nlohmann::json::array({{{"lv", beat(0.1, 1, 1)}, {"rv", beat(0.1, 1, 1)}},
                                                          {{"lv", beat(0.58, 16.5, 1.25)}, {"rv", beat(0.46, 3.0, 0.3)}},
                                                          {{"lv", beat(0.9, 9, 9)}, {"rv", beat(0.9, 9, 9)}}});
  cardiosph::compare_with_reference(r, reference, "ref");
  EXPECT_NEAR(r.errors.value("lv_ejection_fraction_pp", -1), 2.0, 1e-12);
  EXPECT_NEAR(r.errors.value("rv_ejection_fraction_pp", -1), 1.0, 1e-12);
  EXPECT_NEAR(r.errors.value("lv_peak_pressure_kPa", -1), 0.5, 1e-12);
  EXPECT_NEAR(r.errors.value("rv_peak_pressure_kPa", -1), 0.5, 1e-12);
  EXPECT_NEAR(r.errors.value("lv_end_diastolic_pressure_kPa", -1), 0.05, 1e-12);
  EXPECT_NEAR(r.errors.value("rv_end_diastolic_pressure_kPa", -1), 0.2, 1e-12);
  EXPECT_NE(r.reference.find("beat 2"), std::string::npos) << r.reference;
}

TEST(Electromechanics, PulledBackConductionIsFInverseDOfTheDeformedFibreFInverseTransposed) {
  Mat3 F;
  F << 1.1, 0.2, -0.05, 0.03, 0.9, 0.1, -0.02, 0.15, 1.02;
  const Vec3 f0 = Vec3(1, 2, -0.5).normalized();
  const Real Dl = Real(1.2), Dt = Real(0.3);
  const Vec3 f = (F * f0).normalized();
  const Mat3 D = Dt * Mat3::Identity() + (Dl - Dt) * f * f.transpose();
  const Mat3 expected = F.inverse() * D * F.inverse().transpose();
  const Mat3 D0 = cardio::pulled_back_conduction<3>(F, f0, Dl, Dt);
  EXPECT_LT((D0 - expected).norm(), 1e-12 * expected.norm());
  // Identity: the reference tensor.
  const Mat3 I0 = cardio::pulled_back_conduction<3>(Mat3::Identity(), f0, Dl, Dt);
  EXPECT_LT((I0 - (Dt * Mat3::Identity() + (Dl - Dt) * f0 * f0.transpose())).norm(), 1e-14);
}

TEST(ActiveStress, CauchyStressOfTheUndeformedBodyIsTheTensionAlongTheFibre) {
  const Real dp = Real(0.1);
  auto body = geometry::lattice_box<3>("block", Vec3::Zero(), Vec3(1, 1, 1), dp);
  const auto kernel = sph::make_kernel<3>("wendland_c4");
  const auto relation = sph::build_inner_relation<3>(body.position, kernel, Real(1.3) * dp);
  sph::ElasticSolid<3>::Settings settings;
  settings.material = sph::holzapfel_ogden_2009_kpa<3>(100);
  settings.fibre = Vec3(1, 1, 0).normalized();
  settings.sheet = Vec3(-1, 1, 0).normalized();
  settings.active_stress = true;
  sph::ElasticSolid<3> solid(body, relation, settings);
  auto T = body.field(solid.active_tension_field());
  std::fill(T.begin(), T.end(), Real(7));
  solid.update_output_fields();
  const Mat3 expected = 7 * settings.fibre * settings.fibre.transpose();
  for (std::size_t i = 0; i < body.n_particles(); ++i) ASSERT_LT((solid.cauchy_stress_of(i) - expected).norm(), 1e-9);
  // Without any other load the tension is the whole force: the interior is in equilibrium at F = I
  // (uniform stress) while the surface is pulled, so the residual equals the active force.
  const auto r = solid.equilibrium_residual(0);
  EXPECT_GT(r.active, 0);
  EXPECT_NEAR(r.net, r.active, 1e-9 * r.active);
  // Settings::active_stress needs a law with fibres.
  sph::ElasticSolid<3>::Settings isotropic;
  isotropic.material = sph::NeoHookean<3>{1, 1};
  isotropic.active_stress = true;
  EXPECT_THROW(sph::ElasticSolid<3>(body, relation, isotropic), std::invalid_argument);
}

// With the crossbridge stiffness the solid applies T_a + k (lambda - lambda_0); a tension that may not
// fall below zero keeps that sum >= 0 too (ElasticSolid::Settings::active_tension_non_negative).
// At F = I (lambda = 1) the force on the block is that of the applied tension alone, so the net
// residual scales with it: 7 + 1000 (1 - 1.1) = -93 kPa pushes, 93/7 times the force of T_a = 7,
// unless the sum is kept at zero, where no force is left.
TEST(ActiveStress, StretchStiffnessDoesNotMakeANonNegativeTensionPush) {
  const Real dp = Real(0.1);
  auto body = geometry::lattice_box<3>("block", Vec3::Zero(), Vec3(1, 1, 1), dp);
  const auto kernel = sph::make_kernel<3>("wendland_c4");
  const auto relation = sph::build_inner_relation<3>(body.position, kernel, Real(1.3) * dp);
  auto net_force = [&](bool non_negative, Real lambda_0) {
    sph::ElasticSolid<3>::Settings settings;
    settings.material = sph::holzapfel_ogden_2009_kpa<3>(100);
    settings.fibre = Vec3(1, 1, 0).normalized();
    settings.sheet = Vec3(-1, 1, 0).normalized();
    settings.active_stress = true;
    settings.active_stiffness = true;
    settings.active_tension_non_negative = non_negative;
    sph::ElasticSolid<3> solid(body, relation, settings);
    auto T = body.field(solid.active_tension_field());
    auto k = body.field(solid.active_stiffness_field());
    auto l0 = body.field(solid.active_reference_stretch_field());
    std::fill(T.begin(), T.end(), Real(7));
    std::fill(k.begin(), k.end(), Real(1000));
    std::fill(l0.begin(), l0.end(), lambda_0);
    return solid.equilibrium_residual(0).net;
  };
  const double pulling = net_force(true, 1), pushing = net_force(false, Real(1.1)), kept = net_force(true, Real(1.1));
  std::cout << "net force: T = 7 " << pulling << ", T = -93 " << pushing << ", kept at 0 " << kept << "\n";
  EXPECT_GT(pulling, 0);
  EXPECT_NEAR(pushing, 93.0 / 7.0 * pulling, 1e-6 * pushing);
  EXPECT_LT(kept, 1e-9 * pulling);
}

TEST(CavitySurfaces, LvEllipsoidCavityVolumeMatchesTheClosedFormAndFollowsAffineMotion) {
  cardio::HeartGeometrySettings gs;
  gs.mesh = std::filesystem::path(CARDIOSPH_SOURCE_DIR) / "meshes" / "lv_ellipsoid.stl";
  gs.spacing = 1.5;
  gs.relaxation_steps = 0;
  gs.fibres = "none";
  const auto g = cardio::prepare_heart_geometry(gs, {});
  std::vector<Vec3> X(g.body.size());
  std::vector<Real> V(g.body.size());
  for (std::size_t i = 0; i < X.size(); ++i) X[i] = g.body.positions[i].cast<Real>(), V[i] = Real(g.body.volumes[i]);
  const auto mesh = geometry::read_mesh(gs.mesh);
  const auto kernel = sph::make_kernel<3>("wendland_c2");
  const auto cavities = cardio::cavity_surfaces(mesh, cardio::label_faces(mesh).face, X, V, g.labels, Real(1.5), kernel, Real(1.95));
  ASSERT_EQ(cavities.size(), 1u);
  const auto& lv = cavities[0];
  EXPECT_EQ(lv.label, cardio::label_lv_endo);
  // Truncated endocardial ellipsoid r_s = 7, r_l = 17 up to z = 5: pi r_s^2 [z - z^3 / (3 r_l^2)].
  auto primitive = [](double z) { return z - z * z * z / (3 * 17.0 * 17.0); };
  const double exact = std::acos(-1.0) * 49 * (primitive(5) - primitive(-17));
  const double error = (lv.reference_volume - exact) / exact;
  std::cout << "LV cavity volume " << lv.reference_volume << " mm^3 against " << exact << " (relative " << error << ")\n";
  EXPECT_LT(std::abs(error), 0.01);
  // The endocardial area vectors sum to the opening's: pi r(5)^2 along +z.
  Vec3 sum = Vec3::Zero();
  for (const auto& a : lv.area_normals) sum += a;
  const double opening = std::acos(-1.0) * 49 * (1 - 25.0 / 289.0);
  EXPECT_NEAR(sum[2], opening, 0.01 * opening);
  EXPECT_LT(std::hypot(sum[0], sum[1]), 0.01 * opening);
  // Affine motion x = A X + b with F = A: the volume scales by det A (the reconstruction is exact).
  Mat3 A;
  A << 0.9, 0.05, 0, -0.02, 1.1, 0.03, 0.01, 0, 0.95;
  std::vector<Vec3> x(X.size());
  for (std::size_t i = 0; i < X.size(); ++i) x[i] = A * X[i] + Vec3(1, -2, 0.5);
  const std::vector<Mat3> F(X.size(), A);
  EXPECT_NEAR(lv.volume(x, F, X), A.determinant() * lv.reference_volume, 1e-9 * lv.reference_volume);
}

}  // namespace
