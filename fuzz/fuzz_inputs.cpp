#include "fuzz/fuzz_inputs.hpp"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string_view>

#include "geometry/mesh.hpp"
#include "geometry/tet_mesh.hpp"
#include "libsph/core/particles.hpp"
#include "libsph/core/time_stepper.hpp"
#include "libsph/io/checkpoint.hpp"
#include "libsph/io/parameters.hpp"

namespace cardiosph::fuzz {
namespace {

namespace fs = std::filesystem;

std::string_view text_of(Bytes data) { return {reinterpret_cast<const char*>(data.data()), data.size()}; }

// A folder of this process for the files the readers take (on tmpfs where there is one).
const fs::path& scratch() {
  static const fs::path folder = [] {
    const fs::path base = fs::exists("/dev/shm") ? fs::path("/dev/shm") : fs::temp_directory_path();
    fs::path f = base / ("cardiosph_fuzz_" + std::to_string(::getpid()));
    fs::create_directories(f);
    return f;
  }();
  return folder;
}

fs::path write(const std::string& name, std::string_view content) {
  const fs::path path = scratch() / name;
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(content.data(), std::streamsize(content.size()));
  return path;
}

// Parameters of every kind a scene declares.
struct Fixture {
  enum class Mode { slow, fast };
  double spacing = 1, ratio = 0.5, free = 0;
  long steps = 10;
  int count = 3;
  bool flag = false;
  std::string choice = "a", text;
  Mode mode = Mode::slow;
  Eigen::Vector3d direction{1, 0, 0};
  fs::path file;
  sph::Parameters parameters;
  Fixture() {
    parameters.add("dp", spacing, "mm", "spacing", sph::Range::positive());
    parameters.add("ratio", ratio, "1", "ratio", sph::Range::closed(0, 1));
    parameters.add("free", free, "1", "any", sph::Range::any());
    parameters.add("steps", steps, "1", "steps", sph::Range::non_negative());
    parameters.add("count", count, "1", "count", sph::Range::closed(1, 100));
    parameters.add("flag", flag, "flag");
    parameters.add_choice("choice", choice, {"a", "b", "c"}, "choice");
    parameters.add_text("text", text, "text");
    parameters.add_enum("mode", mode, {{"slow", Mode::slow}, {"fast", Mode::fast}}, "mode");
    parameters.add_vector("direction", direction, "1", "direction", false);
    parameters.add_path("file", file, "file");
  }
};

}  // namespace

void surface_mesh(Bytes data) {
  if (data.empty()) return;
  static const char* extensions[] = {".stl", ".obj", ".ply"};
  const fs::path path = write(std::string("surface") + extensions[data[0] % 3], text_of(data.subspan(1)));
  try {
    const auto mesh = geometry::read_mesh(path);
    geometry::check_mesh(mesh);
  } catch (const geometry::MeshError&) {
  }
}

void tet_mesh(Bytes data) {
  if (data.empty()) return;
  const std::string_view rest = text_of(data.subspan(1));
  fs::path path;
  std::string_view vertex_list;
  if (data[0] % 2 == 0) {
    path = write("tets.vtu", rest);
  } else {
    std::string_view parts[4];
    std::size_t start = 0, k = 0;
    for (; k < 3; ++k) {
      const auto end = rest.find("\n%%\n", start);
      if (end == std::string_view::npos) break;
      parts[k] = rest.substr(start, end - start);
      start = end + 4;
    }
    parts[k] = rest.substr(std::min(start, rest.size()));
    fs::remove(scratch() / "tets.lon");
    path = write("tets.pts", parts[0]);
    write("tets.elem", parts[1]);
    if (!parts[2].empty()) write("tets.lon", parts[2]);
    vertex_list = parts[3];
  }
  try {
    auto mesh = geometry::read_tet_mesh(path);
    geometry::check_tet_mesh(mesh, "fuzz");
    geometry::boundary_surface(mesh);
    if (!vertex_list.empty()) geometry::read_vertex_list(write("nodes.vtx", vertex_list), mesh.vertices.size());
  } catch (const geometry::MeshError&) {
  }
}

void config(Bytes data) {
  if (data.empty()) return;
  Fixture f;
  try {
    f.parameters.load_text(std::string(text_of(data.subspan(1))), data[0] % 2 ? "json" : "toml", "fuzz");
    f.parameters.check();
  } catch (const sph::ParameterError&) {
  }
}

void assignments(Bytes data) {
  Fixture f;
  const std::string_view text = text_of(data);
  std::size_t start = 0;
  while (start <= text.size()) {
    const auto end = std::min(text.find('\n', start), text.size());
    try {
      f.parameters.set_assignment(std::string(text.substr(start, end - start)), "--set");
    } catch (const sph::ParameterError&) {
    }
    start = end + 1;
  }
  f.parameters.describe();
}

void checkpoint(Bytes data) {
  try {
    auto c = sph::parse_checkpoint(text_of(data), "fuzz");
    sph::ParticleSet<3> body("body", {sph::Vec<3>::Zero()}, {1});
    body.register_field<sph::Real>("pressure");
    body.register_field<sph::Mat<3>>("F");
    sph::TimeStepper stepper(0, 1);
    stepper.add_periodic_callback(0.1, [](const sph::StepInfo&) {});
    sph::StateArchive archive(c.records, sph::StateArchive::Mode::load);
    auto b = archive.part("body/body");
    body.checkpoint(b);
    auto s = archive.part("stepper");
    stepper.checkpoint(s);
  } catch (const sph::ParameterError&) {
  } catch (const sph::StateError&) {
  }
}

const std::vector<Target>& targets() {
  static const std::vector<Target> all{{"surface_mesh", surface_mesh},
                                       {"tet_mesh", tet_mesh},
                                       {"config", config},
                                       {"assignments", assignments},
                                       {"checkpoint", checkpoint}};
  return all;
}

}  // namespace cardiosph::fuzz
