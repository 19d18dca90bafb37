// Tetrahedral meshes: the openCARP reader and writer, checks, boundary surface and point location.
// The .vtu side is in tet_mesh_vtk.cpp (VTK stays there).

#include "geometry/tet_mesh.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include <Eigen/Dense>

#include "geometry/tet_mesh_vtk.hpp"
#include "libsph/io/atomic_file.hpp"

namespace geometry {
namespace {

namespace fs = std::filesystem;

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

[[noreturn]] void fail(const fs::path& path, const std::string& problem) {
  throw MeshError("tetrahedral mesh '" + path.string() + "': " + problem);
}

// Lines of a text file without '#' comments and blank lines, with their line numbers.
struct TextLines {
  fs::path path;
  std::ifstream in;
  long number = 0;
  explicit TextLines(fs::path p) : path(std::move(p)), in(path) {
    if (!in) fail(path, "cannot be opened for reading");
  }
  bool next(std::vector<std::string>& words) {
    std::string line;
    while (std::getline(in, line)) {
      ++number;
      if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
      std::istringstream s(line);
      words.clear();
      for (std::string w; s >> w;) words.push_back(w);
      if (!words.empty()) return true;
    }
    return false;
  }
  [[noreturn]] void fail_here(const std::string& problem) const {
    throw MeshError("tetrahedral mesh file '" + path.string() + "' line " + std::to_string(number) + ": " + problem);
  }
  double number_at(const std::vector<std::string>& words, std::size_t k) const {
    double value = 0;
    std::size_t used = 0;
    try {
      value = std::stod(words[k], &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != words[k].size()) fail_here("'" + words[k] + "' is not a number");
    return value;
  }
  /// The count on the first line: a whole number no larger than the lines the file can still hold
  /// (each entry is a line of at least two bytes), so that no count makes the reader reserve more
  /// memory than the file's size.
  long count_line() {
    std::vector<std::string> w;
    if (!next(w)) fail_here("empty file");
    const double c = number_at(w, 0);
    if (w.size() != 1 || !(c >= 0) || c != std::floor(c)) fail_here("expected the number of entries on the first line");
    std::error_code ec;
    const auto size = fs::file_size(path, ec);
    if (ec || c > double(size) / 2) fail_here("the count " + w[0] + " is more entries than the file can hold");
    return long(c);
  }
};

fs::path with_extension(fs::path p, const char* extension) { return p.replace_extension(extension); }

fs::path opencarp_base(const fs::path& path) {
  const std::string e = lower(path.extension().string());
  if (e == ".pts" || e == ".elem" || e == ".lon") return with_extension(path, "");
  return path;
}

TetMesh read_opencarp(const fs::path& path, double scale) {
  const fs::path base = opencarp_base(path);
  const fs::path pts = with_extension(base, ".pts"), elem = with_extension(base, ".elem"), lon = with_extension(base, ".lon");
  for (const auto& p : {pts, elem})
    if (!fs::is_regular_file(p)) fail(p, "no such file (an openCARP mesh needs .pts and .elem)");
  TetMesh mesh;
  std::vector<std::string> w;
  {
    TextLines lines(pts);
    const long n = lines.count_line();
    mesh.vertices.reserve(std::size_t(n));
    while (lines.next(w)) {
      if (w.size() != 3) lines.fail_here("expected 'x y z'");
      const Vec3 x(lines.number_at(w, 0), lines.number_at(w, 1), lines.number_at(w, 2));
      if (!x.allFinite()) lines.fail_here("point " + std::to_string(mesh.vertices.size()) + " is not finite");
      mesh.vertices.push_back(scale * x);
    }
    if (long(mesh.vertices.size()) != n)
      fail(pts, "the header announces " + std::to_string(n) + " points but the file holds " + std::to_string(mesh.vertices.size()));
  }
  {
    TextLines lines(elem);
    const long n = lines.count_line();
    mesh.tets.reserve(std::size_t(n));
    while (lines.next(w)) {
      const std::string element = "element " + std::to_string(mesh.tets.size());
      if (w[0] != "Tt") lines.fail_here(element + " is of type '" + w[0] + "': only tetrahedra (Tt) are read");
      if (w.size() != 5 && w.size() != 6) lines.fail_here(element + ": expected 'Tt n0 n1 n2 n3 [tag]'");
      std::array<std::uint32_t, 4> t{};
      for (int k = 0; k < 4; ++k) {
        const double v = lines.number_at(w, std::size_t(k + 1));
        if (v < 0 || v != std::floor(v) || v >= double(mesh.vertices.size()))
          lines.fail_here(element + " refers to vertex " + w[std::size_t(k + 1)] + " but there are " +
                          std::to_string(mesh.vertices.size()) + " points");
        t[std::size_t(k)] = std::uint32_t(v);
      }
      mesh.tets.push_back(t);
      const double tag = w.size() == 6 ? lines.number_at(w, 5) : 0.0;
      if (!(std::abs(tag) < 1e9) || tag != std::floor(tag)) lines.fail_here(element + ": the tag " + w[5] + " is not a whole number");
      mesh.tet_region.push_back(int(tag));
    }
    if (long(mesh.tets.size()) != n)
      fail(elem, "the header announces " + std::to_string(n) + " elements but the file holds " + std::to_string(mesh.tets.size()));
  }
  if (fs::is_regular_file(lon)) {
    TextLines lines(lon);
    // The header (1: fibres, 2: fibres and sheets) may be missing in old files: then the number of
    // values on the first line tells.
    if (!lines.next(w)) lines.fail_here("empty file");
    int vectors = 0;
    bool header = false;
    if (w.size() == 1) {
      const double v = lines.number_at(w, 0);
      if (v != 1 && v != 2) lines.fail_here("the header must be 1 (fibres) or 2 (fibres and sheets), not " + w[0]);
      vectors = int(v);
      header = true;
    } else if (w.size() == 3 || w.size() == 6) {
      vectors = int(w.size() / 3);
    } else {
      lines.fail_here("expected the header 1 or 2, or 3 or 6 values");
    }
    if (header && !lines.next(w)) w.clear();
    std::size_t element = 0;
    for (bool more = !w.empty(); more; more = lines.next(w)) {
      if (int(w.size()) != 3 * vectors)
        lines.fail_here("element " + std::to_string(element) + ": " + std::to_string(w.size()) + " values, expected " +
                        std::to_string(3 * vectors));
      const Vec3 f(lines.number_at(w, 0), lines.number_at(w, 1), lines.number_at(w, 2));
      if (!f.allFinite()) lines.fail_here("element " + std::to_string(element) + ": the fibre is not finite");
      if (f.norm() == 0) lines.fail_here("element " + std::to_string(element) + ": the fibre is zero");
      mesh.fibre.push_back(f);
      if (vectors == 2) mesh.sheet.emplace_back(lines.number_at(w, 3), lines.number_at(w, 4), lines.number_at(w, 5));
      ++element;
    }
    if (mesh.fibre.size() != mesh.tets.size())
      fail(lon, "holds " + std::to_string(mesh.fibre.size()) + " fibres but the mesh has " + std::to_string(mesh.tets.size()) +
                    " elements (one fibre per element)");
    mesh.fibre_location = TetMesh::FibreLocation::cells;
  }
  return mesh;
}

std::string element_text(const TetMesh& mesh, std::size_t t) {
  const auto& v = mesh.tets[t];
  return "element " + std::to_string(t) + " (vertices " + std::to_string(v[0]) + " " + std::to_string(v[1]) + " " +
         std::to_string(v[2]) + " " + std::to_string(v[3]) + ")";
}

double longest_edge(const TetMesh& mesh, std::size_t t) {
  const auto& v = mesh.tets[t];
  double l = 0;
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b) l = std::max(l, (mesh.vertices[v[std::size_t(a)]] - mesh.vertices[v[std::size_t(b)]]).norm());
  return l;
}

// The four faces of a positive tetrahedron, each oriented away from the opposite vertex.
constexpr int tet_faces[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

struct FaceKey {
  std::array<std::uint32_t, 3> sorted;
  std::uint32_t tet;
  std::uint8_t local;
  bool operator<(const FaceKey& o) const { return sorted < o.sorted; }
};

std::vector<FaceKey> sorted_faces(const TetMesh& mesh) {
  std::vector<FaceKey> faces;
  faces.reserve(4 * mesh.tets.size());
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    for (std::uint8_t k = 0; k < 4; ++k) {
      std::array<std::uint32_t, 3> f{mesh.tets[t][std::size_t(tet_faces[k][0])], mesh.tets[t][std::size_t(tet_faces[k][1])],
                                     mesh.tets[t][std::size_t(tet_faces[k][2])]};
      std::sort(f.begin(), f.end());
      faces.push_back({f, std::uint32_t(t), k});
    }
  std::sort(faces.begin(), faces.end());
  return faces;
}

}  // namespace

double TetMesh::signed_volume6(std::size_t t) const {
  const auto& v = tets[t];
  const Vec3& a = vertices[v[0]];
  return (vertices[v[1]] - a).cross(vertices[v[2]] - a).dot(vertices[v[3]] - a);
}

double millimetres_per_unit(const std::string& units) {
  if (units == "um") return 1e-3;
  if (units == "mm") return 1;
  if (units == "cm") return 10;
  if (units == "m") return 1000;
  throw MeshError("units '" + units + "': expected um, mm, cm or m");
}

bool is_tet_mesh_file(const fs::path& path) {
  const std::string e = lower(path.extension().string());
  return e == ".vtu" || e == ".pts" || e == ".elem" || e == ".lon";
}

std::vector<fs::path> tet_mesh_files(const fs::path& path) {
  const std::string e = lower(path.extension().string());
  if (e == ".vtu") return {path};
  if (e != ".pts" && e != ".elem" && e != ".lon") return {};
  const fs::path base = opencarp_base(path);
  std::vector<fs::path> files{with_extension(base, ".pts"), with_extension(base, ".elem")};
  if (fs::is_regular_file(with_extension(base, ".lon"))) files.push_back(with_extension(base, ".lon"));
  return files;
}

TetMesh read_tet_mesh(const fs::path& path, double scale) {
  if (!(scale > 0) || !std::isfinite(scale)) fail(path, "the scale must be positive");
  const std::string e = lower(path.extension().string());
  TetMesh mesh;
  if (e == ".vtu") {
    if (!fs::is_regular_file(path)) fail(path, "no such file");
    mesh = detail::read_vtu_tets(path, scale);
  } else if (e == ".pts" || e == ".elem" || e == ".lon") {
    mesh = read_opencarp(path, scale);
  } else {
    fail(path, "extension '" + e + "' is not .vtu, .pts or .elem");
  }
  if (mesh.tets.empty()) fail(path, "no tetrahedra");
  if (mesh.tet_region.size() != mesh.tets.size()) mesh.tet_region.assign(mesh.tets.size(), 0);
  return mesh;
}

std::vector<std::size_t> read_vertex_list(const fs::path& path, std::size_t n_vertices) {
  if (!fs::is_regular_file(path)) fail(path, "no such file");
  TextLines lines(path);
  const long n = lines.count_line();
  std::vector<std::size_t> nodes;
  std::vector<std::string> w;
  while (lines.next(w)) {
    if (nodes.empty() && w.size() == 1 && (w[0] == "intra" || w[0] == "extra")) continue;
    if (w.size() != 1) lines.fail_here("expected one node index");
    const double v = lines.number_at(w, 0);
    if (v < 0 || v != std::floor(v) || v >= double(n_vertices))
      lines.fail_here("node " + w[0] + " is not a vertex of the mesh (" + std::to_string(n_vertices) + " vertices)");
    nodes.push_back(std::size_t(v));
  }
  if (long(nodes.size()) != n)
    fail(path, "the header announces " + std::to_string(n) + " nodes but the file lists " + std::to_string(nodes.size()));
  if (nodes.empty()) fail(path, "no nodes");
  return nodes;
}

TetMeshCheck check_tet_mesh(TetMesh& mesh, const std::string& name) {
  auto bad = [&](const std::string& problem) { throw MeshError("tetrahedral mesh '" + name + "': " + problem); };
  TetMeshCheck check;
  check.vertices = mesh.vertices.size();
  check.tets = mesh.tets.size();
  const std::size_t n_fibres = mesh.fibre_location == TetMesh::FibreLocation::points ? mesh.vertices.size()
                               : mesh.fibre_location == TetMesh::FibreLocation::cells ? mesh.tets.size()
                                                                                       : 0;
  if (mesh.fibre.size() != n_fibres || (!mesh.sheet.empty() && mesh.sheet.size() != n_fibres))
    bad("the fibre or sheet array has " + std::to_string(mesh.fibre.size()) + " entries, expected " + std::to_string(n_fibres));
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    if (!mesh.vertices[i].allFinite()) bad("vertex " + std::to_string(i) + " is not finite");
  std::vector<double> volume6(mesh.tets.size());
  std::size_t negative = 0;
  check.min_quality = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& v = mesh.tets[t];
    for (auto k : v)
      if (k >= mesh.vertices.size())
        bad(element_text(mesh, t) + " refers to vertex " + std::to_string(k) + " but there are " +
            std::to_string(mesh.vertices.size()));
    const double l = longest_edge(mesh, t);
    volume6[t] = mesh.signed_volume6(t);
    if (!(std::abs(volume6[t]) > 1e-9 * l * l * l))
      bad(element_text(mesh, t) + " is degenerate: volume " + std::to_string(volume6[t] / 6) + " with longest edge " +
          std::to_string(l));
    if (volume6[t] < 0) ++negative;
    check.min_quality = std::min(check.min_quality, std::sqrt(2.0) * std::abs(volume6[t]) / (l * l * l));
  }
  const bool flip = negative * 2 > mesh.tets.size();
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    if ((volume6[t] < 0) != flip)
      bad(element_text(mesh, t) + " is inverted: signed volume " + std::to_string(volume6[t] / 6) + " while " +
          std::to_string(flip ? negative : mesh.tets.size() - negative) + " of the " + std::to_string(mesh.tets.size()) +
          " elements are " + (flip ? "negative" : "positive"));
  if (flip) {
    for (auto& t : mesh.tets) std::swap(t[1], t[2]);
    check.reoriented = true;
  }
  for (double v : volume6) check.volume += std::abs(v) / 6;

  const char* where = mesh.fibre_location == TetMesh::FibreLocation::points ? "point " : "element ";
  for (std::size_t i = 0; i < mesh.fibre.size(); ++i) {
    if (!mesh.fibre[i].allFinite()) bad(std::string("fibre of ") + where + std::to_string(i) + " is not finite");
    if (mesh.fibre[i].norm() == 0) bad(std::string("fibre of ") + where + std::to_string(i) + " is zero");
    if (!mesh.sheet.empty() && !mesh.sheet[i].allFinite())
      bad(std::string("sheet of ") + where + std::to_string(i) + " is not finite");
  }

  const auto faces = sorted_faces(mesh);
  for (std::size_t a = 0; a < faces.size();) {
    std::size_t b = a + 1;
    while (b < faces.size() && faces[b].sorted == faces[a].sorted) ++b;
    if (b - a > 2)
      bad("face (" + std::to_string(faces[a].sorted[0]) + " " + std::to_string(faces[a].sorted[1]) + " " +
          std::to_string(faces[a].sorted[2]) + ") of " + element_text(mesh, faces[a].tet) + " is shared by " +
          std::to_string(b - a) + " elements");
    a = b;
  }
  std::vector<char> used(mesh.vertices.size(), 0);
  for (const auto& t : mesh.tets)
    for (auto k : t) used[k] = 1;
  check.unused_vertices = std::size_t(std::count(used.begin(), used.end(), 0));
  return check;
}

TriangleMesh boundary_surface(const TetMesh& mesh) {
  const auto faces = sorted_faces(mesh);
  std::vector<std::pair<std::array<std::uint32_t, 3>, int>> tagged;
  for (std::size_t f = 0; f < mesh.tagged_faces.size(); ++f) {
    auto key = mesh.tagged_faces[f];
    std::sort(key.begin(), key.end());
    tagged.emplace_back(key, mesh.tagged_face_region[f]);
  }
  std::sort(tagged.begin(), tagged.end());
  TriangleMesh surface;
  std::vector<std::uint32_t> renumber(mesh.vertices.size(), std::numeric_limits<std::uint32_t>::max());
  std::vector<int> tags;
  for (std::size_t a = 0; a < faces.size();) {
    std::size_t b = a + 1;
    while (b < faces.size() && faces[b].sorted == faces[a].sorted) ++b;
    if (b - a == 1) {
      const auto& t = mesh.tets[faces[a].tet];
      std::array<std::uint32_t, 3> f{};
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = t[std::size_t(tet_faces[faces[a].local][k])];
        if (renumber[v] == std::numeric_limits<std::uint32_t>::max()) {
          renumber[v] = std::uint32_t(surface.vertices.size());
          surface.vertices.push_back(mesh.vertices[v]);
        }
        f[std::size_t(k)] = renumber[v];
      }
      surface.faces.push_back(f);
      const auto match = std::lower_bound(tagged.begin(), tagged.end(), std::make_pair(faces[a].sorted, std::numeric_limits<int>::min()));
      tags.push_back(match != tagged.end() && match->first == faces[a].sorted ? match->second
                                                                               : (mesh.tet_region.empty() ? 0 : mesh.tet_region[faces[a].tet]));
    }
    a = b;
  }
  std::vector<int> distinct = tags;
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  if (distinct.size() <= 1) {
    surface.region_names = {""};
    surface.face_region.assign(surface.faces.size(), 0);
  } else {
    for (int d : distinct) surface.region_names.push_back("tag " + std::to_string(d));
    for (int tag : tags) surface.face_region.push_back(int(std::lower_bound(distinct.begin(), distinct.end(), tag) - distinct.begin()));
  }
  return surface;
}

void write_tet_mesh(const TetMesh& mesh, const fs::path& path, double scale) {
  const std::string e = lower(path.extension().string());
  if (e == ".vtu") {
    detail::write_vtu_tets(mesh, path, scale);
    return;
  }
  if (!e.empty() && e != ".pts" && e != ".elem")
    throw MeshError("write_tet_mesh: '" + path.string() + "': extension '" + e + "' is not .vtu, .pts or .elem");
  const fs::path base = opencarp_base(path);
  std::ostringstream pts, elem, lon;
  pts.precision(17);
  lon.precision(17);
  pts << mesh.vertices.size() << '\n';
  for (const Vec3& v : mesh.vertices) pts << v.x() / scale << ' ' << v.y() / scale << ' ' << v.z() / scale << '\n';
  elem << mesh.tets.size() << '\n';
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& v = mesh.tets[t];
    elem << "Tt " << v[0] << ' ' << v[1] << ' ' << v[2] << ' ' << v[3] << ' '
         << (mesh.tet_region.size() == mesh.tets.size() ? mesh.tet_region[t] : 0) << '\n';
  }
  if (mesh.fibre_location == TetMesh::FibreLocation::points)
    throw MeshError("write_tet_mesh: openCARP holds fibres per element; '" + path.string() + "' would lose the point fibres");
  sph::write_file_atomically(with_extension(base, ".pts"), pts.str());
  sph::write_file_atomically(with_extension(base, ".elem"), elem.str());
  if (mesh.fibre_location == TetMesh::FibreLocation::cells) {
    lon << (mesh.sheet.empty() ? 1 : 2) << '\n';
    for (std::size_t t = 0; t < mesh.fibre.size(); ++t) {
      const Vec3& f = mesh.fibre[t];
      lon << f.x() << ' ' << f.y() << ' ' << f.z();
      if (!mesh.sheet.empty()) lon << ' ' << mesh.sheet[t].x() << ' ' << mesh.sheet[t].y() << ' ' << mesh.sheet[t].z();
      lon << '\n';
    }
    sph::write_file_atomically(with_extension(base, ".lon"), lon.str());
  }
}

// ---------------------------------------------------------------------------------------------
// Point location.

TetLocator::TetLocator(const TetMesh& mesh) : mesh_(mesh) {
  if (mesh.tets.empty()) throw MeshError("TetLocator: no tetrahedra");
  Vec3 upper = mesh.vertices[mesh.tets[0][0]];
  lower_ = upper;
  double volume = 0;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    for (auto k : mesh.tets[t]) {
      lower_ = lower_.cwiseMin(mesh.vertices[k]);
      upper = upper.cwiseMax(mesh.vertices[k]);
    }
    volume += std::abs(mesh.signed_volume6(t)) / 6;
  }
  // Cells about two mean tetrahedron sizes wide, and not more than ~4 million of them.
  const Vec3 extent = (upper - lower_).cwiseMax(1e-12);
  cell_ = std::max(2 * std::cbrt(6 * std::sqrt(2.0) * volume / double(mesh.tets.size())), std::cbrt(extent.prod() / 4e6));
  for (int d = 0; d < 3; ++d) cells_[std::size_t(d)] = std::max(1L, long(std::ceil(extent[d] / cell_)));
  bins_.resize(std::size_t(cells_[0] * cells_[1] * cells_[2]));
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    Vec3 lo = mesh.vertices[mesh.tets[t][0]], hi = lo;
    for (auto k : mesh.tets[t]) {
      lo = lo.cwiseMin(mesh.vertices[k]);
      hi = hi.cwiseMax(mesh.vertices[k]);
    }
    for (long z = cell_of(lo.z(), 2); z <= cell_of(hi.z(), 2); ++z)
      for (long y = cell_of(lo.y(), 1); y <= cell_of(hi.y(), 1); ++y)
        for (long x = cell_of(lo.x(), 0); x <= cell_of(hi.x(), 0); ++x)
          bins_[std::size_t(x + cells_[0] * (y + cells_[1] * z))].push_back(std::uint32_t(t));
  }
}

long TetLocator::cell_of(double x, int d) const {
  return std::clamp(long(std::floor((x - lower_[d]) / cell_)), 0L, cells_[std::size_t(d)] - 1);
}

TetLocator::Hit TetLocator::locate(const Vec3& p) const {
  // Barycentric coordinates; the tetrahedron whose smallest coordinate is largest holds the point
  // (smallest >= 0) or is the nearest by that measure.
  auto weights = [&](std::size_t t) {
    const auto& v = mesh_.tets[t];
    const Vec3& a = mesh_.vertices[v[0]];
    Eigen::Matrix3d m;
    m << mesh_.vertices[v[1]] - a, mesh_.vertices[v[2]] - a, mesh_.vertices[v[3]] - a;
    const Vec3 l = m.inverse() * (p - a);
    return std::array<double, 4>{1 - l.sum(), l.x(), l.y(), l.z()};
  };
  Hit best;
  double best_min = -std::numeric_limits<double>::infinity();
  const long c[3] = {cell_of(p.x(), 0), cell_of(p.y(), 1), cell_of(p.z(), 2)};
  const long max_shell = std::max({cells_[0], cells_[1], cells_[2]});
  bool found_any = false;
  for (long shell = 0; shell <= max_shell; ++shell) {
    for (long z = std::max(0L, c[2] - shell); z <= std::min(cells_[2] - 1, c[2] + shell); ++z)
      for (long y = std::max(0L, c[1] - shell); y <= std::min(cells_[1] - 1, c[1] + shell); ++y)
        for (long x = std::max(0L, c[0] - shell); x <= std::min(cells_[0] - 1, c[0] + shell); ++x) {
          if (std::max({std::abs(x - c[0]), std::abs(y - c[1]), std::abs(z - c[2])}) != shell) continue;
          for (std::uint32_t t : bins_[std::size_t(x + cells_[0] * (y + cells_[1] * z))]) {
            const auto w = weights(t);
            const double m = *std::min_element(w.begin(), w.end());
            if (m > best_min || (m == best_min && t < best.tet)) {
              best_min = m;
              best.tet = t;
              best.weights = w;
              found_any = true;
            }
          }
        }
    if (best_min >= -1e-10) break;
    // Outside the mesh: the neighbouring shell decides between nearby tetrahedra.
    if (found_any && shell >= 1) break;
  }
  best.inside = best_min >= -1e-10;
  double sum = 0;
  for (double& w : best.weights) sum += (w = std::max(w, 0.0));
  for (double& w : best.weights) w /= sum;
  return best;
}

}  // namespace geometry
