// Idealised ventricle meshes: the truncated ellipsoidal LV of Land et al. 2015 (closed, outward,
// vertices on the analytic surfaces, volume against the closed form) and the biventricular mesh
// made by CGAL booleans (valid, four regions, volume against the analytic shape), and the files
// written from them.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>
#include <utility>

#include "geometry/heart_meshes.hpp"
#include "temporary_folder.hpp"

namespace {

using geometry::TriangleMesh;
using geometry::Vec3;
namespace fs = std::filesystem;

/// Signed enclosed volume by the divergence theorem: sum over faces of p0 . (p1 x p2) / 6.
double enclosed_volume(const TriangleMesh& mesh) {
  double volume = 0;
  for (const auto& f : mesh.faces) {
    volume += mesh.vertices[f[0]].dot(mesh.vertices[f[1]].cross(mesh.vertices[f[2]])) / 6;
  }
  return volume;
}

/// Closed, manifold and consistently oriented: every directed edge is used by exactly one face and
/// its reverse by exactly one other. Counted here, independently of check_mesh.
void expect_closed_and_consistent(const TriangleMesh& mesh) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const auto& f : mesh.faces) {
    ASSERT_TRUE(f[0] != f[1] && f[1] != f[2] && f[2] != f[0]);
    for (int k = 0; k < 3; ++k) ++directed[{f[k], f[(k + 1) % 3]}];
  }
  std::size_t bad = 0;
  for (const auto& [edge, count] : directed) {
    const auto reverse = directed.find({edge.second, edge.first});
    if (count != 1 || reverse == directed.end() || reverse->second != 1) ++bad;
  }
  EXPECT_EQ(bad, 0u) << "directed edges without exactly one opposite";
  EXPECT_EQ(directed.size(), 3 * mesh.faces.size());
  // Euler characteristic of a sphere: V - E + F = 2 (E = directed / 2).
  EXPECT_EQ(static_cast<long>(mesh.vertices.size()) - static_cast<long>(directed.size() / 2) +
                static_cast<long>(mesh.faces.size()),
            2);
}

int region_index(const TriangleMesh& mesh, const std::string& name) {
  for (std::size_t r = 0; r < mesh.region_names.size(); ++r) {
    if (mesh.region_names[r] == name) return static_cast<int>(r);
  }
  return -1;
}

std::size_t region_faces(const TriangleMesh& mesh, const std::string& name) {
  const int r = region_index(mesh, name);
  return static_cast<std::size_t>(std::count(mesh.face_region.begin(), mesh.face_region.end(), r));
}

/// |(x, y) / r_s, z / r_l|^2 - 1: zero on the ellipsoid.
double ellipsoid_residual(const Vec3& p, double r_s, double r_l) {
  return (p.x() * p.x() + p.y() * p.y()) / (r_s * r_s) + p.z() * p.z() / (r_l * r_l) - 1;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

TEST(HeartMeshes, LvEllipsoidMeshIsClosedOutwardAndOnTheAnalyticSurfaces) {
  const geometry::LvEllipsoid lv;
  const double h = 1.0;
  const TriangleMesh mesh = geometry::lv_ellipsoid_mesh(lv, h);
  ASSERT_EQ(mesh.face_region.size(), mesh.faces.size());
  expect_closed_and_consistent(mesh);
  const geometry::MeshCheckReport report = geometry::check_mesh(mesh);
  EXPECT_TRUE(report.ok()) << report.problems();

  // Volume: the chords cut inside both ellipsoids, so the wall comes out slightly different.
  const double volume = enclosed_volume(mesh);
  const double exact = geometry::lv_ellipsoid_volume(lv);
  std::printf("LV mesh h = %g mm: %zu vertices, %zu faces, volume %.3f mm^3, closed form %.3f mm^3 (%+.3f %%)\n", h,
              mesh.vertices.size(), mesh.faces.size(), volume, exact, 100 * (volume / exact - 1));
  EXPECT_GT(volume, 0);
  EXPECT_NEAR(volume / exact, 1, 0.005);

  ASSERT_EQ(mesh.region_names.size(), 3u);
  for (const char* name : {geometry::region_epi, geometry::region_lv_endo, geometry::region_base}) {
    EXPECT_GT(region_faces(mesh, name), 0u) << name;
  }
  // Every vertex of a face lies on the surface of its region; base vertices at z = base_z exactly.
  const int epi = region_index(mesh, geometry::region_epi);
  const int endo = region_index(mesh, geometry::region_lv_endo);
  const int base = region_index(mesh, geometry::region_base);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    for (const std::uint32_t v : mesh.faces[f]) {
      const Vec3& p = mesh.vertices[v];
      if (mesh.face_region[f] == endo) {
        ASSERT_LT(std::abs(ellipsoid_residual(p, lv.endo_rs, lv.endo_rl)), 1e-9) << p.transpose();
        ASSERT_LE(p.z(), lv.base_z);
      } else if (mesh.face_region[f] == epi) {
        ASSERT_LT(std::abs(ellipsoid_residual(p, lv.epi_rs, lv.epi_rl)), 1e-9) << p.transpose();
        ASSERT_LE(p.z(), lv.base_z);
      } else {
        ASSERT_EQ(mesh.face_region[f], base);
        ASSERT_EQ(p.z(), lv.base_z) << p.transpose();
      }
    }
  }
  // Outward: endocardial normals point into the cavity (towards the axis), epicardial ones away
  // from it, base normals along +z.
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const Vec3& a = mesh.vertices[mesh.faces[f][0]];
    const Vec3 n = (mesh.vertices[mesh.faces[f][1]] - a).cross(mesh.vertices[mesh.faces[f][2]] - a);
    const Vec3 c = (a + mesh.vertices[mesh.faces[f][1]] + mesh.vertices[mesh.faces[f][2]]) / 3;
    // Gradient of the ellipsoid's implicit function: the outward normal of the ellipsoid itself.
    if (mesh.face_region[f] == base) {
      ASSERT_GT(n.z(), 0);
    } else {
      const double r_s = mesh.face_region[f] == epi ? lv.epi_rs : lv.endo_rs;
      const double r_l = mesh.face_region[f] == epi ? lv.epi_rl : lv.endo_rl;
      const Vec3 gradient(c.x() / (r_s * r_s), c.y() / (r_s * r_s), c.z() / (r_l * r_l));
      const double sign = mesh.face_region[f] == epi ? 1 : -1;
      ASSERT_GT(sign * n.dot(gradient), 0) << "face " << f;
    }
  }
  // Triangles of about the requested size, none degenerate.
  double shortest = 1e300, longest = 0;
  for (const auto& f : mesh.faces) {
    for (int k = 0; k < 3; ++k) {
      const double length = (mesh.vertices[f[k]] - mesh.vertices[f[(k + 1) % 3]]).norm();
      shortest = std::min(shortest, length);
      longest = std::max(longest, length);
    }
  }
  std::printf("LV mesh h = %g mm: edges from %.3f to %.3f mm\n", h, shortest, longest);
  EXPECT_GT(shortest, 0.3 * h);
  EXPECT_LT(longest, 1.5 * h);
}

TEST(HeartMeshes, LvEllipsoidMeshIsClosedAtCoarseAndOddEdgeLengths) {
  // Few segments per ring, an annulus of one strip, rings of very different vertex counts.
  for (const double h : {0.73, 1.9, 3.1, 6.0, 12.0}) {
    SCOPED_TRACE(h);
    const TriangleMesh mesh = geometry::lv_ellipsoid_mesh(geometry::LvEllipsoid{}, h);
    expect_closed_and_consistent(mesh);
    EXPECT_TRUE(geometry::check_mesh(mesh).ok()) << geometry::check_mesh(mesh).problems();
    EXPECT_GT(enclosed_volume(mesh), 0);
  }
  // Another shape: base plane below the equator, thin wall.
  const geometry::LvEllipsoid thin{.endo_rs = 9, .endo_rl = 19, .epi_rs = 10, .epi_rl = 20, .base_z = -3};
  const TriangleMesh mesh = geometry::lv_ellipsoid_mesh(thin, 0.8);
  expect_closed_and_consistent(mesh);
  EXPECT_TRUE(geometry::check_mesh(mesh).ok()) << geometry::check_mesh(mesh).problems();
  EXPECT_NEAR(enclosed_volume(mesh) / geometry::lv_ellipsoid_volume(thin), 1, 0.01);
}

TEST(HeartMeshes, LvEllipsoidVolumeMatchesTheShape) {
  const geometry::LvEllipsoid lv;
  const double exact = geometry::lv_ellipsoid_volume(lv);
  // Land et al. 2015 problem 2 by hand: pi [100 (5 - 125/1200 + 20 - 8000/1200)
  //                                           - 49 (5 - 125/867 + 17 - 4913/867)].
  const double by_hand = std::numbers::pi * (100 * (25 - 125.0 / 1200 - 8000.0 / 1200) -
                                             49 * (22 - 125.0 / 867 - 4913.0 / 867));
  EXPECT_NEAR(exact, by_hand, 1e-9 * by_hand);
  const auto start = std::chrono::steady_clock::now();
  const double integrated = geometry::shape_volume(*geometry::lv_ellipsoid_shape(lv), 0.3);
  std::printf("LV wall volume: closed form %.3f mm^3, shape_volume %.3f mm^3 (%+.3f %%, %.2f s)\n", exact, integrated,
              100 * (integrated / exact - 1), seconds_since(start));
  EXPECT_NEAR(integrated / exact, 1, 0.002);
  // The shape is the wall: the cavity and the space above the base are outside.
  const auto shape = geometry::lv_ellipsoid_shape(lv);
  EXPECT_TRUE(shape->contains(Vec3(8.5, 0, 0)));
  EXPECT_TRUE(shape->contains(Vec3(0, 0, -18.5)));
  EXPECT_FALSE(shape->contains(Vec3(0, 0, 0)));
  EXPECT_FALSE(shape->contains(Vec3(8.5, 0, 5.5)));
}

TEST(HeartMeshes, BadDimensionsAreRejectedByName) {
  const auto message = [](auto&& make) -> std::string {
    try {
      make();
    } catch (const std::invalid_argument& error) {
      return error.what();
    }
    return "";
  };
  EXPECT_NE(message([] { geometry::lv_ellipsoid_mesh({.endo_rs = -7}, 1); }).find("endo_rs"), std::string::npos);
  EXPECT_NE(message([] { geometry::lv_ellipsoid_mesh({.endo_rs = 11}, 1); }).find("smaller"), std::string::npos);
  EXPECT_NE(message([] { geometry::lv_ellipsoid_mesh({.base_z = 18}, 1); }).find("base_z"), std::string::npos);
  EXPECT_NE(message([] { geometry::lv_ellipsoid_mesh({}, 0); }).find("edge_length"), std::string::npos);
  geometry::Biventricular biv;
  biv.rv_endo_radii = Vec3(30, 30, 44);
  EXPECT_NE(message([&] { geometry::biventricular_mesh(biv, 3); }).find("rv_endo_radii"), std::string::npos);
  biv = {};
  biv.base_z = 60;
  EXPECT_NE(message([&] { geometry::biventricular_shape(biv); }).find("base_z"), std::string::npos);
}

TEST(HeartMeshes, BiventricularMeshIsValidWithFourRegions) {
  const geometry::Biventricular biv;
  const double h = 3.0;
  auto start = std::chrono::steady_clock::now();
  const TriangleMesh mesh = geometry::biventricular_mesh(biv, h);
  const double mesh_seconds = seconds_since(start);
  const geometry::MeshCheckReport report = geometry::check_mesh(mesh);
  EXPECT_TRUE(report.ok()) << report.problems();
  EXPECT_EQ(report.components, 1u);
  expect_closed_and_consistent(mesh);
  ASSERT_EQ(mesh.face_region.size(), mesh.faces.size());
  ASSERT_EQ(mesh.region_names.size(), 4u);
  for (const char* name : {geometry::region_epi, geometry::region_lv_endo, geometry::region_rv_endo, geometry::region_base}) {
    EXPECT_GT(region_faces(mesh, name), 0u) << name;
  }

  // Every face lies on the analytic surface of its region (within the chordal error of edges up to
  // 1.5 h), and nothing lies above the base. F = (|(c - centre) / radii| - 1) min(radii) is at most
  // the distance to the ellipsoid.
  const auto F = [](const Vec3& c, const Vec3& centre, const Vec3& radii) {
    return ((c - centre).cwiseQuotient(radii).norm() - 1) * radii.minCoeff();
  };
  const double tolerance = 0.3;  // [mm]; the sagitta (1.5 h)^2 / (8 R) for R >= 20 mm is below 0.13 mm
  const int epi = region_index(mesh, geometry::region_epi);
  const int lv_endo = region_index(mesh, geometry::region_lv_endo);
  const int rv_endo = region_index(mesh, geometry::region_rv_endo);
  const int base = region_index(mesh, geometry::region_base);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const auto& face = mesh.faces[f];
    for (const std::uint32_t v : face) {
      ASSERT_LE(mesh.vertices[v].z(), biv.base_z + 1e-9);
      if (mesh.face_region[f] == base) {
        ASSERT_NEAR(mesh.vertices[v].z(), biv.base_z, 1e-9);
      }
    }
    const Vec3 c = (mesh.vertices[face[0]] + mesh.vertices[face[1]] + mesh.vertices[face[2]]) / 3;
    const double F1 = F(c, biv.lv_centre, biv.lv_endo_radii), F2 = F(c, biv.lv_centre, biv.lv_epi_radii);
    const double F3 = F(c, biv.rv_centre, biv.rv_endo_radii), F4 = F(c, biv.rv_centre, biv.rv_epi_radii);
    if (mesh.face_region[f] == lv_endo) {
      ASSERT_LT(std::abs(F1), tolerance) << c.transpose();
    } else if (mesh.face_region[f] == epi) {
      ASSERT_LT(std::min(std::abs(F2), std::abs(F4)), tolerance) << c.transpose();
      ASSERT_GT(F3, 0) << c.transpose();
    } else if (mesh.face_region[f] == rv_endo) {
      ASSERT_LT(std::min(std::abs(F2), std::abs(F3)), tolerance) << c.transpose();
      ASSERT_LT(F3, tolerance) << c.transpose();
    }
  }

  start = std::chrono::steady_clock::now();
  const double analytic = geometry::shape_volume(*geometry::biventricular_shape(biv), 1.5);
  const double volume = enclosed_volume(mesh);
  std::printf(
      "BiV mesh h = %g mm: %zu faces (epi %zu, lv_endo %zu, rv_endo %zu, base %zu) in %.2f s; volume %.0f mm^3, "
      "shape_volume %.0f mm^3 (%+.2f %%, %.2f s)\n",
      h, mesh.faces.size(), region_faces(mesh, geometry::region_epi), region_faces(mesh, geometry::region_lv_endo),
      region_faces(mesh, geometry::region_rv_endo), region_faces(mesh, geometry::region_base), mesh_seconds, volume,
      analytic, 100 * (volume / analytic - 1), seconds_since(start));
  EXPECT_NEAR(volume / analytic, 1, 0.02);

  // The binary STL stores floats: the rounded mesh read back is still valid.
  const test::TemporaryFolder scratch("heart_meshes");
  const fs::path folder = scratch / "biv";
  const auto files = geometry::write_heart_mesh_files(mesh, folder, "biv");
  EXPECT_EQ(files.size(), 6u);
  const geometry::MeshCheckReport read_back = geometry::check_mesh(geometry::read_mesh(folder / "biv.stl"));
  EXPECT_TRUE(read_back.ok()) << read_back.problems();
  EXPECT_EQ(read_back.faces, mesh.faces.size());
}

TEST(HeartMeshes, WritesTheClosedMeshAndOneFilePerRegion) {
  const test::TemporaryFolder scratch("heart_meshes");
  const fs::path folder = scratch / "out";
  const TriangleMesh mesh = geometry::lv_ellipsoid_mesh(geometry::LvEllipsoid{}, 3.0);
  const auto files = geometry::write_heart_mesh_files(mesh, folder, "lv");
  ASSERT_EQ(files.size(), 5u);
  EXPECT_EQ(files[0], folder / "lv.stl");
  EXPECT_EQ(files[1], folder / "lv.obj");
  for (const auto& file : files) EXPECT_TRUE(fs::is_regular_file(file)) << file;
  // Binary STL: 80-byte header, face count, 50 bytes per face.
  EXPECT_EQ(fs::file_size(folder / "lv.stl"), 84 + 50 * mesh.faces.size());
  std::size_t region_total = 0;
  for (const char* name : {geometry::region_epi, geometry::region_lv_endo, geometry::region_base}) {
    const fs::path file = folder / (std::string("lv_") + name + ".stl");
    ASSERT_TRUE(fs::is_regular_file(file)) << file;
    EXPECT_EQ(fs::file_size(file), 84 + 50 * region_faces(mesh, name)) << file;
    region_total += region_faces(mesh, name);
  }
  EXPECT_EQ(region_total, mesh.faces.size());
  // The OBJ keeps the regions and the welded closed mesh.
  const TriangleMesh back = geometry::read_mesh(folder / "lv.obj");
  EXPECT_EQ(back.faces.size(), mesh.faces.size());
  EXPECT_EQ(back.vertices.size(), mesh.vertices.size());
  for (const char* name : {geometry::region_epi, geometry::region_lv_endo, geometry::region_base}) {
    EXPECT_EQ(region_faces(back, name), region_faces(mesh, name)) << name;
  }
  EXPECT_TRUE(geometry::check_mesh(geometry::read_mesh(folder / "lv.stl")).ok());
}

}  // namespace
