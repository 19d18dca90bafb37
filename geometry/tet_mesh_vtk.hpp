#pragma once
// The .vtu side of geometry/tet_mesh.hpp (tet_mesh_vtk.cpp with VTK, or a stand-in that refuses
// .vtu files when the project is built without VTK). Internal to the geometry library.

#include <filesystem>

#include "geometry/tet_mesh.hpp"

namespace geometry::detail {

TetMesh read_vtu_tets(const std::filesystem::path& path, double scale);
void write_vtu_tets(const TetMesh& mesh, const std::filesystem::path& path, double scale);

}  // namespace geometry::detail
