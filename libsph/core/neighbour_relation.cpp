#include "libsph/core/neighbour_relation.hpp"

#include <stdexcept>
#include <string>

#include "libsph/core/cell_linked_list.hpp"
#include "libsph/core/parallel.hpp"

namespace sph {
namespace {

/// Appends to list.extended_sources the images of `sources` that lie within `support` of the box
/// across its periodic faces (every combination of shifts by -1, 0, +1 periods but none).
template <int Dim>
void add_periodic_images(NeighbourList<Dim>& list, std::span<const Vec<Dim>> sources, const PeriodicBox<Dim>& box,
                         Real support) {
  const Vec<Dim> period = box.period();
  for (int d = 0; d < Dim; ++d)
    if (box.periodic[d] && !(period[d] >= 2 * support))
      throw std::invalid_argument("neighbour relation: periodic length " + std::to_string(period[d]) + " along axis " +
                                  std::to_string(d) + " is shorter than two kernel supports (" +
                                  std::to_string(2 * support) + ")");
  list.extended_sources.assign(sources.begin(), sources.end());
  list.image_origin.clear();
  int n_shifts = 1;
  for (int d = 0; d < Dim; ++d) n_shifts *= 3;
  for (std::size_t j = 0; j < sources.size(); ++j) {
    for (int s = 0; s < n_shifts; ++s) {
      int code = s;
      bool moved = false, near = true;
      Vec<Dim> image = sources[j];
      for (int d = 0; d < Dim; ++d, code /= 3) {
        const int shift = code % 3 - 1;
        if (shift == 0) continue;
        if (!box.periodic[d]) {
          near = false;
          break;
        }
        image[d] += Real(shift) * period[d];
        moved = true;
        if (image[d] < box.lower[d] - support || image[d] > box.upper[d] + support) near = false;
      }
      if (moved && near) {
        list.extended_sources.push_back(image);
        list.image_origin.push_back(static_cast<Index>(j));
      }
    }
  }
}

template <int Dim, class Kernel>
void fill_relation(NeighbourList<Dim>& list, std::span<const Vec<Dim>> targets, std::span<const Vec<Dim>> sources_in,
                   Real h, bool exclude_self, const PeriodicBox<Dim>* box = nullptr, bool keep_candidates = true,
                   const Partition<Dim>* partition = nullptr, SourceOrder source_order = SourceOrder::by_index) {
  if (!(h > 0)) throw std::invalid_argument("neighbour relation: smoothing length must be positive");
  const Real support = Kernel::support_radius(h);
  const Real support2 = support * support;
  std::span<const Vec<Dim>> sources = sources_in;
  const std::size_t n_original = sources_in.size();
  if (box && box->any()) {
    add_periodic_images(list, sources_in, *box, support);
    sources = list.extended_sources;
  } else {
    list.image_origin.clear();
  }
  const auto& origin = list.image_origin;
  auto source_index = [&](Index j) { return j < n_original ? j : origin[j - n_original]; };
  if (partition) {
    if (box && box->any()) throw std::logic_error("neighbour relation: periodic images of a distributed set are not supported");
    list.cells.rebuild(sources, support, &partition->grid_origin, partition->id_order);
  } else {
    list.cells.rebuild(sources, support);
  }
  if (source_order == SourceOrder::by_position) list.cells.order_by_position(sources);
  const auto& cells = list.cells;
  const std::size_t n = targets.size();
  list.smoothing_length = h;

  // Pass 1: count the neighbours of each target, keeping up to `stride` of them (enough for any
  // particle distribution near a lattice) so that the second pass need not search again.
  auto& count = list.row_count;
  count.resize(n);
  const std::size_t stride = keep_candidates ? (Dim == 2 ? 48 : 128) : 0;
  list.candidates.resize(n * stride);
  parallel_for(n, [&](std::size_t i) {
    std::size_t c = 0;
    Index* kept = list.candidates.data() + i * stride;
    cells.for_each_within(targets[i], support2, [&](Index j) {
      if (exclude_self && j == i) return;
      if (c < stride) kept[c] = j;
      ++c;
    });
    count[i] = c;
  });

  list.size_rows(count);

  // Pass 2: fill each row in the same candidate order.
  const Real normalisation = Kernel::normalisation(h), inverse_h = Real(1) / h;
  list.kernel_value_at_zero = normalisation * Kernel::shape(Real(0));
  const Real derivative_scale = normalisation * inverse_h;
  parallel_for(n, [&](std::size_t i) {
    std::size_t k = list.offsets[i];
    auto fill = [&](Index j) {
      if (exclude_self && j == i) return;
      const Vec<Dim> x_ij = targets[i] - sources[j];
      const Real r2 = x_ij.squaredNorm();
      if (!(r2 < support2)) return;
      const Real r = std::sqrt(r2);
      list.neighbour[k] = source_index(j);
      list.distance[k] = r;
      const Real q = r * inverse_h;
      list.kernel_value[k] = normalisation * Kernel::shape(q);
      list.kernel_derivative[k] = derivative_scale * Kernel::shape_derivative(q);
      list.unit_vector[k] = r > 0 ? Vec<Dim>(x_ij / r) : Vec<Dim>::Zero();
      ++k;
    };
    if (count[i] <= stride) {
      const Index* kept = list.candidates.data() + i * stride;
      for (std::size_t c = 0; c < count[i]; ++c) fill(kept[c]);
    } else {
      cells.for_each_candidate(targets[i], fill);  // a crowded row: search again
    }
  });
}

}  // namespace

template <int Dim>
void rebuild_inner_relation(InnerRelation<Dim>& relation, std::span<const Vec<Dim>> positions,
                            const AnyKernel<Dim>& kernel, Real smoothing_length) {
  std::visit([&]<class K>(const K&) { fill_relation<Dim, K>(relation, positions, positions, smoothing_length, true); },
             kernel);
}

template <int Dim>
void rebuild_contact_relation(ContactRelation<Dim>& relation, std::span<const Vec<Dim>> targets,
                              std::span<const Vec<Dim>> sources, const AnyKernel<Dim>& kernel, Real smoothing_length,
                              SourceOrder order) {
  std::visit([&]<class K>(const K&) {
    fill_relation<Dim, K>(relation, targets, sources, smoothing_length, false, nullptr, true, nullptr, order);
  }, kernel);
}

template <int Dim>
void rebuild_inner_relation(InnerRelation<Dim>& relation, const ParticleSet<Dim>& particles, const AnyKernel<Dim>& kernel,
                            Real smoothing_length, const PeriodicBox<Dim>& box, SourceOrder order) {
  const std::span<const Vec<Dim>> all = particles.position;
  std::visit([&]<class K>(const K&) {
    fill_relation<Dim, K>(relation, all.first(particles.n_owned()), all, smoothing_length, true, &box, true,
                          particles.partition(), order);
  }, kernel);
}

template <int Dim>
void rebuild_inner_relation(InnerRelation<Dim>& relation, std::span<const Vec<Dim>> positions,
                            const AnyKernel<Dim>& kernel, Real smoothing_length, const PeriodicBox<Dim>& box) {
  std::visit(
      [&]<class K>(const K&) { fill_relation<Dim, K>(relation, positions, positions, smoothing_length, true, &box); },
      kernel);
}

template <int Dim>
void rebuild_contact_relation(ContactRelation<Dim>& relation, std::span<const Vec<Dim>> targets,
                              std::span<const Vec<Dim>> sources, const AnyKernel<Dim>& kernel, Real smoothing_length,
                              const PeriodicBox<Dim>& box) {
  std::visit(
      [&]<class K>(const K&) { fill_relation<Dim, K>(relation, targets, sources, smoothing_length, false, &box); },
      kernel);
}

// A relation built once (solids, probes) does not keep the candidates of its counting pass: the
// second pass searches again instead of holding a stride of indices per particle.
template <int Dim>
InnerRelation<Dim> build_inner_relation(std::span<const Vec<Dim>> positions, const AnyKernel<Dim>& kernel,
                                        Real smoothing_length) {
  InnerRelation<Dim> relation;
  std::visit([&]<class K>(const K&) {
    fill_relation<Dim, K>(relation, positions, positions, smoothing_length, true, nullptr, false);
  }, kernel);
  return relation;
}

template <int Dim>
InnerRelation<Dim> build_inner_relation(const ParticleSet<Dim>& particles, const AnyKernel<Dim>& kernel,
                                        Real smoothing_length) {
  InnerRelation<Dim> relation;
  const std::span<const Vec<Dim>> all = particles.position;
  std::visit([&]<class K>(const K&) {
    fill_relation<Dim, K>(relation, all.first(particles.n_owned()), all, smoothing_length, true, nullptr, false,
                          particles.partition());
  }, kernel);
  return relation;
}

template <int Dim>
ContactRelation<Dim> build_contact_relation(std::span<const Vec<Dim>> targets, std::span<const Vec<Dim>> sources,
                                            const AnyKernel<Dim>& kernel, Real smoothing_length) {
  ContactRelation<Dim> relation;
  std::visit([&]<class K>(const K&) {
    fill_relation<Dim, K>(relation, targets, sources, smoothing_length, false, nullptr, false);
  }, kernel);
  return relation;
}

template <int Dim>
std::vector<std::vector<Index>> brute_force_neighbours(std::span<const Vec<Dim>> targets,
                                                       std::span<const Vec<Dim>> sources, Real support_radius,
                                                       bool exclude_self) {
  std::vector<std::vector<Index>> rows(targets.size());
  for (std::size_t i = 0; i < targets.size(); ++i)
    for (std::size_t j = 0; j < sources.size(); ++j) {
      if (exclude_self && i == j) continue;
      if ((targets[i] - sources[j]).squaredNorm() < support_radius * support_radius)
        rows[i].push_back(static_cast<Index>(j));
    }
  return rows;
}

template void rebuild_inner_relation<2>(InnerRelation<2>&, std::span<const Vec<2>>, const AnyKernel<2>&, Real);
template void rebuild_inner_relation<3>(InnerRelation<3>&, std::span<const Vec<3>>, const AnyKernel<3>&, Real);
template void rebuild_contact_relation<2>(ContactRelation<2>&, std::span<const Vec<2>>, std::span<const Vec<2>>,
                                          const AnyKernel<2>&, Real, SourceOrder);
template void rebuild_contact_relation<3>(ContactRelation<3>&, std::span<const Vec<3>>, std::span<const Vec<3>>,
                                          const AnyKernel<3>&, Real, SourceOrder);
template void rebuild_inner_relation<2>(InnerRelation<2>&, const ParticleSet<2>&, const AnyKernel<2>&, Real,
                                        const PeriodicBox<2>&, SourceOrder);
template void rebuild_inner_relation<3>(InnerRelation<3>&, const ParticleSet<3>&, const AnyKernel<3>&, Real,
                                        const PeriodicBox<3>&, SourceOrder);
template void rebuild_inner_relation<2>(InnerRelation<2>&, std::span<const Vec<2>>, const AnyKernel<2>&, Real,
                                        const PeriodicBox<2>&);
template void rebuild_inner_relation<3>(InnerRelation<3>&, std::span<const Vec<3>>, const AnyKernel<3>&, Real,
                                        const PeriodicBox<3>&);
template void rebuild_contact_relation<2>(ContactRelation<2>&, std::span<const Vec<2>>, std::span<const Vec<2>>,
                                          const AnyKernel<2>&, Real, const PeriodicBox<2>&);
template void rebuild_contact_relation<3>(ContactRelation<3>&, std::span<const Vec<3>>, std::span<const Vec<3>>,
                                          const AnyKernel<3>&, Real, const PeriodicBox<3>&);
template InnerRelation<2> build_inner_relation<2>(std::span<const Vec<2>>, const AnyKernel<2>&, Real);
template InnerRelation<3> build_inner_relation<3>(std::span<const Vec<3>>, const AnyKernel<3>&, Real);
template InnerRelation<2> build_inner_relation<2>(const ParticleSet<2>&, const AnyKernel<2>&, Real);
template InnerRelation<3> build_inner_relation<3>(const ParticleSet<3>&, const AnyKernel<3>&, Real);
template ContactRelation<2> build_contact_relation<2>(std::span<const Vec<2>>, std::span<const Vec<2>>,
                                                      const AnyKernel<2>&, Real);
template ContactRelation<3> build_contact_relation<3>(std::span<const Vec<3>>, std::span<const Vec<3>>,
                                                      const AnyKernel<3>&, Real);
template std::vector<std::vector<Index>> brute_force_neighbours<2>(std::span<const Vec<2>>, std::span<const Vec<2>>,
                                                                   Real, bool);
template std::vector<std::vector<Index>> brute_force_neighbours<3>(std::span<const Vec<3>>, std::span<const Vec<3>>,
                                                                   Real, bool);

}  // namespace sph
