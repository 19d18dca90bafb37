// Built instead of vtu_writer.cpp when CARDIOSPH_WITH_VTK is off: particle fields are not written.
#include "libsph/io/vtk/vtu_writer.hpp"

#include <stdexcept>

namespace sph {

bool vtu_output_available() { return false; }

void write_vtu(const std::filesystem::path& path, const std::vector<double>&, const std::vector<PointArray>&) {
  throw std::runtime_error("cannot write '" + path.string() + "': this build has no VTK (CARDIOSPH_WITH_VTK=OFF)");
}

void write_vtu_piece(const std::filesystem::path& summary, int, int, const std::vector<double>&, const std::vector<PointArray>&) {
  throw std::runtime_error("cannot write '" + summary.string() + "': this build has no VTK (CARDIOSPH_WITH_VTK=OFF)");
}

}  // namespace sph
