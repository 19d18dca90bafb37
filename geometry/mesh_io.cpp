// Mesh input and output: STL (ASCII and binary), OBJ and PLY read through assimp, welded by
// position; binary STL and OBJ written atomically.
//
// What assimp 5.2 does not do for us (see DESIGN.md, "Known traps"):
// - aiProcess_JoinIdenticalVertices keys on position and normal, so a closed STL comes back open:
//   we weld by exact position here instead and do not ask assimp to join anything.
// - Binary STL is recognised only when the file size is exactly 84 + 50 n. A binary file whose
//   header begins with "solid" and whose size does not match (truncated, or padded at the end) is
//   then parsed as ASCII and gives garbage or a confusing error, so the size is checked here first.
// - NaN and infinite coordinates are accepted: checked here after reading.
// - A PLY header with a malformed element or property line (a count that is not a number, a
//   misspelt keyword) can make its PLY reader loop forever; the header is checked here first.

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <vector>
#include <optional>
#include <sstream>
#include <string_view>
#include <unordered_map>

#include <Eigen/Geometry>  // cross
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "geometry/mesh.hpp"
#include "libsph/io/atomic_file.hpp"

namespace geometry {

Aabb TriangleMesh::bounding_box() const {
  if (vertices.empty()) return {};
  Aabb box{vertices.front(), vertices.front()};
  for (const Vec3& v : vertices) {
    box.lower = box.lower.cwiseMin(v);
    box.upper = box.upper.cwiseMax(v);
  }
  return box;
}

void require_well_formed(const TriangleMesh& mesh, const std::string& name) {
  const std::string prefix = name.empty() ? "mesh: " : "mesh '" + name + "': ";
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    if (!mesh.vertices[i].allFinite()) throw MeshError(prefix + "vertex " + std::to_string(i) + " is not finite");
  for (std::size_t f = 0; f < mesh.faces.size(); ++f)
    for (std::uint32_t v : mesh.faces[f])
      if (v >= mesh.vertices.size())
        throw MeshError(prefix + "face " + std::to_string(f) + " refers to vertex " + std::to_string(v) +
                        " but there are " + std::to_string(mesh.vertices.size()) + " vertices");
}

namespace {

constexpr std::size_t binary_stl_header_size = 84;  // 80-byte comment + uint32 triangle count
constexpr std::size_t binary_stl_triangle_size = 50;  // normal, 3 vertices (12 floats), uint16

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& problem) {
  throw MeshError("mesh file '" + path.string() + "': " + problem);
}

std::string lower_case_extension(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

std::vector<char> read_bytes(const std::filesystem::path& path, std::size_t count) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot be opened for reading");
  std::vector<char> bytes(count);
  in.read(bytes.data(), static_cast<std::streamsize>(count));
  bytes.resize(static_cast<std::size_t>(in.gcount()));
  return bytes;
}

// An ASCII STL begins with "solid" (after blanks) and holds no control characters other than
// blanks (bytes above 127 are allowed: UTF-8 in a solid's name). Binary STL headers often begin
// with "solid" too, but their triangle count and coordinates hold control bytes (the count of any
// file below 800 MB has a zero byte). (assimp 5.2 means to test this as well, but compares a
// signed char with 127, which never succeeds.)
bool looks_like_ascii_stl(const std::vector<char>& head) {
  auto first = std::find_if(head.begin(), head.end(), [](char c) { return !std::isspace(static_cast<unsigned char>(c)); });
  if (std::distance(first, head.end()) < 5 || std::string_view(&*first, 5) != "solid") return false;
  return std::none_of(head.begin(), head.end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return (u < 32 || u == 127) && !std::isspace(u);
  });
}

// Checks a .stl file before assimp sees it. Returns the number of bytes to hand to assimp when the
// file is a binary STL with bytes after its last triangle (assimp would not recognise it), or
// nullopt to let assimp read the file itself.
std::optional<std::size_t> check_stl_file(const std::filesystem::path& path, std::uintmax_t file_size) {
  const auto head = read_bytes(path, static_cast<std::size_t>(std::min<std::uintmax_t>(file_size, 512)));
  if (file_size >= binary_stl_header_size) {
    std::uint32_t n_triangles = 0;
    std::memcpy(&n_triangles, head.data() + 80, sizeof n_triangles);  // little endian on disk and here
    const std::uintmax_t expected = binary_stl_header_size + binary_stl_triangle_size * std::uintmax_t{n_triangles};
    if (file_size == expected) return std::nullopt;  // binary, as assimp decides too
    if (looks_like_ascii_stl(head)) return std::nullopt;
    if (file_size < expected)
      fail(path, "truncated or not a binary STL: its header announces " + std::to_string(n_triangles) +
                     " triangles (" + std::to_string(expected) + " bytes) but the file has " +
                     std::to_string(file_size) + " bytes");
    return static_cast<std::size_t>(expected);  // binary STL followed by extra bytes
  }
  if (looks_like_ascii_stl(head)) return std::nullopt;
  fail(path, "not an STL file: too short for a binary STL (" + std::to_string(file_size) +
                 " bytes, the header alone takes 84) and not ASCII STL text");
}

// assimp's made-up names for parts that have none in the file.
bool is_generated_name(const std::string& name) {
  return name.empty() || name == "defaultobject" || (name.front() == '<' && name.back() == '>');
}

// Welds corners by exact position (the float triple as read; -0 and +0 are one position).
class VertexWelder {
 public:
  explicit VertexWelder(std::vector<Vec3>& vertices) : vertices_(vertices) {}

  std::uint32_t index_of(const aiVector3D& v) {
    const Key key{v.x + ai_real(0), v.y + ai_real(0), v.z + ai_real(0)};  // + 0 maps -0 to +0
    const auto [it, inserted] = index_.try_emplace(key, static_cast<std::uint32_t>(vertices_.size()));
    if (inserted) vertices_.emplace_back(key[0], key[1], key[2]);
    return it->second;
  }

 private:
  using Key = std::array<ai_real, 3>;
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      std::size_t h = 0;
      for (ai_real c : k) {
        std::uint64_t bits = 0;
        std::memcpy(&bits, &c, sizeof c);
        h ^= std::hash<std::uint64_t>{}(bits) + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
      }
      return h;
    }
  };
  std::vector<Vec3>& vertices_;
  std::unordered_map<Key, std::uint32_t, KeyHash> index_;
};

struct SceneReader {
  const aiScene& scene;
  TriangleMesh& mesh;
  VertexWelder welder;
  std::unordered_map<std::string, int> region_of_name;
  std::size_t skipped_primitives = 0;  // points and lines

  int region(const std::string& name) {
    const auto [it, inserted] = region_of_name.try_emplace(name, static_cast<int>(mesh.region_names.size()));
    if (inserted) mesh.region_names.push_back(name);
    return it->second;
  }

  // Each aiMesh is a part of the file (OBJ group or object, ASCII STL solid): one region, named by
  // the mesh, else by the node holding it. Parts with the same name share a region.
  void add_node(const aiNode& node, const aiMatrix4x4& parent_transform) {
    const aiMatrix4x4 transform = parent_transform * node.mTransformation;
    for (unsigned k = 0; k < node.mNumMeshes; ++k) {
      const aiMesh& part = *scene.mMeshes[node.mMeshes[k]];
      std::string name = part.mName.C_Str();
      if (is_generated_name(name)) name = node.mName.C_Str();
      if (is_generated_name(name)) name.clear();
      add_part(part, name, transform);
    }
    for (unsigned c = 0; c < node.mNumChildren; ++c) add_node(*node.mChildren[c], transform);
  }

  void add_part(const aiMesh& part, const std::string& name, const aiMatrix4x4& transform) {
    const bool moved = !transform.IsIdentity();
    int region_index = -1;  // made on the first triangle, so that no region is empty
    for (unsigned f = 0; f < part.mNumFaces; ++f) {
      const aiFace& face = part.mFaces[f];
      if (face.mNumIndices < 3) {  // points and lines
        ++skipped_primitives;
        continue;
      }
      std::vector<std::uint32_t> polygon(face.mNumIndices);
      for (unsigned c = 0; c < face.mNumIndices; ++c) {
        if (face.mIndices[c] >= part.mNumVertices)
          throw MeshError("face " + std::to_string(f) + " refers to vertex " + std::to_string(face.mIndices[c]) + " of " +
                          std::to_string(part.mNumVertices));
        const aiVector3D& v = part.mVertices[face.mIndices[c]];
        polygon[c] = welder.index_of(moved ? transform * v : v);
      }
      if (region_index < 0) region_index = region(name);
      // A polygon as a fan of triangles from its first corner (exact for the convex quads and
      // polygons of mesh files).
      for (std::size_t c = 1; c + 1 < polygon.size(); ++c) {
        mesh.faces.push_back({polygon[0], polygon[c], polygon[c + 1]});
        mesh.face_region.push_back(region_index);
      }
    }
  }
};

// The PLY header (Bourke's format description): "ply", "format ascii|binary_little_endian|
// binary_big_endian 1.0", then "element NAME COUNT", "property TYPE NAME", "property list TYPE
// TYPE NAME", "comment ...", "obj_info ..." lines up to "end_header". Anything else is refused.
void check_ply_header(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  auto words_of = [](const std::string& l) {
    std::vector<std::string> words;
    std::istringstream s(l);
    for (std::string w; s >> w;) words.push_back(w);
    return words;
  };
  static const std::array<std::string, 16> types{"char", "uchar", "short", "ushort", "int", "uint", "float", "double",
                                                 "int8", "uint8", "int16", "uint16", "int32", "uint32", "float32", "float64"};
  auto is_type = [&](const std::string& t) { return std::find(types.begin(), types.end(), t) != types.end(); };
  long number = 0;
  bool elements = false;
  while (std::getline(in, line) && number < 10000) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto w = words_of(line);
    auto bad = [&](const std::string& what) {
      fail(path, "not a valid PLY header: line " + std::to_string(number) + " ('" + line.substr(0, 60) + "') " + what);
    };
    if (number == 1) {
      if (w.size() != 1 || w[0] != "ply") bad("should be 'ply'");
      continue;
    }
    if (number == 2) {
      if (w.size() != 3 || w[0] != "format" || (w[1] != "ascii" && w[1] != "binary_little_endian" && w[1] != "binary_big_endian"))
        bad("should be 'format ascii|binary_little_endian|binary_big_endian 1.0'");
      continue;
    }
    if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "end_header") {
      if (w.size() != 1) bad("should be 'end_header'");
      if (!elements) bad("ends a header without elements");
      return;
    }
    if (w[0] == "element") {
      if (w.size() != 3 || w[2].find_first_not_of("0123456789") != std::string::npos || w[2].size() > 12)
        bad("should be 'element NAME COUNT'");
      elements = true;
    } else if (w[0] == "property") {
      const bool scalar = w.size() == 3 && is_type(w[1]);
      const bool list = w.size() == 5 && w[1] == "list" && is_type(w[2]) && is_type(w[3]);
      if (!scalar && !list) bad("should be 'property TYPE NAME' or 'property list TYPE TYPE NAME'");
      if (!elements) bad("is a property before any element");
    } else {
      bad("is not a PLY header line");
    }
  }
  fail(path, "not a valid PLY file: no 'end_header' line");
}

}  // namespace

TriangleMesh read_mesh(const std::filesystem::path& path, double scale) {
  if (!(std::isfinite(scale) && scale > 0))
    fail(path, "scale " + std::to_string(scale) + " must be positive and finite");
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) fail(path, "file not found");
  if (!std::filesystem::is_regular_file(status)) fail(path, "not a regular file");
  const std::uintmax_t file_size = std::filesystem::file_size(path, error);
  if (error) fail(path, "cannot read its size: " + error.message());
  if (file_size == 0) fail(path, "empty file");

  std::optional<std::size_t> binary_stl_bytes;
  if (lower_case_extension(path) == ".stl") binary_stl_bytes = check_stl_file(path, file_size);
  if (lower_case_extension(path) == ".ply") check_ply_header(path);

  // No aiProcess_JoinIdenticalVertices (we weld), nothing that merges, sorts or drops faces.
  // Polygons are split into triangles below: assimp's aiProcess_Triangulate aborts the process (an
  // assertion in the Debian build) on some malformed PLY faces.
  constexpr unsigned flags = aiProcess_ValidateDataStructure;
  Assimp::Importer importer;
  const aiScene* scene = nullptr;
  if (binary_stl_bytes) {
    const auto bytes = read_bytes(path, *binary_stl_bytes);
    scene = importer.ReadFileFromMemory(bytes.data(), bytes.size(), flags, "stl");
  } else {
    scene = importer.ReadFile(path.string(), flags);
  }
  if (scene == nullptr) {
    const std::string reason = importer.GetErrorString();
    if (reason.find("mNumMeshes is 0") != std::string::npos) fail(path, "contains no faces (is it a mesh file?)");
    fail(path, "not a readable mesh (assimp: " + reason + ")");
  }
  if (scene->mRootNode == nullptr) fail(path, "contains no faces (is it a mesh file?)");

  TriangleMesh mesh;
  SceneReader reader{*scene, mesh, VertexWelder(mesh.vertices), {}, 0};
  try {
    reader.add_node(*scene->mRootNode, aiMatrix4x4());
  } catch (const MeshError& bad_face) {
    fail(path, bad_face.what());
  }
  if (mesh.faces.empty())
    fail(path, "contains no triangles" +
                   (reader.skipped_primitives > 0
                        ? " (only " + std::to_string(reader.skipped_primitives) + " points or lines)"
                        : std::string()));

  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    Vec3& v = mesh.vertices[i];
    if (!v.allFinite()) {
      std::ostringstream text;
      text << "vertex " << i << " has a non-finite coordinate (" << v.x() << ", " << v.y() << ", " << v.z() << ")";
      fail(path, text.str());
    }
    v *= scale;
    if (!v.allFinite()) fail(path, "vertex " + std::to_string(i) + " overflows when scaled by " + std::to_string(scale));
  }
  return mesh;
}

TriangleMesh extract_region(const TriangleMesh& mesh, int region) {
  if (region < 0 || static_cast<std::size_t>(region) >= mesh.region_names.size())
    throw std::out_of_range("extract_region: region " + std::to_string(region) + " does not exist (the mesh has " +
                            std::to_string(mesh.region_names.size()) + ")");
  TriangleMesh part;
  part.region_names = {mesh.region_names[static_cast<std::size_t>(region)]};
  constexpr auto unused = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> new_index(mesh.vertices.size(), unused);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    if (mesh.face_region[f] != region) continue;
    std::array<std::uint32_t, 3> corners{};
    for (int c = 0; c < 3; ++c) {
      std::uint32_t& index = new_index[mesh.faces[f][c]];
      if (index == unused) {
        index = static_cast<std::uint32_t>(part.vertices.size());
        part.vertices.push_back(mesh.vertices[mesh.faces[f][c]]);
      }
      corners[c] = index;
    }
    part.faces.push_back(corners);
    part.face_region.push_back(0);
  }
  return part;
}

namespace {

template <class T>
void append_binary(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));  // little endian on every platform we build for
  out.append(bytes, sizeof(T));
}

std::string binary_stl(const TriangleMesh& mesh) {
  static_assert(std::endian::native == std::endian::little, "binary STL is little endian");
  std::string out;
  out.reserve(binary_stl_header_size + binary_stl_triangle_size * mesh.faces.size());
  // The header must not begin with "solid", or readers take the file for ASCII.
  std::string header = "binary STL written by cardiosph";
  header.resize(80, ' ');
  out += header;
  append_binary(out, static_cast<std::uint32_t>(mesh.faces.size()));
  for (const auto& face : mesh.faces) {
    const Vec3& a = mesh.vertices[face[0]];
    const Vec3& b = mesh.vertices[face[1]];
    const Vec3& c = mesh.vertices[face[2]];
    const Vec3 normal = (b - a).cross(c - a).normalized();
    for (const Vec3* v : {&normal, &a, &b, &c})
      for (int d = 0; d < 3; ++d) append_binary(out, static_cast<float>((*v)[d]));
    append_binary(out, std::uint16_t{0});
  }
  return out;
}

std::string obj_group_name(const std::string& region) {
  std::string name = region;
  std::replace_if(name.begin(), name.end(), [](unsigned char c) { return std::isspace(c) != 0; }, '_');
  return name;
}

// One group per region ("g name"), faces of unnamed regions before any group line.
std::string obj(const TriangleMesh& mesh) {
  std::ostringstream out;
  out.precision(17);
  out << "# written by cardiosph: " << mesh.vertices.size() << " vertices, " << mesh.faces.size() << " faces\n";
  for (const Vec3& v : mesh.vertices) out << "v " << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
  std::vector<int> regions(mesh.region_names.size());
  for (std::size_t r = 0; r < regions.size(); ++r) regions[r] = static_cast<int>(r);
  std::stable_partition(regions.begin(), regions.end(), [&](int r) { return mesh.region_names[r].empty(); });
  for (int r : regions) {
    if (!mesh.region_names[r].empty()) out << "g " << obj_group_name(mesh.region_names[r]) << '\n';
    for (std::size_t f = 0; f < mesh.faces.size(); ++f)
      if (mesh.face_region[f] == r)
        out << "f " << mesh.faces[f][0] + 1 << ' ' << mesh.faces[f][1] + 1 << ' ' << mesh.faces[f][2] + 1 << '\n';
  }
  return out.str();
}

}  // namespace

void write_mesh(const TriangleMesh& mesh, const std::filesystem::path& path) {
  const std::string extension = lower_case_extension(path);
  if (extension == ".stl") {
    sph::write_file_atomically(path, binary_stl(mesh));
  } else if (extension == ".obj") {
    if (mesh.face_region.empty()) {  // a mesh built without regions: one unnamed group
      TriangleMesh unnamed = mesh;
      unnamed.face_region.assign(mesh.faces.size(), 0);
      unnamed.region_names = {""};
      sph::write_file_atomically(path, obj(unnamed));
      return;
    }
    const bool regions_valid =
        mesh.face_region.size() == mesh.faces.size() &&
        std::all_of(mesh.face_region.begin(), mesh.face_region.end(),
                    [&](int r) { return r >= 0 && static_cast<std::size_t>(r) < mesh.region_names.size(); });
    if (!regions_valid)
      throw std::invalid_argument("write_mesh: face_region must give each of the " + std::to_string(mesh.faces.size()) +
                                  " faces a region below " + std::to_string(mesh.region_names.size()));
    sph::write_file_atomically(path, obj(mesh));
  } else if (extension == ".off") {
    std::ostringstream off;
    off.precision(17);
    off << "OFF\n" << mesh.vertices.size() << ' ' << mesh.faces.size() << " 0\n";
    for (const Vec3& v : mesh.vertices) off << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
    for (const auto& f : mesh.faces) off << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
    sph::write_file_atomically(path, off.str());
  } else {
    throw MeshError("write_mesh: cannot write '" + path.string() + "': extension '" + extension +
                    "' is not .stl, .obj or .off");
  }
}

}  // namespace geometry
