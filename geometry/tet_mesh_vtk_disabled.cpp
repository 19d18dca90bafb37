#include "geometry/tet_mesh_vtk.hpp"

namespace geometry::detail {

TetMesh read_vtu_tets(const std::filesystem::path& path, double) {
  throw MeshError("tetrahedral mesh '" + path.string() + "': this build has no VTK (CARDIOSPH_WITH_VTK=OFF), so it reads openCARP meshes only");
}

void write_vtu_tets(const TetMesh&, const std::filesystem::path& path, double) {
  throw MeshError("write_tet_mesh: '" + path.string() + "': this build has no VTK (CARDIOSPH_WITH_VTK=OFF)");
}

}  // namespace geometry::detail
