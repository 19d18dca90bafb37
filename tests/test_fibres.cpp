// Surface labels (regions, geometric rule) and fibre fields (frames, files, LDRB on a coarse LV).

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "cardio/fibres.hpp"
#include "cardio/heart_geometry.hpp"
#include "cardio/surface_labels.hpp"
#include "geometry/heart_meshes.hpp"
#include "temporary_folder.hpp"

namespace {

using geometry::Vec3;
namespace fs = std::filesystem;


// Fraction of faces whose rule label equals the label of the generator's region.
double agreement(const geometry::TriangleMesh& mesh, const cardio::FaceLabels& rule) {
  std::size_t same = 0;
  for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
    const auto& region = mesh.region_names[static_cast<std::size_t>(mesh.face_region[f])];
    const cardio::SurfaceLabel truth = region == "epi"       ? cardio::label_epi
                                       : region == "lv_endo" ? cardio::label_lv_endo
                                       : region == "rv_endo" ? cardio::label_rv_endo
                                                             : cardio::label_base;
    same += rule.face[f] == truth;
  }
  return double(same) / double(mesh.n_faces());
}

TEST(SurfaceLabels, GeometricRuleRecoversTheGeneratedRegions) {
  const auto lv = geometry::lv_ellipsoid_mesh(geometry::LvEllipsoid{}, 1.0);
  const auto lv_rule = cardio::face_labels_by_rule(lv);
  EXPECT_TRUE(lv_rule.has_base);
  EXPECT_LT((lv_rule.base_normal - Vec3::UnitZ()).norm(), 1e-12);
  EXPECT_EQ(agreement(lv, lv_rule), 1.0);

  const auto biv = geometry::biventricular_mesh(geometry::Biventricular{}, 4.0);
  const auto biv_rule = cardio::face_labels_by_rule(biv);
  const double a = agreement(biv, biv_rule);
  std::cout << "[ measured ] biventricular rule/region agreement " << a << ", cavity compactness LV "
            << biv_rule.cavity_compactness.at(0) << ", RV " << biv_rule.cavity_compactness.at(1) << '\n';
  EXPECT_EQ(a, 1.0);
  // Named regions take precedence over the rule.
  EXPECT_EQ(cardio::label_faces(biv).method, "regions");
}

TEST(SurfaceLabels, UnknownRegionNamesAreRejected) {
  auto lv = geometry::lv_ellipsoid_mesh(geometry::LvEllipsoid{}, 2.0);
  lv.region_names[0] = "outer wall";
  EXPECT_THROW(cardio::face_labels_from_regions(lv), geometry::MeshError);
}

TEST(Fibres, HelixAngleAndUniformField) {
  const Vec3 c = Vec3::UnitX(), l = Vec3::UnitZ();
  EXPECT_NEAR(cardio::helix_angle_deg(Vec3(1, 0, 1), c, l), 45, 1e-12);
  EXPECT_NEAR(cardio::helix_angle_deg(Vec3(-1, 0, -1), c, l), 45, 1e-12);  // no sign
  EXPECT_NEAR(cardio::helix_angle_deg(Vec3(1, 0, -std::sqrt(3.0)), c, l), -60, 1e-12);
  const auto u = cardio::uniform_fibres(3, Vec3(2, 0, 0), Vec3(1, 1, 0));
  EXPECT_LT((u.sheet[2] - Vec3::UnitY()).norm(), 1e-15);
  EXPECT_THROW(cardio::uniform_fibres(3, Vec3(1, 0, 0), Vec3(3, 0, 0)), std::invalid_argument);
}

TEST(Fibres, FileFibresMapToTheNearestPoint) {
  const test::TemporaryFolder folder("fibres");
  {
    std::ofstream f(folder / "fibres.txt");
    f << "# x y z fx fy fz\n0 0 0 1 0 0\n10, 0, 0, 0, 2, 0\n0 10 0 0 0 1 1 0 0\n";
  }
  const std::vector<Vec3> points{Vec3(1, 1, 0), Vec3(8, -1, 0), Vec3(-1, 9, 3), Vec3(40, 0, 0)};
  const auto field = cardio::fibres_from_file(points, folder / "fibres.txt");
  EXPECT_LT((field.fibre[0] - Vec3::UnitX()).norm(), 1e-15);
  EXPECT_LT((field.fibre[1] - Vec3::UnitY()).norm(), 1e-15);
  EXPECT_LT((field.fibre[2] - Vec3::UnitZ()).norm(), 1e-15);
  EXPECT_LT((field.sheet[2] - Vec3::UnitX()).norm(), 1e-15);
  EXPECT_LT((field.fibre[3] - Vec3::UnitY()).norm(), 1e-15);
  {
    std::ofstream f(folder / "bad.txt");
    f << "0 0 0 1 0 0\n1 2 3 4\n";
  }
  try {
    cardio::fibres_from_file(points, folder / "bad.txt");
    ADD_FAILURE() << "a line of four values was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("line 2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(cardio::fibres_from_file(points, folder / "missing.txt"), std::invalid_argument);
}

// The whole stage on a coarse LV: labels, LDRB fibres within a loose bound at this coarse spacing
// (the 3-degree bound at the default spacing is a validation test), then the cache.
TEST(HeartGeometry, CoarseLvStageAndCache) {
  const test::TemporaryFolder folder("fibres");
  geometry::write_heart_mesh_files(geometry::lv_ellipsoid_mesh(geometry::LvEllipsoid{}, 1.0), folder.path(), "lv");
  cardio::HeartGeometrySettings settings;
  settings.mesh = folder / "lv.stl";
  settings.spacing = 1.0;
  settings.relaxation_steps = 20;
  const auto first = cardio::prepare_heart_geometry(settings, folder / "cache");
  EXPECT_FALSE(first.from_cache);
  EXPECT_EQ(first.label_method, "geometric rule");
  for (auto l : {cardio::label_epi, cardio::label_lv_endo, cardio::label_base})
    EXPECT_GT(std::count(first.labels.begin(), first.labels.end(), l), 0) << cardio::surface_label_name(l);
  EXPECT_EQ(std::count(first.labels.begin(), first.labels.end(), cardio::label_rv_endo), 0);
  for (std::size_t i = 0; i < first.body.size(); ++i) {
    ASSERT_NEAR(first.fibres.fibre[i].norm(), 1.0, 1e-9);
    ASSERT_NEAR(first.fibres.fibre[i].dot(first.fibres.sheet[i]), 0.0, 1e-9);
  }
  const auto check = cardio::check_lv_ellipsoid_fibres(first.body.positions, first.fibres, geometry::LvEllipsoid{},
                                                       settings.ldrb, 1.0, 2.0);
  std::cout << "[ measured ] LV dp = 1 mm: " << first.body.size() << " particles, volume error "
            << first.body.volume_relative_error << ", fibre angle MAD " << check.mad_deg << " deg over "
            << check.particles << " particles (bound 6 at this spacing)\n";
  EXPECT_LT(check.mad_deg, 6.0);

  // Same inputs: read back. Other inputs (an angle, the mesh bytes): regenerated.
  const auto second = cardio::prepare_heart_geometry(settings, folder / "cache");
  EXPECT_TRUE(second.from_cache);
  EXPECT_EQ(second.hash, first.hash);
  ASSERT_EQ(second.body.size(), first.body.size());
  EXPECT_EQ(second.body.positions.back(), first.body.positions.back());
  EXPECT_EQ(second.fibres.fibre.back(), first.fibres.fibre.back());
  EXPECT_EQ(second.labels, first.labels);
  settings.ldrb.alpha_endo_deg = 50;
  EXPECT_FALSE(cardio::prepare_heart_geometry(settings, folder / "cache").from_cache);
  settings.ldrb.alpha_endo_deg = 60;
  geometry::write_heart_mesh_files(geometry::lv_ellipsoid_mesh(geometry::LvEllipsoid{}, 0.9), folder.path(), "lv");
  EXPECT_FALSE(cardio::prepare_heart_geometry(settings, folder / "cache").from_cache);
}

}  // namespace
