// Tetrahedral meshes (.vtu and openCARP): reading and writing, checks that name the file and the
// element, the boundary surface, point location; and a heart geometry from a mesh the project
// makes itself (its LV ellipsoid tetrahedralised by TetGen, Debian package tetgen) with an analytic
// fibre field, whose fibre angle after interpolation to the particles is measured.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

#include "apps/scenes/electromechanics/em_scenes.hpp"
#include "cardio/fibres.hpp"
#include "cardio/heart_geometry.hpp"
#include "geometry/heart_meshes.hpp"
#include "geometry/tet_mesh.hpp"
#include "libsph/io/parameters.hpp"
#include "run_scene_for_test.hpp"
#include "temporary_folder.hpp"

namespace {

namespace fs = std::filesystem;
using geometry::MeshError;
using geometry::TetMesh;
using geometry::Vec3;

// The unit cube split into six tetrahedra around its diagonal (0,0,0)-(1,1,1), all positive.
TetMesh unit_cube() {
  TetMesh m;
  for (int k = 0; k < 8; ++k) m.vertices.emplace_back(k & 1, (k >> 1) & 1, (k >> 2) & 1);
  const int paths[6][2] = {{1, 3}, {1, 5}, {2, 3}, {2, 6}, {4, 5}, {4, 6}};  // 0 -> a -> b -> 7
  for (const auto& p : paths) {
    std::array<std::uint32_t, 4> t{0, std::uint32_t(p[0]), std::uint32_t(p[1]), 7};
    m.tets.push_back(t);
    if (m.signed_volume6(m.tets.size() - 1) < 0) std::swap(m.tets.back()[1], m.tets.back()[2]);
    m.tet_region.push_back(int(m.tets.size()) % 2 + 1);
  }
  m.fibre_location = TetMesh::FibreLocation::cells;
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    m.fibre.push_back(Vec3(1, 0.1 * double(t), 0).normalized());
    m.sheet.emplace_back(0, 0, 1);
  }
  return m;
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const MeshError& e) {
    return e.what();
  }
  return "(no MeshError)";
}

void write_text(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

// Reads and checks, as the geometry stage does.
void read_and_check(const fs::path& path, double scale = 1) {
  TetMesh m = geometry::read_tet_mesh(path, scale);
  geometry::check_tet_mesh(m, path.string());
}

TEST(TetMesh, OpenCarpAndVtuRoundTrip) {
  const test::TemporaryFolder folder("tets");
  TetMesh cube = unit_cube();
  const auto check = geometry::check_tet_mesh(cube, "cube");
  EXPECT_NEAR(check.volume, 1.0, 1e-14);
  EXPECT_FALSE(check.reoriented);
  EXPECT_NEAR(check.min_quality, std::sqrt(2.0) / (std::sqrt(3.0) * std::sqrt(3.0) * std::sqrt(3.0)), 1e-12);

  // openCARP in um, read back in mm.
  geometry::write_tet_mesh(cube, folder / "cube.elem", 1e-3);
  ASSERT_TRUE(fs::exists(folder / "cube.pts") && fs::exists(folder / "cube.lon"));
  const TetMesh carp = geometry::read_tet_mesh(folder / "cube.pts", geometry::millimetres_per_unit("um"));
  ASSERT_EQ(carp.vertices.size(), 8u);
  for (std::size_t i = 0; i < 8; ++i) EXPECT_LT((carp.vertices[i] - cube.vertices[i]).norm(), 1e-12);
  EXPECT_EQ(carp.tets, cube.tets);
  EXPECT_EQ(carp.tet_region, cube.tet_region);
  EXPECT_EQ(carp.fibre_location, TetMesh::FibreLocation::cells);
  ASSERT_EQ(carp.sheet.size(), 6u);
  for (std::size_t t = 0; t < 6; ++t) EXPECT_LT((carp.fibre[t] - cube.fibre[t]).norm(), 1e-14);
  EXPECT_EQ(geometry::tet_mesh_files(folder / "cube.elem").size(), 3u);

  // .vtu with point fibres.
  TetMesh points = cube;
  points.fibre_location = TetMesh::FibreLocation::points;
  points.fibre.assign(8, Vec3(0, 1, 0));
  points.sheet.clear();
  geometry::write_tet_mesh(points, folder / "cube.vtu");
  const TetMesh vtu = geometry::read_tet_mesh(folder / "cube.vtu", 2.0);
  EXPECT_EQ(vtu.tets, cube.tets);
  EXPECT_EQ(vtu.tet_region, cube.tet_region);
  EXPECT_EQ(vtu.fibre_location, TetMesh::FibreLocation::points);
  EXPECT_TRUE(vtu.sheet.empty());
  EXPECT_LT((vtu.vertices[7] - Vec3(2, 2, 2)).norm(), 1e-14);

  // The boundary: 12 triangles, closed, outward, volume 1; regions from the two tags.
  const auto surface = geometry::boundary_surface(cube);
  EXPECT_EQ(surface.n_faces(), 12u);
  EXPECT_EQ(surface.vertices.size(), 8u);
  const auto report = geometry::require_valid_mesh(surface, "cube boundary");
  EXPECT_NEAR(report.volume, 1.0, 1e-14);
  EXPECT_EQ(surface.region_names, (std::vector<std::string>{"tag 1", "tag 2"}));
}

TEST(TetMesh, TaggedTrianglesOfAVtuNameTheBoundary) {
  const test::TemporaryFolder folder("tets");
  TetMesh cube = unit_cube();
  // Tag the two triangles of the face z = 1 (vertices 4..7) with 9.
  for (const auto& t : cube.tets) {
    std::vector<std::uint32_t> top;
    for (auto v : t)
      if (v >= 4) top.push_back(v);
    if (top.size() == 3) {
      cube.tagged_faces.push_back({top[0], top[1], top[2]});
      cube.tagged_face_region.push_back(9);
    }
  }
  ASSERT_EQ(cube.tagged_faces.size(), 2u);
  geometry::write_tet_mesh(cube, folder / "tagged.vtu");
  const TetMesh read = geometry::read_tet_mesh(folder / "tagged.vtu");
  EXPECT_EQ(read.tets.size(), 6u);  // the triangles are not tetrahedra
  ASSERT_EQ(read.tagged_faces.size(), 2u);
  const auto surface = geometry::boundary_surface(read);
  std::size_t nine = 0;
  for (std::size_t f = 0; f < surface.n_faces(); ++f) {
    if (surface.region_names[std::size_t(surface.face_region[f])] != "tag 9") continue;
    ++nine;
    for (auto v : surface.faces[f]) EXPECT_EQ(surface.vertices[v].z(), 1.0);
  }
  EXPECT_EQ(nine, 2u);
}

TEST(TetMesh, AllNegativeTetrahedraAreFlippedAsAWhole) {
  TetMesh cube = unit_cube();
  for (auto& t : cube.tets) std::swap(t[0], t[1]);
  const auto check = geometry::check_tet_mesh(cube, "mirrored");
  EXPECT_TRUE(check.reoriented);
  for (std::size_t t = 0; t < cube.n_tets(); ++t) EXPECT_GT(cube.signed_volume6(t), 0);
}

TEST(TetMesh, BadInputNamesTheFileAndTheElement) {
  const test::TemporaryFolder folder("tets");
  const TetMesh cube = unit_cube();
  geometry::write_tet_mesh(cube, folder / "good.elem");
  auto pts = [&] {
    std::ifstream in(folder / "good.pts");
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }();
  auto elem_with = [&](std::size_t bad, const std::string& line) {
    std::ostringstream s;
    s << cube.n_tets() << '\n';
    for (std::size_t t = 0; t < cube.n_tets(); ++t) {
      const auto& v = cube.tets[t];
      if (t == bad)
        s << line << '\n';
      else
        s << "Tt " << v[0] << ' ' << v[1] << ' ' << v[2] << ' ' << v[3] << " 1\n";
    }
    return s.str();
  };
  auto expect = [&](const std::string& stem, const std::vector<std::string>& parts) {
    const std::string m = message_of([&] { read_and_check(folder / (stem + ".elem")); });
    for (const auto& part : parts) EXPECT_NE(m.find(part), std::string::npos) << "message: " << m << "\nexpected: " << part;
    std::cout << "[ rejected ] " << m << '\n';
  };
  // Inverted: tetrahedron 3 with two vertices swapped.
  const auto& t3 = cube.tets[3];
  write_text(folder / "inverted.pts", pts);
  write_text(folder / "inverted.elem", elem_with(3, "Tt " + std::to_string(t3[1]) + " " + std::to_string(t3[0]) + " " +
                                                        std::to_string(t3[2]) + " " + std::to_string(t3[3]) + " 1"));
  expect("inverted", {"inverted.elem", "element 3", "inverted"});
  // Degenerate: a tetrahedron on four coplanar vertices of the face z = 0.
  write_text(folder / "flat.pts", pts);
  write_text(folder / "flat.elem", elem_with(2, "Tt 0 1 3 2 1"));
  expect("flat", {"flat.elem", "element 2", "degenerate"});
  // A vertex index out of range, and an element that is not a tetrahedron.
  write_text(folder / "range.pts", pts);
  write_text(folder / "range.elem", elem_with(4, "Tt 0 1 3 8 1"));
  expect("range", {"range.elem", "line 6", "element 4", "vertex 8"});
  write_text(folder / "hex.pts", pts);
  write_text(folder / "hex.elem", elem_with(1, "Hx 0 1 3 2 4 5 7 6 1"));
  expect("hex", {"hex.elem", "element 1", "Hx", "only tetrahedra"});
  // Fibres: one line short, a NaN, a zero vector.
  auto lon_with = [&](std::size_t lines, std::size_t bad, const std::string& value) {
    std::ostringstream s;
    s << "1\n";
    for (std::size_t t = 0; t < lines; ++t) s << (t == bad ? value : "1 0 0") << '\n';
    return s.str();
  };
  for (const auto& [stem, lon, parts] :
       std::vector<std::tuple<std::string, std::string, std::vector<std::string>>>{
           {"short", lon_with(5, 99, ""), {"short.lon", "5 fibres", "6 elements"}},
           {"nan", lon_with(6, 2, "nan 0 1"), {"nan.lon", "line 4", "element 2", "not finite"}},
           {"zero", lon_with(6, 4, "0 0 0"), {"zero.lon", "line 6", "element 4", "zero"}},
           {"sheetless", lon_with(6, 1, "1 0 0 0 1 0"), {"sheetless.lon", "line 3", "element 1", "6 values, expected 3"}}}) {
    write_text(folder / (stem + ".pts"), pts);
    write_text(folder / (stem + ".elem"), elem_with(99, ""));
    write_text(folder / (stem + ".lon"), lon);
    expect(stem, parts);
  }
  // A .vtu whose point fibre is NaN.
  TetMesh nan_points = cube;
  nan_points.fibre_location = TetMesh::FibreLocation::points;
  nan_points.fibre.assign(8, Vec3(1, 0, 0));
  nan_points.fibre[5] = Vec3(std::nan(""), 0, 0);
  nan_points.sheet.clear();
  geometry::write_tet_mesh(nan_points, folder / "nan.vtu");
  const std::string m = message_of([&] { read_and_check(folder / "nan.vtu"); });
  EXPECT_NE(m.find("nan.vtu"), std::string::npos) << m;
  EXPECT_NE(m.find("point 5 is not finite"), std::string::npos) << m;
  // Missing companion file, not a .vtu, unknown units.
  fs::remove(folder / "good.pts");
  EXPECT_NE(message_of([&] { read_and_check(folder / "good.elem"); }).find("good.pts': no such file"), std::string::npos);
  write_text(folder / "text.vtu", "not xml");
  EXPECT_NE(message_of([&] { read_and_check(folder / "text.vtu"); }).find("text.vtu"), std::string::npos);
  EXPECT_NE(message_of([] { geometry::millimetres_per_unit("furlong"); }).find("'furlong'"), std::string::npos);
}

TEST(TetMesh, LocatorInterpolatesALinearFieldExactly) {
  const TetMesh cube = unit_cube();
  const geometry::TetLocator locator(cube);
  auto field = [](const Vec3& x) { return 1 + 2 * x.x() - 3 * x.y() + 0.5 * x.z(); };
  double worst = 0;
  for (int i = 0; i < 200; ++i) {
    const Vec3 p(std::fmod(0.137 * i, 1.0), std::fmod(0.291 * i + 0.05, 1.0), std::fmod(0.713 * i + 0.11, 1.0));
    const auto hit = locator.locate(p);
    EXPECT_TRUE(hit.inside);
    double value = 0;
    for (std::size_t k = 0; k < 4; ++k) value += hit.weights[k] * field(cube.vertices[cube.tets[hit.tet][k]]);
    worst = std::max(worst, std::abs(value - field(p)));
  }
  EXPECT_LT(worst, 1e-12);
  const auto outside = locator.locate(Vec3(1.2, 0.5, 0.5));
  EXPECT_FALSE(outside.inside);
  double sum = 0;
  for (double w : outside.weights) sum += w;
  EXPECT_NEAR(sum, 1.0, 1e-14);
}

// ---------------------------------------------------------------------------------------------
// The LV ellipsoid through TetGen.

std::string tetgen_command() {
  for (const char* dir : {"/usr/bin", "/usr/local/bin"})
    if (fs::exists(fs::path(dir) / "tetgen")) return (fs::path(dir) / "tetgen").string();
  return "";
}

// Reads TetGen's .node and .ele (first index 0 or 1).
TetMesh read_tetgen(const fs::path& node, const fs::path& ele) {
  TetMesh m;
  std::ifstream n(node), e(ele);
  long count = 0, dim = 0, attributes = 0, markers = 0;
  n >> count >> dim >> attributes >> markers;
  long first = -1;
  for (long i = 0; i < count; ++i) {
    long index;
    double x, y, z, skip;
    n >> index >> x >> y >> z;
    for (long k = 0; k < attributes + markers; ++k) n >> skip;
    if (first < 0) first = index;
    m.vertices.emplace_back(x, y, z);
  }
  long tets = 0, corners = 0, region = 0;
  e >> tets >> corners >> region;
  for (long t = 0; t < tets; ++t) {
    long index, a, b, c, d, skip;
    e >> index >> a >> b >> c >> d;
    for (long k = 0; k < region; ++k) e >> skip;
    m.tets.push_back({std::uint32_t(a - first), std::uint32_t(b - first), std::uint32_t(c - first), std::uint32_t(d - first)});
  }
  return m;
}

// The analytic fibre of the LV: helix angle alpha_endo (1 - t) + alpha_epi t from the
// circumferential towards the longitudinal direction (cardio::lv_ellipsoid_frame); sheet = the
// wall normal.
struct AnalyticFibre {
  geometry::LvEllipsoid lv;
  double alpha_endo = 60, alpha_epi = -60;
  Vec3 fibre(const Vec3& p) const {
    const auto f = cardio::lv_ellipsoid_frame(p, lv);
    const double a = (alpha_endo * (1 - f.t) + alpha_epi * f.t) * M_PI / 180;
    return std::cos(a) * f.circumferential + std::sin(a) * f.longitudinal;
  }
  Vec3 sheet(const Vec3& p) const { return cardio::lv_ellipsoid_frame(p, lv).normal; }
};

struct AngleError {
  double mean = 0, p95 = 0, max = 0;
  std::size_t particles = 0;
};

// Angle between the particles' fibres and the analytic ones, away from the base rim and the axis.
AngleError angle_error(const std::vector<Vec3>& x, const std::vector<Vec3>& fibre, const AnalyticFibre& a, double rim,
                       double axis) {
  std::vector<double> angles;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (x[i].z() > a.lv.base_z - rim || std::hypot(x[i].x(), x[i].y()) < axis) continue;
    const double c = std::min(1.0, std::abs(fibre[i].normalized().dot(a.fibre(x[i]))));
    angles.push_back(std::acos(c) * 180 / M_PI);
  }
  AngleError e;
  e.particles = angles.size();
  if (angles.empty()) return e;
  for (double v : angles) e.mean += v / double(angles.size());
  std::sort(angles.begin(), angles.end());
  e.p95 = angles[std::size_t(0.95 * double(angles.size() - 1))];
  e.max = angles.back();
  return e;
}

TEST(TetMeshHeart, LvEllipsoidFromTetGenCarriesItsFibresToTheParticles) {
  const std::string tetgen = tetgen_command();
  if (tetgen.empty()) GTEST_SKIP() << "needs TetGen: no /usr/bin/tetgen or /usr/local/bin/tetgen (Debian package tetgen)";
  const test::TemporaryFolder folder("tets");
  const AnalyticFibre analytic;
  const auto surface = geometry::lv_ellipsoid_mesh(analytic.lv, 1.0);
  geometry::write_mesh(surface, folder / "lv.off");
  // -p: tetrahedralise the closed surface; -q1.5: radius-edge ratio; -a0.2: largest volume
  // [mm^3]; -Y: keep the surface triangles; -Q: quiet.
  const std::string command = tetgen + " -pq1.5a0.2YQ " + (folder / "lv.off").string() + " > /dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  TetMesh lv = read_tetgen(folder / "lv.1.node", folder / "lv.1.ele");
  ASSERT_GT(lv.n_tets(), 1000u);
  geometry::check_tet_mesh(lv, "tetgen lv");

  // Point fibres and sheets in a .vtu (mm); element fibres at the centroids in openCARP (um).
  TetMesh on_points = lv;
  on_points.fibre_location = TetMesh::FibreLocation::points;
  for (const Vec3& v : lv.vertices) {
    on_points.fibre.push_back(analytic.fibre(v));
    on_points.sheet.push_back(analytic.sheet(v));
  }
  geometry::write_tet_mesh(on_points, folder / "lv.vtu");
  TetMesh on_cells = lv;
  on_cells.fibre_location = TetMesh::FibreLocation::cells;
  for (const auto& t : lv.tets) {
    const Vec3 c = 0.25 * (lv.vertices[t[0]] + lv.vertices[t[1]] + lv.vertices[t[2]] + lv.vertices[t[3]]);
    on_cells.fibre.push_back(analytic.fibre(c));
  }
  geometry::write_tet_mesh(on_cells, folder / "lv_carp.elem", 1e-3);

  const double dp = 1.0, rim = 1.5, axis = 2.0;
  cardio::HeartGeometrySettings s;
  s.spacing = dp;
  s.relaxation_steps = 50;
  s.ldrb.alpha_endo_deg = analytic.alpha_endo;
  s.ldrb.alpha_epi_deg = analytic.alpha_epi;
  auto run = [&](const fs::path& mesh, double scale, const std::string& fibres) {
    s.mesh = mesh;
    s.scale = scale;
    s.fibres = fibres;
    return cardio::prepare_heart_geometry(s, {});
  };
  const auto points = run(folder / "lv.vtu", 1.0, "auto");
  const auto cells = run(folder / "lv_carp.pts", geometry::millimetres_per_unit("um"), "auto");
  const auto ldrb = run(folder / "lv.vtu", 1.0, "ldrb");
  EXPECT_EQ(points.fibre_method, "mesh (points)");
  EXPECT_EQ(cells.fibre_method, "mesh (cells)");
  EXPECT_EQ(ldrb.fibre_method, "ldrb");
  EXPECT_EQ(points.tets, lv.n_tets());
  EXPECT_EQ(points.label_method, "geometric rule");
  // The same particles from either file (the same boundary, in mm).
  ASSERT_EQ(points.body.size(), cells.body.size());
  EXPECT_EQ(points.body.positions, ldrb.body.positions);
  // Mesh fibres keep the LDRB coordinates; the .vtu's sheets are used, orthogonal to the fibre.
  EXPECT_EQ(points.fibres.transmural.size(), points.body.size());
  double worst_dot = 0;
  for (std::size_t i = 0; i < points.body.size(); ++i)
    worst_dot = std::max(worst_dot, std::abs(points.fibres.fibre[i].dot(points.fibres.sheet[i])));
  EXPECT_LT(worst_dot, 1e-12);

  // Surface labels from tags: the boundary's faces labelled by the geometric rule and written as
  // tagged triangles give the same particle labels through surface_tags.
  {
    TetMesh tagged = on_points;
    const auto boundary = geometry::boundary_surface(lv);
    const auto rule = cardio::face_labels_by_rule(boundary);
    // The boundary's vertices are renumbered: map them back by position.
    std::map<std::array<double, 3>, std::uint32_t> index;
    for (std::size_t v = 0; v < lv.vertices.size(); ++v)
      index[{lv.vertices[v].x(), lv.vertices[v].y(), lv.vertices[v].z()}] = std::uint32_t(v);
    for (std::size_t f = 0; f < boundary.n_faces(); ++f) {
      std::array<std::uint32_t, 3> face{};
      for (std::size_t k = 0; k < 3; ++k) {
        const Vec3& x = boundary.vertices[boundary.faces[f][k]];
        face[k] = index.at({x.x(), x.y(), x.z()});
      }
      tagged.tagged_faces.push_back(face);
      tagged.tagged_face_region.push_back(int(rule.face[f]) * 10);
    }
    tagged.tet_region.assign(lv.n_tets(), 0);
    geometry::write_tet_mesh(tagged, folder / "lv_tagged.vtu");
    s.surface_tags = "epi=10, lv_endo=20, base=40";
    const auto by_tags = run(folder / "lv_tagged.vtu", 1.0, "auto");
    EXPECT_EQ(by_tags.label_method, "regions");
    EXPECT_EQ(by_tags.labels, points.labels);
    s.surface_tags = "epi=10,lv_endo=20";  // the base faces' tag 40 is left unnamed
    EXPECT_THROW(run(folder / "lv_tagged.vtu", 1.0, "auto"), MeshError);
    s.surface_tags = "epi=10,heart=20";
    EXPECT_THROW(run(folder / "lv_tagged.vtu", 1.0, "auto"), std::invalid_argument);
    s.surface_tags.clear();
  }

  const auto e_points = angle_error(points.body.positions, points.fibres.fibre, analytic, rim, axis);
  const auto e_cells = angle_error(cells.body.positions, cells.fibres.fibre, analytic, rim, axis);
  const auto e_ldrb = angle_error(ldrb.body.positions, ldrb.fibres.fibre, analytic, rim, axis);
  std::printf("[ measured ] TetGen LV: %zu tetrahedra, %zu vertices; %zu particles at dp %.2f mm, %zu outside every "
              "tetrahedron\n",
              lv.n_tets(), lv.vertices.size(), points.body.size(), dp, points.fibre_particles_outside);
  std::printf("[ measured ] fibre angle to the analytic field over %zu particles: mean / p95 / max [deg]\n"
              "             point fibres (.vtu)     %6.2f %6.2f %6.2f\n"
              "             element fibres (openCARP) %6.2f %6.2f %6.2f\n"
              "             LDRB on the same particles %6.2f %6.2f %6.2f\n",
              e_points.particles, e_points.mean, e_points.p95, e_points.max, e_cells.mean, e_cells.p95, e_cells.max,
              e_ldrb.mean, e_ldrb.p95, e_ldrb.max);
  // Bounds: point fibres are interpolated linearly, so the error is second order in the element size
  // (~1 mm here, against a field that turns 120 degrees across the 3 mm wall); element fibres are
  // piecewise constant, off by up to half an element's turn. LDRB is printed for scale only: its
  // transmural coordinate (a Laplace solution) is not the analytic field's t.
  EXPECT_LT(e_points.mean, 1.0);
  EXPECT_LT(e_points.max, 5.0);
  EXPECT_LT(e_cells.mean, 8.0);
}

// The heart scene on a biventricular mesh brought as openCARP files in um, without fibres (LDRB
// then) and paced at a .vtx list of mesh nodes near the apex.
TEST(TetMeshHeart, HeartRunsOnAnOpenCarpMeshPacedAtMeshNodes) {
  const std::string tetgen = tetgen_command();
  if (tetgen.empty()) GTEST_SKIP() << "needs TetGen: no /usr/bin/tetgen or /usr/local/bin/tetgen (Debian package tetgen)";
  const test::TemporaryFolder folder("tets");
  geometry::write_mesh(geometry::biventricular_mesh(geometry::Biventricular{}, 3.0), folder / "biv.off");
  const std::string command = tetgen + " -pq1.5a30YQ " + (folder / "biv.off").string() + " > /dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  TetMesh biv = read_tetgen(folder / "biv.1.node", folder / "biv.1.ele");
  geometry::write_tet_mesh(biv, folder / "biv.elem", 1e-3);
  // The nodes within 4 mm of the lowest one.
  double z_min = 1e300;
  for (const Vec3& v : biv.vertices) z_min = std::min(z_min, v.z());
  std::vector<std::size_t> apex;
  for (std::size_t v = 0; v < biv.vertices.size(); ++v)
    if (biv.vertices[v].z() < z_min + 4) apex.push_back(v);
  {
    std::ofstream vtx(folder / "apex.vtx");
    vtx << apex.size() << "\nintra\n";
    for (auto v : apex) vtx << v << '\n';
  }
  auto run = [&](const std::vector<std::string>& extra) {
    auto scene = cardiosph::make_heart_scene();
    std::vector<std::string> assignments{"preset=coarse", "mesh=" + (folder / "biv.elem").string(), "units=um",
                                         "end_time=2", "output_interval=0"};
    assignments.insert(assignments.end(), extra.begin(), extra.end());
    sph::Parameters parameters;
    test::set_parameters(*scene, parameters, assignments);
    return test::run_scene(*scene, "heart_tets");
  };
  const auto r = run({"stimulus_site=nodes", "stimulus_nodes=" + (folder / "apex.vtx").string(), "stimulus_radius=3"});
  EXPECT_EQ(r.status, "completed");
  const auto particles = r.particles.json().begin().value().get<double>();
  const auto stimulated = r.results.at("stimulated_particles").get<double>();
  std::printf("[ measured ] heart on %zu tetrahedra (openCARP, um): %.0f particles, %.0f stimulated at %zu apical nodes, "
              "fibres %s\n",
              biv.n_tets(), particles, stimulated, apex.size(), r.results.at("fibre_method").get<std::string>().c_str());
  EXPECT_EQ(r.results.at("fibre_method"), "ldrb");
  EXPECT_GT(stimulated, 0);
  EXPECT_LT(stimulated, 0.1 * particles);
  // A node list that points past the mesh is refused, naming the file and the line.
  {
    std::ofstream vtx(folder / "bad.vtx");
    vtx << "2\nintra\n0\n" << biv.vertices.size() << '\n';
  }
  try {
    run({"stimulus_site=nodes", "stimulus_nodes=" + (folder / "bad.vtx").string()});
    ADD_FAILURE() << "a node beyond the mesh was accepted";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.vtx' line 4"), std::string::npos) << e.what();
  }
  const auto epi = run({"stimulus_site=surface", "stimulus_surface=epi"});
  EXPECT_GT(epi.results.at("stimulated_particles").get<double>(), stimulated);
}

}  // namespace
