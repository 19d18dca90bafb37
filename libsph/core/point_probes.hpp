#pragma once
// The one observer mechanism: values of particle fields at fixed points, by a linear
// moving-least-squares fit over the particles within the kernel support of each point,
//   f(p) = a,  where a + b.(x_j - p) fits f_j with weights V_j W(|x_j - p|).
// The fit reproduces linear fields exactly, so a point on an edge or corner of the body (where a
// Shepard average is biased inwards) is sampled to second order.
//
// Configurations. Built on the reference positions of a total-Lagrangian body, the weights are
// fixed and a probe follows the material point: sampling the current positions gives where that
// point has moved (exact for affine motion), sampling a field gives its value there. Built on the
// current positions (fluids, or points fixed in space), update() recomputes the weights after the
// particles move. Any field type that is a vector space (Real, Vec<Dim>, Mat<Dim>) can be sampled.

#include <Eigen/Dense>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "libsph/core/neighbour_relation.hpp"

namespace sph {

template <int Dim>
class PointProbes {
 public:
  /// Probes at `points` over the particles at `positions` (reference or current configuration).
  PointProbes(std::vector<Vec<Dim>> points, std::span<const Vec<Dim>> positions, std::span<const Real> volumes,
              const AnyKernel<Dim>& kernel, Real smoothing_length)
      : points_(std::move(points)), kernel_(kernel), smoothing_length_(smoothing_length) {
    update(positions, volumes);
  }

  /// Recomputes the weights for particles now at `positions` (probes in the current configuration).
  /// Throws std::invalid_argument naming the probe when too few particles surround it.
  void update(std::span<const Vec<Dim>> positions, std::span<const Real> volumes) {
    rebuild_contact_relation<Dim>(relation_, points_, positions, kernel_, smoothing_length_);
    weight_.resize(relation_.n_pairs());
    using Matrix = Eigen::Matrix<double, Dim + 1, Dim + 1>;
    using Vector = Eigen::Matrix<double, Dim + 1, 1>;
    const auto& offsets = relation_.offsets;
    const auto& source = relation_.neighbour;
    for (std::size_t p = 0; p < points_.size(); ++p) {
      Matrix moment = Matrix::Zero();
      for (std::size_t k = offsets[p]; k < offsets[p + 1]; ++k) {
        Vector basis;
        basis << 1, (positions[source[k]] - points_[p]).template cast<double>();
        moment += double(volumes[source[k]] * relation_.kernel_value[k]) * basis * basis.transpose();
      }
      const Eigen::FullPivLU<Matrix> lu(moment);
      if (offsets[p + 1] - offsets[p] < Dim + 1 || !lu.isInvertible())
        throw std::invalid_argument("probe " + std::to_string(p) + " has too few particles around it for a linear fit");
      const Vector row = lu.inverse().col(0);  // moment is symmetric: first row of its inverse
      for (std::size_t k = offsets[p]; k < offsets[p + 1]; ++k) {
        Vector basis;
        basis << 1, (positions[source[k]] - points_[p]).template cast<double>();
        weight_[k] = double(volumes[source[k]] * relation_.kernel_value[k]) * row.dot(basis);
      }
    }
  }

  std::size_t size() const { return points_.size(); }
  const Vec<Dim>& point(std::size_t p) const { return points_[p]; }

  /// The fitted value of a scalar field at point p.
  double sample(std::size_t p, std::span<const Real> field) const {
    double value = 0;
    for (std::size_t k = relation_.offsets[p]; k < relation_.offsets[p + 1]; ++k)
      value += weight_[k] * field[relation_.neighbour[k]];
    return value;
  }
  /// The fitted value of a vector or tensor field at point p.
  template <class T>
  T sample_value(std::size_t p, std::span<const T> field) const {
    T value = field[0] * Real(0);
    for (std::size_t k = relation_.offsets[p]; k < relation_.offsets[p + 1]; ++k)
      value += Real(weight_[k]) * field[relation_.neighbour[k]];
    return value;
  }
  /// True if every particle that contributes to point p satisfies `predicate` on its value.
  template <class Predicate>
  bool all_sources(std::size_t p, std::span<const Real> field, Predicate&& predicate) const {
    for (std::size_t k = relation_.offsets[p]; k < relation_.offsets[p + 1]; ++k)
      if (!predicate(field[relation_.neighbour[k]])) return false;
    return true;
  }

 private:
  std::vector<Vec<Dim>> points_;
  AnyKernel<Dim> kernel_;
  Real smoothing_length_;
  ContactRelation<Dim> relation_;
  std::vector<double> weight_;
};

}  // namespace sph
