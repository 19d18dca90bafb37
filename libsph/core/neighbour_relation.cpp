#include "libsph/core/neighbour_relation.hpp"

#include <stdexcept>

#include "libsph/core/cell_linked_list.hpp"
#include "libsph/core/parallel.hpp"

namespace sph {
namespace {

template <int Dim, class Kernel>
void fill_relation(NeighbourList<Dim>& list, std::span<const Vec<Dim>> targets, std::span<const Vec<Dim>> sources,
                   Real h, bool exclude_self) {
  if (!(h > 0)) throw std::invalid_argument("neighbour relation: smoothing length must be positive");
  const Real support = Kernel::support_radius(h);
  const Real support2 = support * support;
  list.cells.rebuild(sources, support);
  const auto& cells = list.cells;
  const std::size_t n = targets.size();
  list.smoothing_length = h;

  // Pass 1: count the neighbours of each target.
  auto& count = list.row_count;
  count.resize(n);
  parallel_for(n, [&](std::size_t i) {
    std::size_t c = 0;
    cells.for_each_candidate(targets[i], [&](Index j) {
      if (exclude_self && j == i) return;
      if ((targets[i] - sources[j]).squaredNorm() < support2) ++c;
    });
    count[i] = c;
  });

  // Exclusive scan into row offsets.
  list.offsets.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) list.offsets[i + 1] = list.offsets[i] + count[i];
  const std::size_t n_pairs = list.offsets[n];
  list.neighbour.resize(n_pairs);
  list.kernel_value.resize(n_pairs);
  list.kernel_derivative.resize(n_pairs);
  list.distance.resize(n_pairs);
  list.unit_vector.resize(n_pairs);

  // Pass 2: fill each row in the same candidate order.
  parallel_for(n, [&](std::size_t i) {
    std::size_t k = list.offsets[i];
    cells.for_each_candidate(targets[i], [&](Index j) {
      if (exclude_self && j == i) return;
      const Vec<Dim> x_ij = targets[i] - sources[j];
      const Real r2 = x_ij.squaredNorm();
      if (!(r2 < support2)) return;
      const Real r = std::sqrt(r2);
      list.neighbour[k] = j;
      list.distance[k] = r;
      list.kernel_value[k] = Kernel::value(r, h);
      list.kernel_derivative[k] = Kernel::derivative(r, h);
      list.unit_vector[k] = r > 0 ? Vec<Dim>(x_ij / r) : Vec<Dim>::Zero();
      ++k;
    });
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
                              std::span<const Vec<Dim>> sources, const AnyKernel<Dim>& kernel, Real smoothing_length) {
  std::visit([&]<class K>(const K&) { fill_relation<Dim, K>(relation, targets, sources, smoothing_length, false); },
             kernel);
}

template <int Dim>
InnerRelation<Dim> build_inner_relation(std::span<const Vec<Dim>> positions, const AnyKernel<Dim>& kernel,
                                        Real smoothing_length) {
  InnerRelation<Dim> relation;
  rebuild_inner_relation<Dim>(relation, positions, kernel, smoothing_length);
  return relation;
}

template <int Dim>
ContactRelation<Dim> build_contact_relation(std::span<const Vec<Dim>> targets, std::span<const Vec<Dim>> sources,
                                            const AnyKernel<Dim>& kernel, Real smoothing_length) {
  ContactRelation<Dim> relation;
  rebuild_contact_relation<Dim>(relation, targets, sources, kernel, smoothing_length);
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
                                          const AnyKernel<2>&, Real);
template void rebuild_contact_relation<3>(ContactRelation<3>&, std::span<const Vec<3>>, std::span<const Vec<3>>,
                                          const AnyKernel<3>&, Real);
template InnerRelation<2> build_inner_relation<2>(std::span<const Vec<2>>, const AnyKernel<2>&, Real);
template InnerRelation<3> build_inner_relation<3>(std::span<const Vec<3>>, const AnyKernel<3>&, Real);
template ContactRelation<2> build_contact_relation<2>(std::span<const Vec<2>>, std::span<const Vec<2>>,
                                                      const AnyKernel<2>&, Real);
template ContactRelation<3> build_contact_relation<3>(std::span<const Vec<3>>, std::span<const Vec<3>>,
                                                      const AnyKernel<3>&, Real);
template std::vector<std::vector<Index>> brute_force_neighbours<2>(std::span<const Vec<2>>, std::span<const Vec<2>>,
                                                                   Real, bool);
template std::vector<std::vector<Index>> brute_force_neighbours<3>(std::span<const Vec<3>>, std::span<const Vec<3>>,
                                                                   Real, bool);

}  // namespace sph
