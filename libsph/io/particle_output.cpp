#include "libsph/io/particle_output.hpp"

#include <cstdio>
#include <iomanip>
#include <sstream>

#include "libsph/core/communicator.hpp"
#include "libsph/io/atomic_file.hpp"
#include "libsph/io/vtk/vtu_writer.hpp"

namespace sph {
namespace {

template <int Dim>
std::vector<PointArray> point_arrays(const ParticleSet<Dim>& particles, std::size_t n) {
  std::vector<PointArray> arrays;
  arrays.push_back({"volume", 1, std::vector<double>(particles.volume.begin(), particles.volume.begin() + std::ptrdiff_t(n))});
  for (const auto& base : particles.fields()) {
    if (!base->write_output()) continue;
    if (const auto* f = dynamic_cast<const FieldArray<Real>*>(base.get())) {
      arrays.push_back({f->name(), 1, std::vector<double>(f->values.begin(), f->values.begin() + std::ptrdiff_t(n))});
    } else if (const auto* v = dynamic_cast<const FieldArray<Vec<Dim>>*>(base.get())) {
      PointArray a{v->name(), 3, std::vector<double>(3 * n, 0.0)};
      for (std::size_t i = 0; i < n; ++i)
        for (int d = 0; d < Dim; ++d) a.values[3 * i + d] = v->values[i][d];
      arrays.push_back(std::move(a));
    } else if (const auto* m = dynamic_cast<const FieldArray<Mat<Dim>>*>(base.get())) {
      PointArray a{m->name(), 9, std::vector<double>(9 * n, 0.0)};
      for (std::size_t i = 0; i < n; ++i)
        for (int r = 0; r < Dim; ++r)
          for (int c = 0; c < Dim; ++c) a.values[9 * i + 3 * r + c] = m->values[i](r, c);
      arrays.push_back(std::move(a));
    } else if (const auto* k = dynamic_cast<const FieldArray<int>*>(base.get())) {
      arrays.push_back({k->name(), 1, std::vector<double>(k->values.begin(), k->values.begin() + std::ptrdiff_t(n))});
    }
  }
  return arrays;
}

}  // namespace

template <int Dim>
ParticleOutput<Dim>::ParticleOutput(std::filesystem::path folder, std::string body_name)
    : folder_(std::move(folder)), body_(std::move(body_name)) {}

namespace {
bool pieces_asked = false;
}  // namespace

void write_distributed_output_in_pieces(bool pieces) { pieces_asked = pieces; }
bool distributed_output_in_pieces() { return pieces_asked; }

template <int Dim>
void ParticleOutput<Dim>::write(const ParticleSet<Dim>& particles, double time) {
  write_file(particles, particles.n_particles(), time, false);
}

template <int Dim>
void ParticleOutput<Dim>::write_piece(const ParticleSet<Dim>& particles, double time) {
  write_file(particles, particles.n_owned(), time, true);
}

template <int Dim>
void ParticleOutput<Dim>::write_file(const ParticleSet<Dim>& particles, std::size_t n, double time, bool piece) {
  char name[256];
  std::snprintf(name, sizeof(name), piece ? "%s_%05zu.pvtu" : "%s_%05zu.vtu", body_.c_str(), entries_.size());
  std::vector<double> points(3 * n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    for (int d = 0; d < Dim; ++d) points[3 * i + d] = particles.position[i][d];
  auto arrays = point_arrays(particles, n);
  entries_.emplace_back(time, name);
  if (piece) {
    // Each particle's global id (its index in a one-rank run), so that pieces can be matched.
    const Partition<Dim>* p = particles.partition();
    PointArray ids{"global_id", 1, std::vector<double>(n)};
    for (std::size_t i = 0; i < n; ++i) ids.values[i] = p ? double(p->global_id[i]) : double(i);
    arrays.push_back(std::move(ids));
    const Communicator& world = Communicator::world();
    write_vtu_piece(folder_ / name, world.rank(), world.size(), points, arrays);
    if (!world.is_root()) return;  // rank 0 keeps the collection
  } else {
    write_vtu(folder_ / name, points, arrays);
  }

  std::ostringstream pvd;
  pvd << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n"
      << std::setprecision(12);
  for (const auto& [t, file] : entries_)
    pvd << "    <DataSet timestep=\"" << t << "\" group=\"\" part=\"0\" file=\"" << file << "\"/>\n";
  pvd << "  </Collection>\n</VTKFile>\n";
  write_file_atomically(folder_ / (body_ + ".pvd"), pvd.str());
}

template <int Dim>
void ParticleOutput<Dim>::checkpoint(StateArchive& archive) {
  std::vector<double> times;
  std::string names;
  for (const auto& [t, file] : entries_) times.push_back(t), names += file + '\n';
  archive.io("output_times", times);
  archive.io("output_files", names);
  if (archive.saving()) return;
  entries_.clear();
  std::istringstream lines(names);
  std::string file;
  for (const double t : times) {
    if (!std::getline(lines, file)) throw StateError("the state lists fewer output files of '" + body_ + "' than output times");
    entries_.emplace_back(t, file);
  }
}

template class ParticleOutput<2>;
template class ParticleOutput<3>;

}  // namespace sph
