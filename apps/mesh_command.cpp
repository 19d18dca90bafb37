#include "apps/mesh_command.hpp"

#include <iostream>

#include "apps/run_scene.hpp"
#include "geometry/heart_meshes.hpp"

namespace cardiosph {

int run_mesh_command(const std::string& kind, const std::filesystem::path& folder, double edge, bool quiet) {
  geometry::TriangleMesh mesh;
  std::string stem;
  double analytic_volume = 0;
  if (kind == "lv-ellipsoid") {
    const geometry::LvEllipsoid lv;
    mesh = geometry::lv_ellipsoid_mesh(lv, edge > 0 ? edge : 0.5);
    analytic_volume = geometry::lv_ellipsoid_volume(lv);
    stem = "lv_ellipsoid";
  } else if (kind == "biventricular") {
    const geometry::Biventricular biv;
    mesh = geometry::biventricular_mesh(biv, edge > 0 ? edge : 1.5);
    analytic_volume = geometry::shape_volume(*geometry::biventricular_shape(biv), 0.1);
    stem = "biventricular";
  } else {
    std::cerr << "cardiosph mesh: unknown kind '" << kind << "' (expected lv-ellipsoid or biventricular)\n";
    return exit_bad_input;
  }
  const auto check = geometry::require_valid_mesh(mesh, stem);
  const auto files = geometry::write_heart_mesh_files(mesh, folder, stem);
  if (!quiet) {
    std::cout << stem << ": " << check.faces << " faces, " << check.vertices << " vertices, closed and outward; volume "
              << check.volume << " mm^3 (analytic " << analytic_volume << ", relative difference "
              << check.volume / analytic_volume - 1 << ")\n";
    for (const auto& f : files) std::cout << "  " << f.string() << '\n';
  }
  return exit_ok;
}

}  // namespace cardiosph
