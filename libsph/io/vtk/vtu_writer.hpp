#pragma once
// Particles as a VTK XML unstructured grid of vertices (.vtu), readable by ParaView.
// No VTK type appears here; VTK stays inside vtu_writer.cpp.

#include <filesystem>
#include <string>
#include <vector>

namespace sph {

struct PointArray {
  std::string name;
  int n_components = 1;        ///< 1 (scalar), 3 (vector) or 9 (tensor, row-major)
  std::vector<double> values;  ///< n_points * n_components
};

/// Writes points (x, y, z per point) and point arrays to `path` atomically.
void write_vtu(const std::filesystem::path& path, const std::vector<double>& points_xyz,
               const std::vector<PointArray>& arrays);

/// True when the build has VTK output (CARDIOSPH_WITH_VTK).
bool vtu_output_available();

}  // namespace sph
