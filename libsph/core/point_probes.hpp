#pragma once
// Values of particle fields at fixed points (observers), by a linear moving-least-squares fit over
// the particles within the kernel support of each point: f(p) = a, where a + b.(x_j - p) fits f_j
// with weights V_j W(|x_j - p|). The fit reproduces linear fields exactly, so a point on an edge or
// corner of the body (where a Shepard average is biased inwards) is sampled to second order. The
// weights are computed once, for particles that do not move.

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
  PointProbes(std::vector<Vec<Dim>> points, std::span<const Vec<Dim>> positions, std::span<const Real> volumes,
              const AnyKernel<Dim>& kernel, Real smoothing_length)
      : points_(std::move(points)) {
    const auto relation = build_contact_relation<Dim>(points_, positions, kernel, smoothing_length);
    offsets_ = relation.offsets;
    source_ = relation.neighbour;
    weight_.resize(source_.size());
    using Matrix = Eigen::Matrix<double, Dim + 1, Dim + 1>;
    using Vector = Eigen::Matrix<double, Dim + 1, 1>;
    for (std::size_t p = 0; p < points_.size(); ++p) {
      Matrix moment = Matrix::Zero();
      for (std::size_t k = offsets_[p]; k < offsets_[p + 1]; ++k) {
        Vector basis;
        basis << 1, (positions[source_[k]] - points_[p]).template cast<double>();
        moment += double(volumes[source_[k]] * relation.kernel_value[k]) * basis * basis.transpose();
      }
      const Eigen::FullPivLU<Matrix> lu(moment);
      if (offsets_[p + 1] - offsets_[p] < Dim + 1 || !lu.isInvertible())
        throw std::invalid_argument("probe " + std::to_string(p) + " has too few particles around it for a linear fit");
      const Vector row = lu.inverse().col(0);  // moment is symmetric: first row of its inverse
      for (std::size_t k = offsets_[p]; k < offsets_[p + 1]; ++k) {
        Vector basis;
        basis << 1, (positions[source_[k]] - points_[p]).template cast<double>();
        weight_[k] = double(volumes[source_[k]] * relation.kernel_value[k]) * row.dot(basis);
      }
    }
  }

  std::size_t size() const { return points_.size(); }
  const Vec<Dim>& point(std::size_t p) const { return points_[p]; }

  /// The fitted value of `field` at point p.
  double sample(std::size_t p, std::span<const Real> field) const {
    double value = 0;
    for (std::size_t k = offsets_[p]; k < offsets_[p + 1]; ++k) value += weight_[k] * field[source_[k]];
    return value;
  }
  /// True if every particle that contributes to point p satisfies `predicate` on its value.
  template <class Predicate>
  bool all_sources(std::size_t p, std::span<const Real> field, Predicate&& predicate) const {
    for (std::size_t k = offsets_[p]; k < offsets_[p + 1]; ++k)
      if (!predicate(field[source_[k]])) return false;
    return true;
  }

 private:
  std::vector<Vec<Dim>> points_;
  std::vector<std::size_t> offsets_;
  std::vector<Index> source_;
  std::vector<double> weight_;
};

}  // namespace sph
