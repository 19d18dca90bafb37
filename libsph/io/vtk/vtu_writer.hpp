#pragma once
// Particles as a VTK XML unstructured grid of vertices (.vtu), readable by ParaView.
// No VTK type appears here; VTK stays inside vtu_writer.cpp.

#include <filesystem>
#include <string>
#include <vector>

class vtkUnstructuredGrid;

namespace sph {

struct PointArray {
  std::string name;
  int n_components = 1;        ///< 1 (scalar), 3 (vector) or 9 (tensor, row-major)
  std::vector<double> values;  ///< n_points * n_components
};

/// Writes points (x, y, z per point) and point arrays to `path` atomically.
void write_vtu(const std::filesystem::path& path, const std::vector<double>& points_xyz,
               const std::vector<PointArray>& arrays);

/// Writes this rank's piece of a distributed set: the piece `piece` of `pieces` into the folder
/// named after `summary` (<stem>/<stem>_<piece>.vtu), and with piece 0 the summary file itself
/// (.pvtu, which ParaView opens as one data set). VTK's parallel XML writer, one piece per rank.
void write_vtu_piece(const std::filesystem::path& summary, int piece, int pieces, const std::vector<double>& points_xyz,
                     const std::vector<PointArray>& arrays);

/// Writes a grid built by the caller (VTK code of its own, e.g. tetrahedral meshes) to `path`
/// atomically, in the same form as write_vtu (appended binary, zlib). Builds with VTK only.
void write_unstructured_grid(vtkUnstructuredGrid& grid, const std::filesystem::path& path);

/// True when the build has VTK output (CARDIOSPH_WITH_VTK).
bool vtu_output_available();

}  // namespace sph
