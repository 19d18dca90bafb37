#pragma once
// Kernel-correction matrix B_i = ( - sum_j V_j x_ij (x) grad_i W_ij )^{-1}, x_ij = x_i - x_j,
// which makes the corrected gradient sum_j V_j (f_j - f_i) B_i grad_i W_ij exact for linear f.
// Source: Bonet & Lok 1999, Comput. Methods Appl. Mech. Eng. 180:97, eq. (34) ("corrected gradient");
// used in total-Lagrangian SPH as B0 (Vignjevic, Reveles, Campbell 2006).
// With grad_i W_ij = dW/dr e_ij and x_ij = r_ij e_ij the sum is  - sum_j V_j r_ij dW/dr e_ij (x) e_ij.
// Deviation: where that matrix is (nearly) singular (an isolated or collinear neighbourhood,
// det < 1e-6 relative to the full-support value det = 1) B_i = I is used instead.

#include <span>
#include <vector>

#include "libsph/core/neighbour_relation.hpp"
#include "libsph/core/parallel.hpp"

namespace sph {

/// B from its moment matrix -sum_j V_j r_ij dW/dr e_ij (x) e_ij, with the guard above.
template <int Dim>
Mat<Dim> correction_from_moment(const Mat<Dim>& moment) {
  return moment.determinant() > Real(1e-6) ? Mat<Dim>(moment.inverse()) : Mat<Dim>::Identity();
}

template <int Dim>
void compute_correction_matrix(const NeighbourList<Dim>& relation, std::span<const Real> source_volume,
                               std::span<Mat<Dim>> correction_matrix) {
  parallel_for(relation.n_targets(), [&](std::size_t i) {
    Mat<Dim> moment = Mat<Dim>::Zero();
    for (const auto [k, j] : relation.row(i)) {
      const Vec<Dim>& e_ij = relation.unit_vector[k];
      moment -= source_volume[j] * relation.distance[k] * relation.kernel_derivative[k] *
                (e_ij * e_ij.transpose());
    }
    correction_matrix[i] = correction_from_moment<Dim>(moment);
  });
}

}  // namespace sph
