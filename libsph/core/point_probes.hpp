#pragma once
// The one observer mechanism: values of particle fields at fixed points, by a linear
// moving-least-squares fit over the particles within the kernel support of each point,
//   f(p) = a,  where a + b.(x_j - p) fits f_j with weights V_j W(|x_j - p|).
// The fit reproduces linear fields exactly, so a point on an edge or corner of the body (where a
// Shepard average is biased inwards) is sampled to second order.
//
// The weights satisfy sum_j w_j = 1 and sum_j w_j (x_j - p) = 0, so for a field with the Taylor
// expansion f(x) = f(p) + g.(x - p) + 1/2 (x - p).H (x - p) the fit is off by +1/2 sum_j w_j d_j.H d_j
// (d_j = x_j - p). Where the particles also carry the gradient G_j of the field (the deformation
// gradient F for the position field of a solid), sample_with_gradient takes
//   f(p) = sum_j w_j (f_j - 1/2 G_j d_j),
// whose quadratic terms cancel (f_j - 1/2 G_j d_j = f(p) + 1/2 g.d_j + O(d^3) with G_j = g + H d_j),
// so it is exact on quadratic fields. Near a free surface, where the support is one-sided and spans
// much of a thin wall, this removes the bias of the linear fit (e.g. an apex position under bending).
//
// Configurations. Built on the reference positions of a total-Lagrangian body, the weights are
// fixed and a probe follows the material point: sampling the current positions (with F as their
// gradient) gives where that point has moved, sampling a field gives its value there. Built on the
// current positions (fluids, or points fixed in space), update() recomputes the weights after the
// particles move. Any field type that is a vector space (Real, Vec<Dim>, Mat<Dim>) can be sampled.
//
// ProbeFit::shepard takes the kernel-weighted average f(p) = sum_j V_j W_j f_j / sum_j V_j W_j
// instead: first order only, but defined with a single particle in reach and zero with none, which
// is what a pressure sensor on a wall that a fluid reaches only later needs.

#include <Eigen/Dense>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "libsph/core/neighbour_relation.hpp"

namespace sph {

enum class ProbeFit { linear, shepard };

template <int Dim>
class PointProbes {
 public:
  /// Probes at `points` over the particles at `positions` (reference or current configuration).
  PointProbes(std::vector<Vec<Dim>> points, std::span<const Vec<Dim>> positions, std::span<const Real> volumes,
              const AnyKernel<Dim>& kernel, Real smoothing_length, ProbeFit fit = ProbeFit::linear)
      : points_(std::move(points)), kernel_(kernel), smoothing_length_(smoothing_length), fit_(fit) {
    update(positions, volumes);
  }

  /// Recomputes the weights for particles now at `positions` (probes in the current configuration).
  /// The particles enter each probe's sums in the order of their positions (SourceOrder::by_position),
  /// so a sample does not depend on the order in which they are stored or gathered.
  /// Throws std::invalid_argument naming the probe when too few particles surround it.
  void update(std::span<const Vec<Dim>> positions, std::span<const Real> volumes) {
    rebuild_contact_relation<Dim>(relation_, points_, positions, kernel_, smoothing_length_, SourceOrder::by_position);
    weight_.resize(relation_.n_pairs());
    offset_.resize(relation_.n_pairs());
    using Matrix = Eigen::Matrix<double, Dim + 1, Dim + 1>;
    using Vector = Eigen::Matrix<double, Dim + 1, 1>;
    if (fit_ == ProbeFit::shepard) {
      for (std::size_t p = 0; p < points_.size(); ++p) {
        double total = 0;
        for (const auto [k, j] : relation_.row(p)) total += double(volumes[j] * relation_.kernel_value[k]);
        for (const auto [k, j] : relation_.row(p)) {
          weight_[k] = total > 0 ? double(volumes[j] * relation_.kernel_value[k]) / total : 0.0;
          offset_[k] = positions[j] - points_[p];
        }
      }
      return;
    }
    for (std::size_t p = 0; p < points_.size(); ++p) {
      Matrix moment = Matrix::Zero();
      for (const auto [k, j] : relation_.row(p)) {
        Vector basis;
        basis << 1, (positions[j] - points_[p]).template cast<double>();
        moment += double(volumes[j] * relation_.kernel_value[k]) * basis * basis.transpose();
      }
      const Eigen::FullPivLU<Matrix> lu(moment);
      if (relation_.n_neighbours(p) < Dim + 1 || !lu.isInvertible())
        throw std::invalid_argument("probe " + std::to_string(p) + " has too few particles around it for a linear fit");
      const Vector first_row = lu.inverse().col(0);  // moment is symmetric: first row of its inverse
      for (const auto [k, j] : relation_.row(p)) {
        Vector basis;
        basis << 1, (positions[j] - points_[p]).template cast<double>();
        weight_[k] = double(volumes[j] * relation_.kernel_value[k]) * first_row.dot(basis);
        offset_[k] = positions[j] - points_[p];
      }
    }
  }

  std::size_t size() const { return points_.size(); }
  /// Number of particles within reach of point p.
  std::size_t n_sources(std::size_t p) const { return relation_.offsets[p + 1] - relation_.offsets[p]; }
  const Vec<Dim>& point(std::size_t p) const { return points_[p]; }

  /// The fitted value of a scalar field at point p.
  double sample(std::size_t p, std::span<const Real> field) const {
    double value = 0;
    for (const auto [k, j] : relation_.row(p))
      value += weight_[k] * field[j];
    return value;
  }
  /// The fitted value of a vector or tensor field at point p.
  template <class T>
  T sample_value(std::size_t p, std::span<const T> field) const {
    T value = field[0] * Real(0);
    for (const auto [k, j] : relation_.row(p))
      value += Real(weight_[k]) * field[j];
    return value;
  }
  /// The value at point p of a field with known gradients (exact on quadratic fields, see above):
  /// sum_j w_j (f_j - 1/2 G_j (x_j - p)), with x_j the positions the probes were last built on.
  template <class T, class Gradient>
  T sample_with_gradient(std::size_t p, std::span<const T> field, std::span<const Gradient> gradient) const {
    T value = field[0] * Real(0);
    for (const auto [k, j] : relation_.row(p)) {
      value += Real(weight_[k]) * (field[j] - Real(0.5) * (gradient[j] * offset_[k]));
    }
    return value;
  }
  /// True if every particle that contributes to point p satisfies `predicate` on its value.
  template <class Predicate>
  bool all_sources(std::size_t p, std::span<const Real> field, Predicate&& predicate) const {
    for (const auto [k, j] : relation_.row(p))
      if (!predicate(field[j])) return false;
    return true;
  }

 private:
  std::vector<Vec<Dim>> points_;
  AnyKernel<Dim> kernel_;
  Real smoothing_length_;
  ProbeFit fit_;
  ContactRelation<Dim> relation_;
  std::vector<double> weight_;
  std::vector<Vec<Dim>> offset_;  ///< x_j - p of each pair
};

}  // namespace sph
