// Triangle meshes: reading (STL binary/ASCII, OBJ, PLY), welding, regions, checks, repair,
// writing, and MeshShape queries. The small meshes are built here; the shared heart comes from
// ../shared/meshes (CARDIOSPH_SHARED_MESHES, set in tests/CMakeLists.txt).

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "geometry/mesh.hpp"
#include "libsph/core/parallel.hpp"
#include "temporary_folder.hpp"

namespace {

using geometry::MeshError;
using geometry::TriangleMesh;
using geometry::Vec3;
namespace fs = std::filesystem;

// Unit cube [0,1]^3: vertex x + 2y + 4z, two outward triangles per side; faces 2 and 3 are the top.
TriangleMesh unit_cube(const Vec3& offset = Vec3::Zero()) {
  TriangleMesh cube;
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x) cube.vertices.push_back(offset + Vec3(x, y, z));
  cube.faces = {{0, 2, 3}, {0, 3, 1},   // bottom, -z
                {4, 5, 7}, {4, 7, 6},   // top, +z
                {0, 1, 5}, {0, 5, 4},   // front, -y
                {2, 6, 7}, {2, 7, 3},   // back, +y
                {0, 4, 6}, {0, 6, 2},   // left, -x
                {1, 3, 7}, {1, 7, 5}};  // right, +x
  cube.face_region.assign(cube.faces.size(), 0);
  cube.region_names = {""};
  return cube;
}

TriangleMesh flipped(TriangleMesh mesh, std::size_t face) {
  std::swap(mesh.faces[face][1], mesh.faces[face][2]);
  return mesh;
}

TriangleMesh without_faces(TriangleMesh mesh, std::vector<std::size_t> faces) {
  std::sort(faces.rbegin(), faces.rend());
  for (std::size_t f : faces) {
    mesh.faces.erase(mesh.faces.begin() + static_cast<std::ptrdiff_t>(f));
    mesh.face_region.erase(mesh.face_region.begin() + static_cast<std::ptrdiff_t>(f));
  }
  return mesh;
}

using test::TemporaryFolder;

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

template <class T>
void put(std::string& bytes, T value) {
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  bytes.append(raw, sizeof(T));
}

// Binary STL whose header begins with "solid", as many exporters write it (the classic trap).
std::string binary_stl(const TriangleMesh& mesh) {
  std::string header = "solid cube, but this is a binary STL";
  header.resize(80, ' ');
  std::string bytes = header;
  put(bytes, static_cast<std::uint32_t>(mesh.faces.size()));
  for (const auto& f : mesh.faces) {
    for (int d = 0; d < 3; ++d) put(bytes, 0.0f);  // normal: readers must not rely on it
    for (int c = 0; c < 3; ++c)
      for (int d = 0; d < 3; ++d) put(bytes, static_cast<float>(mesh.vertices[f[c]][d]));
    put(bytes, std::uint16_t{0});
  }
  return bytes;
}

std::string ascii_stl(const TriangleMesh& mesh, const std::string& name = "cube") {
  std::ostringstream out;
  out << "solid " << name << "\n";
  for (const auto& f : mesh.faces) {
    const Vec3 n = (mesh.vertices[f[1]] - mesh.vertices[f[0]]).cross(mesh.vertices[f[2]] - mesh.vertices[f[0]]);
    out << "  facet normal " << n.x() << " " << n.y() << " " << n.z() << "\n    outer loop\n";
    for (int c = 0; c < 3; ++c) {
      const Vec3& v = mesh.vertices[f[c]];
      out << "      vertex " << v.x() << " " << v.y() << " " << v.z() << "\n";
    }
    out << "    endloop\n  endfacet\n";
  }
  out << "endsolid " << name << "\n";
  return out.str();
}

// OBJ with one group per entry of `groups` (name, faces).
std::string obj(const TriangleMesh& mesh, const std::vector<std::pair<std::string, std::vector<int>>>& groups) {
  std::ostringstream out;
  for (const Vec3& v : mesh.vertices) out << "v " << v.x() << " " << v.y() << " " << v.z() << "\n";
  for (const auto& [name, faces] : groups) {
    if (!name.empty()) out << "g " << name << "\n";
    for (int f : faces)
      out << "f " << mesh.faces[f][0] + 1 << " " << mesh.faces[f][1] + 1 << " " << mesh.faces[f][2] + 1 << "\n";
  }
  return out.str();
}

std::string ply(const TriangleMesh& mesh) {
  std::ostringstream out;
  out << "ply\nformat ascii 1.0\nelement vertex " << mesh.vertices.size()
      << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << mesh.faces.size()
      << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const Vec3& v : mesh.vertices) out << v.x() << " " << v.y() << " " << v.z() << "\n";
  for (const auto& f : mesh.faces) out << "3 " << f[0] << " " << f[1] << " " << f[2] << "\n";
  return out.str();
}

std::vector<int> all_faces(const TriangleMesh& mesh) {
  std::vector<int> faces(mesh.faces.size());
  for (std::size_t i = 0; i < faces.size(); ++i) faces[i] = static_cast<int>(i);
  return faces;
}

void expect_unit_cube(const TriangleMesh& mesh, double scale, const std::string& what) {
  SCOPED_TRACE(what);
  EXPECT_EQ(mesh.vertices.size(), 8u);
  EXPECT_EQ(mesh.n_faces(), 12u);
  EXPECT_EQ(mesh.face_region.size(), 12u);
  const auto report = geometry::check_mesh(mesh);
  EXPECT_TRUE(report.ok()) << report.problems();
  EXPECT_EQ(report.components, 1u);
  EXPECT_NEAR(report.volume, scale * scale * scale, 1e-12 * scale * scale * scale);
  const auto box = mesh.bounding_box();
  EXPECT_NEAR((box.lower - Vec3::Zero()).norm(), 0.0, 1e-12 * scale);
  EXPECT_NEAR((box.upper - Vec3::Constant(scale)).norm(), 0.0, 1e-12 * scale);
}

// The message of the MeshError thrown by read_mesh(path) ("" if none is thrown).
std::string read_error(const fs::path& path) {
  try {
    geometry::read_mesh(path);
  } catch (const MeshError& error) {
    return error.what();
  }
  return "";
}

std::string validity_error(const TriangleMesh& mesh, const std::string& name) {
  try {
    geometry::require_valid_mesh(mesh, name);
  } catch (const MeshError& error) {
    return error.what();
  }
  return "";
}

// Exact signed distance to the unit cube.
double unit_cube_distance(const Vec3& p) {
  const Vec3 q = (p - Vec3::Constant(0.5)).cwiseAbs() - Vec3::Constant(0.5);
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

// Uniform in [0, 1) from the raw bits of the engine (see STYLE.md, "Seeds").
double uniform(std::mt19937_64& engine) { return static_cast<double>(engine() >> 11) * 0x1.0p-53; }

}  // namespace

TEST(Mesh, UnitCubeReadsBackWeldedFromEveryFormat) {
  const TemporaryFolder folder;
  const TriangleMesh cube = unit_cube();
  write_text(folder / "cube_binary.stl", binary_stl(cube));
  write_text(folder / "cube_ascii.stl", ascii_stl(cube));
  write_text(folder / "cube.obj", obj(cube, {{"", all_faces(cube)}}));
  write_text(folder / "cube.ply", ply(cube));
  for (const char* name : {"cube_binary.stl", "cube_ascii.stl", "cube.obj", "cube.ply"}) {
    expect_unit_cube(geometry::read_mesh(folder / name), 1.0, name);
    expect_unit_cube(geometry::read_mesh(folder / name, 10.0), 10.0, std::string(name) + " scaled by 10");
  }
  // One region: unnamed for binary STL, OBJ without groups and PLY; the solid's name for ASCII STL.
  EXPECT_EQ(geometry::read_mesh(folder / "cube_binary.stl").region_names, std::vector<std::string>{""});
  EXPECT_EQ(geometry::read_mesh(folder / "cube.obj").region_names, std::vector<std::string>{""});
  EXPECT_EQ(geometry::read_mesh(folder / "cube.ply").region_names, std::vector<std::string>{""});
  EXPECT_EQ(geometry::read_mesh(folder / "cube_ascii.stl").region_names, std::vector<std::string>{"cube"});
}

TEST(Mesh, BinaryStlWithBytesAfterTheLastTriangleIsRead) {
  const TemporaryFolder folder;
  write_text(folder / "padded.stl", binary_stl(unit_cube()) + std::string(7, '\0'));
  expect_unit_cube(geometry::read_mesh(folder / "padded.stl"), 1.0, "padded binary STL");
}

TEST(Mesh, OpenBoxHasFourBorderEdges) {
  const TriangleMesh open_box = without_faces(unit_cube(), {2, 3});  // no top
  const auto report = geometry::check_mesh(open_box);
  EXPECT_EQ(report.border_edges, 4u);
  EXPECT_EQ(report.non_manifold_edges, 0u);
  EXPECT_EQ(report.inconsistent_edges, 0u);
  EXPECT_FALSE(report.ok());
  const std::string message = validity_error(open_box, "open box");
  EXPECT_NE(message.find("mesh 'open box'"), std::string::npos) << message;
  EXPECT_NE(message.find("4 border edges"), std::string::npos) << message;
}

TEST(Mesh, InvertedCubeHasNegativeVolumeAndRepairFixesIt) {
  TriangleMesh inverted = unit_cube();
  for (std::size_t f = 0; f < inverted.n_faces(); ++f) inverted = flipped(inverted, f);
  const auto report = geometry::check_mesh(inverted);
  EXPECT_NEAR(report.volume, -1.0, 1e-12);
  EXPECT_EQ(report.inconsistent_edges, 0u);
  EXPECT_EQ(report.border_edges, 0u);
  EXPECT_FALSE(report.ok());
  const std::string message = validity_error(inverted, "inverted");
  EXPECT_NE(message.find("inverted"), std::string::npos) << message;
  EXPECT_NE(message.find("negative"), std::string::npos) << message;

  const TriangleMesh repaired = geometry::repair_mesh(inverted);
  const auto after = geometry::check_mesh(repaired);
  EXPECT_TRUE(after.ok()) << after.problems();
  EXPECT_NEAR(after.volume, 1.0, 1e-12);
  EXPECT_EQ(repaired.n_faces(), 12u);
}

TEST(Mesh, OneFlippedFaceGivesThreeInconsistentEdges) {
  const TriangleMesh mesh = flipped(unit_cube(), 5);
  const auto report = geometry::check_mesh(mesh);
  EXPECT_EQ(report.inconsistent_edges, 3u);
  EXPECT_EQ(report.border_edges, 0u);
  EXPECT_FALSE(report.ok());
  EXPECT_NE(report.problems().find("3 edges"), std::string::npos) << report.problems();

  const auto repaired = geometry::check_mesh(geometry::repair_mesh(mesh));
  EXPECT_TRUE(repaired.ok()) << repaired.problems();
  EXPECT_NEAR(repaired.volume, 1.0, 1e-12);
}

TEST(Mesh, RepairFillsTheHoleOfAnOpenBoxAndKeepsRegions) {
  TriangleMesh open_box = unit_cube();
  open_box.region_names = {"caps", "sides"};
  for (std::size_t f = 0; f < open_box.n_faces(); ++f) open_box.face_region[f] = f < 4 ? 0 : 1;
  open_box = without_faces(open_box, {2, 3});
  const TriangleMesh repaired = geometry::repair_mesh(open_box);
  const auto report = geometry::check_mesh(repaired);
  EXPECT_TRUE(report.ok()) << report.problems();
  EXPECT_NEAR(report.volume, 1.0, 1e-12);
  ASSERT_EQ(repaired.n_faces(), 12u);
  EXPECT_EQ(repaired.region_names, open_box.region_names);
  for (std::size_t f = 0; f < 10; ++f) EXPECT_EQ(repaired.face_region[f], open_box.face_region[f]) << f;
}

TEST(Mesh, RepairRemovesDegenerateFaces) {
  TriangleMesh mesh = unit_cube();
  mesh.faces.push_back({0, 1, 1});  // repeated vertex
  mesh.vertices.push_back(Vec3(0.5, 0, 0));
  mesh.faces.push_back({0, 8, 1});  // zero area
  mesh.face_region.resize(mesh.faces.size(), 0);
  const auto report = geometry::check_mesh(mesh);
  EXPECT_EQ(report.degenerate_faces, 2u);
  EXPECT_NE(report.problems().find("degenerate: 2 faces"), std::string::npos) << report.problems();
  const TriangleMesh repaired = geometry::repair_mesh(mesh);
  EXPECT_EQ(repaired.n_faces(), 12u);
  EXPECT_EQ(repaired.vertices.size(), 8u);
  EXPECT_TRUE(geometry::check_mesh(repaired).ok()) << geometry::check_mesh(repaired).problems();
}

TEST(Mesh, OverlappingCubesSelfIntersect) {
  TriangleMesh two = unit_cube();
  const TriangleMesh second = unit_cube(Vec3(0.5, 0.25, 0.125));
  for (const auto& f : second.faces) two.faces.push_back({f[0] + 8, f[1] + 8, f[2] + 8});
  two.vertices.insert(two.vertices.end(), second.vertices.begin(), second.vertices.end());
  two.face_region.assign(two.faces.size(), 0);
  const auto report = geometry::check_mesh(two);
  EXPECT_GT(report.self_intersecting_faces, 0u);
  EXPECT_EQ(report.components, 2u);
  EXPECT_EQ(report.border_edges, 0u);
  const std::string message = validity_error(two, "two cubes");
  EXPECT_NE(message.find("self-intersecting: " + std::to_string(report.self_intersecting_faces) + " faces"),
            std::string::npos)
      << message;

  // Two disjoint cubes: two components, valid.
  TriangleMesh apart = unit_cube();
  const TriangleMesh far = unit_cube(Vec3(2, 0, 0));
  for (const auto& f : far.faces) apart.faces.push_back({f[0] + 8, f[1] + 8, f[2] + 8});
  apart.vertices.insert(apart.vertices.end(), far.vertices.begin(), far.vertices.end());
  apart.face_region.assign(apart.faces.size(), 0);
  const auto apart_report = geometry::check_mesh(apart);
  EXPECT_TRUE(apart_report.ok()) << apart_report.problems();
  EXPECT_EQ(apart_report.components, 2u);
  EXPECT_NEAR(apart_report.volume, 2.0, 1e-12);
}

TEST(Mesh, BadFilesAreRejectedNamingTheFile) {
  const TemporaryFolder folder;
  const std::string cube_bytes = binary_stl(unit_cube());
  write_text(folder / "empty.stl", "");
  write_text(folder / "truncated.stl", cube_bytes.substr(0, 84 + 50 * 5 + 17));
  write_text(folder / "notes.stl", "these are my notes, not a mesh\n");
  write_text(folder / "notes.obj", "these are my notes, not a mesh\n");
  write_text(folder / "notes.txt", "these are my notes, not a mesh\n");
  std::string random_bytes(2000, '\0');
  std::mt19937_64 engine(342343901);
  for (char& c : random_bytes) c = static_cast<char>(engine() & 0xff);
  write_text(folder / "random.stl", random_bytes);
  write_text(folder / "random.ply", random_bytes);
  TriangleMesh nan_cube = unit_cube();
  nan_cube.vertices[3].y() = std::numeric_limits<double>::quiet_NaN();
  write_text(folder / "nan_ascii.stl", ascii_stl(nan_cube));
  write_text(folder / "nan_binary.stl", binary_stl(nan_cube));
  nan_cube.vertices[3].y() = std::numeric_limits<double>::infinity();
  write_text(folder / "inf.obj", obj(nan_cube, {{"", all_faces(nan_cube)}}));
  write_text(folder / "points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");

  for (const char* name : {"missing.stl", "empty.stl", "truncated.stl", "notes.stl", "notes.obj", "notes.txt",
                           "random.stl", "random.ply", "nan_ascii.stl", "nan_binary.stl", "inf.obj", "points.obj"}) {
    const std::string message = read_error(folder / name);
    EXPECT_NE(message.find((folder / name).string()), std::string::npos) << name << ": '" << message << "'";
  }
  EXPECT_NE(read_error(folder / "missing.stl").find("not found"), std::string::npos);
  EXPECT_NE(read_error(folder / "empty.stl").find("empty"), std::string::npos);
  EXPECT_NE(read_error(folder / "truncated.stl").find("truncated"), std::string::npos);
  EXPECT_NE(read_error(folder / "nan_ascii.stl").find("non-finite"), std::string::npos);
  EXPECT_NE(read_error(folder / "nan_binary.stl").find("non-finite"), std::string::npos);
  EXPECT_NE(read_error(folder / "inf.obj").find("non-finite"), std::string::npos);
}

TEST(Mesh, MalformedMeshesBuiltInCodeAreRejected) {
  TriangleMesh bad_index = unit_cube();
  bad_index.faces[4][1] = 8;
  EXPECT_THROW(geometry::check_mesh(bad_index), MeshError);
  EXPECT_THROW(geometry::repair_mesh(bad_index), MeshError);
  EXPECT_THROW(geometry::MeshShape(bad_index, true, "bad"), MeshError);
  TriangleMesh bad_vertex = unit_cube();
  bad_vertex.vertices[2].x() = std::numeric_limits<double>::infinity();
  EXPECT_THROW(geometry::check_mesh(bad_vertex), MeshError);
  EXPECT_THROW(geometry::MeshShape(bad_vertex, false, "bad"), MeshError);
  EXPECT_THROW(geometry::MeshShape(TriangleMesh{}, true, "empty"), MeshError);
}

TEST(Mesh, ObjGroupsBecomeRegions) {
  const TemporaryFolder folder;
  const TriangleMesh cube = unit_cube();
  write_text(folder / "groups.obj", obj(cube, {{"caps", {0, 1, 2, 3}}, {"sides", {4, 5, 6, 7, 8, 9, 10, 11}}}));
  const TriangleMesh mesh = geometry::read_mesh(folder / "groups.obj");
  expect_unit_cube(mesh, 1.0, "groups.obj");
  ASSERT_EQ(mesh.region_names, (std::vector<std::string>{"caps", "sides"}));
  EXPECT_EQ(std::count(mesh.face_region.begin(), mesh.face_region.end(), 0), 4);
  EXPECT_EQ(std::count(mesh.face_region.begin(), mesh.face_region.end(), 1), 8);
  for (std::size_t f = 0; f < mesh.n_faces(); ++f) {  // caps are the faces whose normal is along z
    const auto& face = mesh.faces[f];
    const Vec3 n = (mesh.vertices[face[1]] - mesh.vertices[face[0]]).cross(mesh.vertices[face[2]] - mesh.vertices[face[0]]);
    EXPECT_EQ(mesh.face_region[f] == 0, std::abs(n.z()) > 0.5) << f;
  }

  const TriangleMesh sides = geometry::extract_region(mesh, 1);
  EXPECT_EQ(sides.n_faces(), 8u);
  EXPECT_EQ(sides.vertices.size(), 8u);
  EXPECT_EQ(sides.region_names, std::vector<std::string>{"sides"});
  EXPECT_EQ(geometry::check_mesh(sides).border_edges, 8u);  // two square rims
  const TriangleMesh caps = geometry::extract_region(mesh, 0);
  EXPECT_EQ(caps.n_faces(), 4u);
  EXPECT_EQ(caps.vertices.size(), 8u);
  EXPECT_THROW(geometry::extract_region(mesh, 2), std::out_of_range);
}

TEST(Mesh, AsciiStlSolidsBecomeRegions) {
  const TemporaryFolder folder;
  const TriangleMesh cube = unit_cube();
  write_text(folder / "solids.stl", ascii_stl(without_faces(cube, {2, 3}), "wall") +
                                        ascii_stl(without_faces(cube, {0, 1, 4, 5, 6, 7, 8, 9, 10, 11}), "lid"));
  const TriangleMesh mesh = geometry::read_mesh(folder / "solids.stl");
  expect_unit_cube(mesh, 1.0, "solids.stl");
  ASSERT_EQ(mesh.region_names, (std::vector<std::string>{"wall", "lid"}));
  EXPECT_EQ(geometry::extract_region(mesh, 0).n_faces(), 10u);
  EXPECT_EQ(geometry::extract_region(mesh, 1).n_faces(), 2u);

  // A name in UTF-8 does not make the file look binary.
  write_text(folder / "utf8.stl", ascii_stl(cube, "w\xc3\xbcrfel"));
  const TriangleMesh utf8 = geometry::read_mesh(folder / "utf8.stl");
  expect_unit_cube(utf8, 1.0, "utf8.stl");
  EXPECT_EQ(utf8.region_names, std::vector<std::string>{"w\xc3\xbcrfel"});
}

TEST(Mesh, WrittenMeshesReadBack) {
  const TemporaryFolder folder;
  TriangleMesh cube = unit_cube();
  cube.region_names = {"caps", "sides"};
  for (std::size_t f = 0; f < cube.n_faces(); ++f) cube.face_region[f] = f < 4 ? 0 : 1;
  geometry::write_mesh(cube, folder / "cube.stl");
  geometry::write_mesh(cube, folder / "cube.obj");
  EXPECT_FALSE(fs::exists(folder / "cube.stl.partial"));
  EXPECT_EQ(fs::file_size(folder / "cube.stl"), 84u + 50u * 12u);
  expect_unit_cube(geometry::read_mesh(folder / "cube.stl"), 1.0, "written STL");
  const TriangleMesh obj_back = geometry::read_mesh(folder / "cube.obj");
  expect_unit_cube(obj_back, 1.0, "written OBJ");
  EXPECT_EQ(obj_back.region_names, cube.region_names);
  EXPECT_EQ(obj_back.face_region, cube.face_region);
  EXPECT_THROW(geometry::write_mesh(cube, folder / "cube.vtk"), MeshError);
}

TEST(Mesh, SharedBiventricularHeartIsValid) {
  // The weld by position is also checked on meshes the tests write themselves (the STL tests above).
  const fs::path path = fs::path(CARDIOSPH_SHARED_MESHES) / "biventricular_heart.stl";
  if (!fs::exists(path)) GTEST_SKIP() << "third-party mesh not found: " << path;
  const TriangleMesh heart = geometry::read_mesh(path);
  EXPECT_EQ(heart.n_faces(), 9972u);
  EXPECT_EQ(heart.vertices.size(), 4988u);
  const auto report = geometry::require_valid_mesh(heart, "biventricular_heart.stl");
  EXPECT_EQ(report.components, 1u);
  EXPECT_EQ(report.self_intersecting_faces, 0u);
  EXPECT_NEAR(report.volume, 116972.0, 1.0);
  const auto box = heart.bounding_box();
  EXPECT_NEAR(box.lower.x(), 2.5, 0.5);
  EXPECT_NEAR(box.lower.y(), 0.0, 0.5);
  EXPECT_NEAR(box.lower.z(), 2.6, 0.5);
  EXPECT_NEAR(box.upper.x(), 83.5, 0.5);
  EXPECT_NEAR(box.upper.y(), 70.0, 0.5);
  EXPECT_NEAR(box.upper.z(), 62.6, 0.5);

  const geometry::MeshShape shape(heart, true, "biventricular_heart.stl");
  EXPECT_NEAR(*shape.volume(), 116972.0, 1.0);
  EXPECT_EQ(shape.describe(), "mesh 'biventricular_heart.stl' (9972 faces)");
  // Far outside and at vertices.
  EXPECT_GT(shape.signed_distance(box.upper + Vec3::Constant(10)), 10.0);
  EXPECT_NEAR(shape.signed_distance(heart.vertices[0]), 0.0, 1e-9);
}

TEST(Mesh, MeshShapeOfUnitCube) {
  const geometry::MeshShape cube(unit_cube(), true, "cube");
  EXPECT_NEAR(cube.signed_distance(Vec3(0.5, 0.5, 0.5)), -0.5, 1e-15);
  EXPECT_NEAR(cube.signed_distance(Vec3(2, 0.5, 0.5)), 1.0, 1e-15);
  EXPECT_NEAR(cube.signed_distance(Vec3(0.5, 0.5, 1.25)), 0.25, 1e-15);
  EXPECT_NEAR(cube.signed_distance(Vec3(0.5, 0.5, 0.9)), -0.1, 1e-15);
  EXPECT_EQ(cube.signed_distance(Vec3(0.5, 0.25, 1.0)), 0.0);
  EXPECT_TRUE(cube.contains(Vec3(0.1, 0.2, 0.3)));
  EXPECT_FALSE(cube.contains(Vec3(1.1, 0.2, 0.3)));

  EXPECT_LT((cube.normal(Vec3(0.5, 0.5, 1.25)) - Vec3(0, 0, 1)).norm(), 1e-15);
  EXPECT_LT((cube.normal(Vec3(0.5, 0.5, 0.9)) - Vec3(0, 0, 1)).norm(), 1e-15);    // inside, near the top
  EXPECT_LT((cube.normal(Vec3(0.5, 0.25, 1.0)) - Vec3(0, 0, 1)).norm(), 1e-15);   // on the top
  EXPECT_LT((cube.normal(Vec3(-0.5, 0.5, 0.5)) - Vec3(-1, 0, 0)).norm(), 1e-15);

  const std::size_t top = cube.nearest_face(Vec3(0.5, 0.5, 1.25));
  for (int c = 0; c < 3; ++c) EXPECT_EQ(cube.mesh().vertices[cube.mesh().faces[top][c]].z(), 1.0);
  EXPECT_NEAR(cube.unsigned_distance(Vec3(0.5, 0.5, 0.9)), 0.1, 1e-15);
  EXPECT_NEAR(*cube.volume(), 1.0, 1e-15);
  const auto box = cube.bounding_box();
  EXPECT_EQ(box.lower, Vec3::Zero());
  EXPECT_EQ(box.upper, Vec3::Ones());
  EXPECT_EQ(cube.describe(), "mesh 'cube' (12 faces)");
}

TEST(Mesh, OpenSurfaceAnswersOnlyUnsignedQueries) {
  const geometry::MeshShape lidless(without_faces(unit_cube(), {2, 3}), false, "lidless");
  EXPECT_NEAR(lidless.unsigned_distance(Vec3(0.5, 0.5, 1.25)), std::sqrt(0.5 * 0.5 + 0.25 * 0.25), 1e-15);
  EXPECT_NEAR(lidless.unsigned_distance(Vec3(0.5, 0.5, 0.25)), 0.25, 1e-15);
  const std::size_t bottom = lidless.nearest_face(Vec3(0.5, 0.4, -1));
  EXPECT_LT(bottom, 2u);
  EXPECT_THROW(lidless.signed_distance(Vec3(0.5, 0.5, 0.5)), std::logic_error);
  EXPECT_THROW(lidless.normal(Vec3(0.5, 0.5, 0.5)), std::logic_error);
  EXPECT_THROW(lidless.volume(), std::logic_error);
  EXPECT_NE(lidless.describe().find("lidless"), std::string::npos);
}

TEST(Mesh, MeshShapeQueriesAreThreadSafe) {
  const geometry::MeshShape cube(unit_cube(), true, "cube");
  constexpr std::size_t n = 10000;
  std::mt19937_64 engine(342343901);
  std::vector<Vec3> points(n);
  for (Vec3& p : points) p = Vec3(uniform(engine), uniform(engine), uniform(engine)) * 2.0 - Vec3::Constant(0.5);

  std::vector<double> serial_distance(n), parallel_distance(n);
  std::vector<Vec3> serial_normal(n), parallel_normal(n);
  std::vector<std::size_t> serial_face(n), parallel_face(n);
  sph::sequential_for(n, [&](std::size_t i) {
    serial_distance[i] = cube.signed_distance(points[i]);
    serial_normal[i] = cube.normal(points[i]);
    serial_face[i] = cube.nearest_face(points[i]);
  });
  sph::parallel_for(n, [&](std::size_t i) {
    parallel_distance[i] = cube.signed_distance(points[i]);
    parallel_normal[i] = cube.normal(points[i]);
    parallel_face[i] = cube.nearest_face(points[i]);
  });
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_EQ(serial_distance[i], parallel_distance[i]) << i;
    ASSERT_EQ(serial_normal[i], parallel_normal[i]) << i;
    ASSERT_EQ(serial_face[i], parallel_face[i]) << i;
    ASSERT_NEAR(serial_distance[i], unit_cube_distance(points[i]), 1e-14) << points[i].transpose();
  }
}
