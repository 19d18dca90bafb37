#pragma once
// Writes a particle set as a time series for ParaView: <body>_NNNNN.vtu per output time and
// <body>.pvd listing them with their times (open the .pvd in ParaView). Positions, volumes and
// every registered field marked for output are written; vectors and tensors of 2D sets are padded
// to 3 and 3x3 components.

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "libsph/core/particles.hpp"
#include "libsph/core/state_archive.hpp"

namespace sph {

template <int Dim>
class ParticleOutput {
 public:
  ParticleOutput(std::filesystem::path folder, std::string body_name);
  void write(const ParticleSet<Dim>& particles, double time);
  std::size_t n_files() const { return entries_.size(); }
  /// Saves or loads the list of files written (checkpoints); the files themselves stay in the folder.
  void checkpoint(StateArchive& archive);

 private:
  std::filesystem::path folder_;
  std::string body_;
  std::vector<std::pair<double, std::string>> entries_;
};

extern template class ParticleOutput<2>;
extern template class ParticleOutput<3>;

}  // namespace sph
