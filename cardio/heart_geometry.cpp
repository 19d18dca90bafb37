#include "cardio/heart_geometry.hpp"

#include <Eigen/Geometry>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <sstream>

#include <nlohmann/json.hpp>

#include "libsph/core/communicator.hpp"
#include "libsph/core/types.hpp"
#include "libsph/io/atomic_file.hpp"

namespace cardio {
namespace {

namespace fs = std::filesystem;
using geometry::Vec3;
using Clock = std::chrono::steady_clock;

// Version of the stage: bump when the generation, labels or fibres change, so old caches are not reused.
constexpr const char* stage_version = "heart-geometry-4";
constexpr char magic[8] = {'C', 'S', 'P', 'H', 'G', 'E', 'O', '1'};

std::string read_bytes(const fs::path& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(what + " '" + path.string() + "': cannot be opened");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// FNV-1a, 64 bits.
struct Hash {
  std::uint64_t value = 1469598103934665603ULL;
  void add(std::string_view bytes) {
    for (unsigned char c : bytes) {
      value ^= c;
      value *= 1099511628211ULL;
    }
    // Separate consecutive inputs.
    value ^= bytes.size();
    value *= 1099511628211ULL;
  }
  std::string hex() const {
    std::ostringstream s;
    s << std::hex << std::setw(16) << std::setfill('0') << value;
    return s.str();
  }
};

nlohmann::json settings_json(const HeartGeometrySettings& s) {
  auto vec = [](const Vec3& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); };
  return {{"version", stage_version},
          {"scale", s.scale},
          {"surface_tags", s.surface_tags},
          {"repair", s.repair},
          {"spacing", s.spacing},
          {"relaxation_steps", s.relaxation_steps},
          {"surfaces", {s.epi_surface.empty(), s.lv_surface.empty(), s.rv_surface.empty(), s.base_surface.empty()}},
          {"fibres", s.fibres},
          {"alpha", {s.ldrb.alpha_endo_deg, s.ldrb.alpha_epi_deg}},
          {"beta", {s.ldrb.beta_endo_deg, s.ldrb.beta_epi_deg}},
          {"ldrb", {s.ldrb.smoothing_ratio, s.ldrb.kernel, s.ldrb.tolerance}},
          {"uniform", {vec(s.uniform_fibre), vec(s.uniform_sheet)}},
          {"real_bytes", sizeof(sph::Real)}};
}

template <class T>
void put(std::string& out, const std::vector<T>& v) {
  const std::uint64_t n = v.size();
  out.append(reinterpret_cast<const char*>(&n), sizeof n);
  out.append(reinterpret_cast<const char*>(v.data()), n * sizeof(T));
}
template <class T>
void take(std::istream& in, std::vector<T>& v) {
  std::uint64_t n = 0;
  in.read(reinterpret_cast<char*>(&n), sizeof n);
  if (!in || n > (1ULL << 34)) throw std::runtime_error("corrupt cache");
  v.resize(n);
  in.read(reinterpret_cast<char*>(v.data()), std::streamsize(n * sizeof(T)));
  if (!in) throw std::runtime_error("truncated cache");
}

nlohmann::json statistics_json(const HeartGeometry& g) {
  const auto& b = g.body;
  const auto& c = g.mesh_check;
  return {{"shape_volume", b.shape_volume},
          {"volume_relative_error", b.volume_relative_error},
          {"density_spread", b.density_spread},
          {"volume_ratio", {b.volume_min_ratio, b.volume_max_ratio}},
          {"residual", {b.residual_initial, b.residual_final}},
          {"spacing_ratio", {b.spacing_min_ratio, b.spacing_mean_ratio, b.spacing_max_ratio, b.spacing_spread}},
          {"relaxation_steps", b.relaxation_steps_done},
          {"neighbour_builds", b.neighbour_builds},
          {"neighbourhoods", {b.neighbours_median, b.neighbours_min, b.conditioning_min}},
          {"seconds", {b.level_set_seconds, b.lattice_seconds, b.relaxation_seconds, b.volume_seconds}},
          {"mesh", {c.vertices, c.faces, c.components, c.volume}},
          {"label_method", g.label_method},
          {"fibre_method", g.fibre_method},
          {"tets", g.tets},
          {"fibre_particles_outside", g.fibre_particles_outside},
          {"base_normal", {g.base_normal.x(), g.base_normal.y(), g.base_normal.z()}},
          {"fibre_solver", {g.fibres.solver_iterations, g.fibres.solver_seconds, g.fibres.total_seconds, g.fibres.matrix_nonzeros}}};
}

void store(const HeartGeometry& g, const nlohmann::json& settings, const fs::path& file) {
  if (!sph::Communicator::world().is_root()) return;  // under mpirun every rank built the same; one writes it
  std::string out(magic, sizeof magic);
  const std::string header = nlohmann::json{{"settings", settings}, {"statistics", statistics_json(g)}}.dump();
  put(out, std::vector<char>(header.begin(), header.end()));
  put(out, g.body.positions);
  put(out, g.body.volumes);
  put(out, g.body.depth);
  put(out, g.body.normals);
  put(out, g.body.surface);
  put(out, g.labels);
  put(out, g.fibres.fibre);
  put(out, g.fibres.sheet);
  put(out, g.fibres.transmural);
  put(out, g.fibres.apicobasal);
  put(out, g.fibres.lv);
  put(out, g.fibres.rv);
  fs::create_directories(file.parent_path());
  sph::write_file_atomically(file, out);
}

// The cached result, or false when there is none or it does not match (then it is regenerated).
bool load(const fs::path& file, const nlohmann::json& settings, HeartGeometry& g) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return false;
  try {
    char m[sizeof magic];
    in.read(m, sizeof m);
    if (!in || std::memcmp(m, magic, sizeof magic) != 0) return false;
    std::vector<char> header;
    take(in, header);
    const auto j = nlohmann::json::parse(std::string(header.begin(), header.end()));
    if (j.at("settings") != settings) return false;
    take(in, g.body.positions);
    take(in, g.body.volumes);
    take(in, g.body.depth);
    take(in, g.body.normals);
    take(in, g.body.surface);
    take(in, g.labels);
    take(in, g.fibres.fibre);
    take(in, g.fibres.sheet);
    take(in, g.fibres.transmural);
    take(in, g.fibres.apicobasal);
    take(in, g.fibres.lv);
    take(in, g.fibres.rv);
    const auto& s = j.at("statistics");
    auto& b = g.body;
    b.shape_volume = s.at("shape_volume");
    b.volume_relative_error = s.at("volume_relative_error");
    b.density_spread = s.at("density_spread");
    b.volume_min_ratio = s.at("volume_ratio")[0];
    b.volume_max_ratio = s.at("volume_ratio")[1];
    b.residual_initial = s.at("residual")[0];
    b.residual_final = s.at("residual")[1];
    b.spacing_min_ratio = s.at("spacing_ratio")[0];
    b.spacing_mean_ratio = s.at("spacing_ratio")[1];
    b.spacing_max_ratio = s.at("spacing_ratio")[2];
    b.spacing_spread = s.at("spacing_ratio")[3];
    b.relaxation_steps_done = s.at("relaxation_steps");
    b.neighbour_builds = s.at("neighbour_builds");
    b.neighbours_median = s.at("neighbourhoods")[0];
    b.neighbours_min = s.at("neighbourhoods")[1];
    b.conditioning_min = s.at("neighbourhoods")[2];
    b.level_set_seconds = s.at("seconds")[0];
    b.lattice_seconds = s.at("seconds")[1];
    b.relaxation_seconds = s.at("seconds")[2];
    b.volume_seconds = s.at("seconds")[3];
    auto& c = g.mesh_check;
    c.vertices = s.at("mesh")[0];
    c.faces = s.at("mesh")[1];
    c.components = s.at("mesh")[2];
    c.volume = s.at("mesh")[3];
    g.label_method = s.at("label_method");
    g.fibre_method = s.at("fibre_method");
    g.tets = s.at("tets");
    g.fibre_particles_outside = s.at("fibre_particles_outside");
    g.base_normal = Vec3(s.at("base_normal")[0], s.at("base_normal")[1], s.at("base_normal")[2]);
    g.fibres.solver_iterations = s.at("fibre_solver")[0];
    g.fibres.solver_seconds = s.at("fibre_solver")[1];
    g.fibres.total_seconds = s.at("fibre_solver")[2];
    g.fibres.matrix_nonzeros = s.at("fibre_solver")[3];
    const std::size_t n = b.positions.size();
    if (b.volumes.size() != n || g.labels.size() != n || b.surface.size() != n) return false;
  } catch (const std::exception&) {
    return false;
  }
  g.from_cache = true;
  return true;
}

// "epi=1,lv_endo=2": tag -> surface name.
std::vector<std::pair<int, std::string>> parse_surface_tags(const std::string& text) {
  std::vector<std::pair<int, std::string>> tags;
  std::istringstream items(text);
  for (std::string item; std::getline(items, item, ',');) {
    item.erase(std::remove_if(item.begin(), item.end(), [](unsigned char c) { return std::isspace(c); }), item.end());
    if (item.empty()) continue;
    const auto eq = item.find('=');
    std::size_t used = 0;
    int tag = 0;
    try {
      if (eq != std::string::npos) tag = std::stoi(item.substr(eq + 1), &used);
    } catch (const std::exception&) {
      used = 0;
    }
    const std::string name = item.substr(0, eq);
    if (eq == std::string::npos || used == 0 || used != item.size() - eq - 1)
      throw std::invalid_argument("surface_tags '" + text + "': '" + item + "' is not name=tag (e.g. epi=1,lv_endo=2)");
    if (label_of_surface_name(name) == label_none)
      throw std::invalid_argument("surface_tags '" + text + "': '" + name + "' is not a surface (epi, lv_endo, rv_endo, base)");
    tags.emplace_back(tag, name);
  }
  return tags;
}

}  // namespace

geometry::TriangleMesh read_heart_surface(const HeartGeometrySettings& settings, geometry::TetMesh* tets) {
  if (!geometry::is_tet_mesh_file(settings.mesh)) {
    if (!settings.surface_tags.empty())
      throw std::invalid_argument("surface_tags is for tetrahedral meshes; '" + settings.mesh.string() +
                                  "' is a surface mesh (its named parts label it)");
    geometry::TriangleMesh mesh = geometry::read_mesh(settings.mesh, settings.scale);
    return settings.repair ? geometry::repair_mesh(mesh) : mesh;
  }
  const auto tags = parse_surface_tags(settings.surface_tags);
  geometry::TetMesh volume = geometry::read_tet_mesh(settings.mesh, settings.scale);
  geometry::check_tet_mesh(volume, settings.mesh.string());
  geometry::TriangleMesh surface = geometry::boundary_surface(volume);
  for (auto& name : surface.region_names)
    for (const auto& [tag, label] : tags)
      if (name == "tag " + std::to_string(tag)) name = label;
  if (!tags.empty() && surface.region_names.size() == 1 && surface.region_names[0].empty())
    throw std::invalid_argument("surface_tags: the boundary of '" + settings.mesh.string() + "' has a single tag");
  if (tets) *tets = std::move(volume);
  return surface;
}

namespace {

geometry::TriangleMesh read_checked(const HeartGeometrySettings& settings, geometry::MeshCheckReport* report,
                                    geometry::TetMesh* tets) {
  const geometry::TriangleMesh mesh = read_heart_surface(settings, tets);
  const auto check = geometry::require_valid_mesh(mesh, settings.mesh.string());
  if (report) *report = check;
  return mesh;
}

}  // namespace

fs::path default_cache_folder() {
  if (const char* c = std::getenv("CARDIOSPH_CACHE"); c && *c) return c;
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return fs::path(x) / "cardiosph";
  if (const char* h = std::getenv("HOME"); h && *h) return fs::path(h) / ".cache" / "cardiosph";
  return fs::temp_directory_path() / "cardiosph-cache";
}

HeartGeometry prepare_heart_geometry(const HeartGeometrySettings& settings, const fs::path& cache_folder,
                                     const std::function<void(const std::string&)>& log) {
  const auto start = Clock::now();
  auto say = [&](const std::string& line) {
    if (log) log(line);
  };
  if (!(settings.scale > 0)) throw std::invalid_argument("mesh scale must be positive");
  if (settings.fibres != "auto" && settings.fibres != "ldrb" && settings.fibres != "mesh" && settings.fibres != "uniform" &&
      settings.fibres != "file" && settings.fibres != "none")
    throw std::invalid_argument("fibres '" + settings.fibres + "': expected auto, ldrb, mesh, uniform, file or none");
  if (settings.fibres == "file" && settings.fibre_file.empty())
    throw std::invalid_argument("fibres = file needs a fibre file");

  // Hash every input.
  const auto settings_text = settings_json(settings);
  Hash hash;
  hash.add(settings_text.dump());
  if (const auto files = geometry::tet_mesh_files(settings.mesh); !files.empty())
    for (const auto& file : files) hash.add(read_bytes(file, "mesh"));
  else
    hash.add(read_bytes(settings.mesh, "mesh"));
  for (const auto* p : {&settings.epi_surface, &settings.lv_surface, &settings.rv_surface, &settings.base_surface})
    if (!p->empty()) hash.add(read_bytes(*p, "surface mesh"));
  if (settings.fibres == "file") hash.add(read_bytes(settings.fibre_file, "fibre file"));
  HeartGeometry g;
  g.hash = hash.hex();
  const fs::path cache_file = cache_folder.empty() ? fs::path() : cache_folder / (g.hash + ".geometry");
  if (!cache_file.empty() && load(cache_file, settings_text, g)) {
    g.hash = hash.hex();
    g.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    say("geometry: " + std::to_string(g.body.size()) + " particles from the cache " + cache_file.string());
    return g;
  }

  // Mesh.
  say("geometry: reading and checking " + settings.mesh.string());
  geometry::TetMesh tets;
  const auto mesh = read_checked(settings, &g.mesh_check, &tets);
  g.tets = tets.n_tets();
  if (g.tets) say("geometry: " + std::to_string(g.tets) + " tetrahedra, boundary of " + std::to_string(mesh.n_faces()) + " faces");
  const bool mesh_fibres = tets.fibre_location != geometry::TetMesh::FibreLocation::none;
  std::string fibres = settings.fibres;
  if (fibres == "auto") fibres = mesh_fibres ? "mesh" : "ldrb";
  if (fibres == "mesh" && !mesh_fibres)
    throw std::invalid_argument("fibres = mesh but '" + settings.mesh.string() + "' has no fibre array" +
                                (g.tets ? "" : " (it is a surface mesh)"));
  const geometry::MeshShape shape(mesh, true, settings.mesh.filename().string());

  // Particles.
  geometry::ParticleGenerationSettings generation;
  generation.spacing = settings.spacing;
  generation.relaxation_steps = settings.relaxation_steps;
  long last_reported = 0;
  generation.on_step = [&](long step, double residual) {
    if (step - last_reported >= 25) {
      last_reported = step;
      say("geometry: relaxation step " + std::to_string(step) + ", rms residual " + std::to_string(residual));
    }
  };
  say("geometry: particles at dp = " + std::to_string(settings.spacing));
  g.body = geometry::generate_particles(shape, generation);
  say("geometry: " + std::to_string(g.body.size()) + " particles, volume error " +
      std::to_string(g.body.volume_relative_error));
  // The mechanics must not start from a degenerate neighbourhood: stop, naming the place.
  geometry::require_no_thin_features(g.body, settings.spacing, "mesh '" + settings.mesh.string() + "'");

  // Labels.
  const bool separate = !settings.epi_surface.empty() || !settings.lv_surface.empty() || !settings.rv_surface.empty();
  if (separate) {
    if (settings.epi_surface.empty() || settings.lv_surface.empty())
      throw std::invalid_argument("separate surfaces need at least the epicardium and the LV endocardium");
    std::vector<std::unique_ptr<geometry::MeshShape>> meshes;
    std::vector<LabelledSurface> surfaces;
    auto add = [&](const fs::path& p, SurfaceLabel label) {
      if (p.empty()) return;
      meshes.push_back(std::make_unique<geometry::MeshShape>(geometry::read_mesh(p, settings.scale), false, p.filename().string()));
      surfaces.push_back({label, meshes.back().get()});
    };
    add(settings.epi_surface, label_epi);
    add(settings.lv_surface, label_lv_endo);
    add(settings.rv_surface, label_rv_endo);
    FaceLabels rule;
    if (settings.base_surface.empty()) {
      rule = face_labels_by_rule(mesh);
      if (!rule.has_base) throw std::invalid_argument("no base surface given and no flat base found in the mesh");
      // The base faces of the closed mesh serve as the base surface.
      geometry::TriangleMesh base;
      base.region_names = {"base"};
      for (std::size_t f = 0; f < mesh.n_faces(); ++f) {
        if (rule.face[f] != label_base) continue;
        const auto offset = std::uint32_t(base.vertices.size());
        for (int k = 0; k < 3; ++k) base.vertices.push_back(mesh.vertices[mesh.faces[f][k]]);
        base.faces.push_back({offset, offset + 1, offset + 2});
        base.face_region.push_back(0);
      }
      meshes.push_back(std::make_unique<geometry::MeshShape>(std::move(base), false, "base"));
      surfaces.push_back({label_base, meshes.back().get()});
      g.base_normal = rule.base_normal;
    } else {
      add(settings.base_surface, label_base);
      Vec3 normal = Vec3::Zero();
      for (std::size_t f = 0; f < meshes.back()->mesh().n_faces(); ++f) {
        const auto& m = meshes.back()->mesh();
        const auto& t = m.faces[f];
        normal += (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]);
      }
      // Orient it away from the body: the base lies at the body's extreme along its normal.
      if (normal.norm() == 0) throw std::invalid_argument("base surface '" + settings.base_surface.string() + "' has no area");
      normal.normalize();
      const Vec3 centre = mesh.bounding_box().lower + 0.5 * mesh.bounding_box().extent();
      if ((meshes.back()->mesh().vertices[0] - centre).dot(normal) < 0) normal = -normal;
      g.base_normal = normal;
    }
    g.labels = label_particles_by_surfaces(g.body.positions, g.body.surface, surfaces);
    g.label_method = "surfaces";
  } else {
    try {
      const FaceLabels faces = label_faces(mesh);
      g.labels = label_particles(g.body.positions, g.body.surface, shape, faces);
      g.label_method = faces.method;
      g.base_normal = faces.base_normal;
    } catch (const geometry::MeshError& error) {
      // Only the rule-based fibres need the labels; other geometries (a slab, a cube) go without.
      // Tags named by the user must label the surface.
      if (fibres == "ldrb" || !settings.surface_tags.empty()) throw;
      g.labels.assign(g.body.size(), label_none);
      g.label_method = std::string("none (") + error.what() + ")";
      say("geometry: no surface labels: " + std::string(error.what()));
    }
  }
  say("geometry: surface labels by " + g.label_method);

  // Fibres.
  const std::size_t n = g.body.size();
  if (fibres == "ldrb") {
    say("geometry: LDRB fibres (4 Laplace solves)");
    g.fibres = ldrb_fibres(g.body.positions, g.body.volumes, g.labels, g.base_normal, settings.spacing, settings.ldrb);
  } else if (fibres == "mesh") {
    const bool on_points = tets.fibre_location == geometry::TetMesh::FibreLocation::points;
    say(std::string("geometry: fibres interpolated from the mesh's ") + (on_points ? "points" : "elements"));
    FibreField from_mesh = fibres_from_tet_mesh(g.body.positions, tets, &g.fibre_particles_outside);
    // The LDRB coordinates (transmural, apico-basal) serve the cell variants and the early
    // activation sites, and give the sheet when the mesh has none; they need the surface labels.
    try {
      g.fibres = ldrb_fibres(g.body.positions, g.body.volumes, g.labels, g.base_normal, settings.spacing, settings.ldrb);
    } catch (const std::invalid_argument& error) {
      say(std::string("geometry: no LDRB coordinates: ") + error.what());
      g.fibres = FibreField{};
    }
    if (from_mesh.sheet.empty()) {
      from_mesh.sheet.resize(n);
      for (std::size_t i = 0; i < n; ++i) {
        const Vec3& f = from_mesh.fibre[i];
        Vec3 s = g.fibres.sheet.empty() ? Vec3::Zero() : Vec3(g.fibres.sheet[i] - g.fibres.sheet[i].dot(f) * f);
        if (s.norm() < 1e-9) s = f.unitOrthogonal();
        from_mesh.sheet[i] = s.normalized();
      }
    }
    g.fibres.fibre = std::move(from_mesh.fibre);
    g.fibres.sheet = std::move(from_mesh.sheet);
  } else if (fibres == "uniform") {
    g.fibres = uniform_fibres(n, settings.uniform_fibre, settings.uniform_sheet);
  } else if (fibres == "file") {
    g.fibres = fibres_from_file(g.body.positions, settings.fibre_file);
  }
  g.fibre_method = fibres == "mesh" ? (tets.fibre_location == geometry::TetMesh::FibreLocation::points ? "mesh (points)" : "mesh (cells)")
                                    : fibres;
  if (!cache_file.empty()) store(g, settings_text, cache_file);
  g.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return g;
}

}  // namespace cardio
