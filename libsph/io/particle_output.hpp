#pragma once
// Writes a particle set as a time series for ParaView: <body>_NNNNN.vtu per output time and
// <body>.pvd listing them with their times (open the .pvd in ParaView). Positions, volumes and
// every registered field marked for output are written; vectors and tensors of 2D sets are padded
// to 3 and 3x3 components. A distributed set is written either whole by rank 0 after a gather
// (the files of a one-rank run; the default) or, with write_distributed_output_in_pieces(true)
// (`--output-pieces`), by every rank as its piece of <body>_NNNNN.pvtu (pieces in the folder
// <body>_NNNNN/, each with the particles' global_id), listed in the same .pvd.

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "libsph/core/particles.hpp"
#include "libsph/core/state_archive.hpp"

namespace sph {

/// Whether distributed sets are written in pieces, one per rank (see above); off by default.
void write_distributed_output_in_pieces(bool pieces);
bool distributed_output_in_pieces();

template <int Dim>
class ParticleOutput {
 public:
  ParticleOutput(std::filesystem::path folder, std::string body_name);
  void write(const ParticleSet<Dim>& particles, double time);
  /// This rank's owned particles as its piece of the frame's .pvtu (collective: every rank calls it).
  void write_piece(const ParticleSet<Dim>& particles, double time);
  std::size_t n_files() const { return entries_.size(); }
  /// Saves or loads the list of files written (checkpoints); the files themselves stay in the folder.
  void checkpoint(StateArchive& archive);

 private:
  void write_file(const ParticleSet<Dim>& particles, std::size_t n, double time, bool piece);
  std::filesystem::path folder_;
  std::string body_;
  std::vector<std::pair<double, std::string>> entries_;
};

extern template class ParticleOutput<2>;
extern template class ParticleOutput<3>;

}  // namespace sph
