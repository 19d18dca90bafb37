#include "libsph/diffusion/diffusion_operator.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "libsph/core/parallel.hpp"

namespace sph {

const std::vector<std::pair<std::string, DiffusionCorrection>>& diffusion_correction_names() {
  static const std::vector<std::pair<std::string, DiffusionCorrection>> names{
      {"moment", DiffusionCorrection::moment}, {"gradient", DiffusionCorrection::gradient}, {"none", DiffusionCorrection::none}};
  return names;
}

template <int Dim>
void check_diffusion_tensor(const Mat<Dim>& D, const std::string& what) {
  if (!D.allFinite()) throw std::invalid_argument(what + ": diffusion tensor has a non-finite entry");
  const Real scale = D.cwiseAbs().maxCoeff();
  if ((D - D.transpose()).cwiseAbs().maxCoeff() > Real(1e-12) * scale)
    throw std::invalid_argument(what + ": diffusion tensor is not symmetric");
  const Eigen::SelfAdjointEigenSolver<Mat<Dim>> eigen(D);
  const Real smallest = eigen.eigenvalues().minCoeff();
  if (!(smallest > Real(1e-12) * scale) || !(scale > 0)) {
    std::ostringstream s;
    s << what << ": diffusion tensor is not positive definite (eigenvalues " << eigen.eigenvalues().transpose()
      << ")";
    throw std::invalid_argument(s.str());
  }
}

template <int Dim>
Mat<Dim> transversely_isotropic_tensor(Real longitudinal, Real transverse, const Vec<Dim>& direction) {
  const Vec<Dim> f = direction.normalized();
  return transverse * Mat<Dim>::Identity() + (longitudinal - transverse) * (f * f.transpose());
}

namespace {

// Independent components of a symmetric Dim x Dim matrix: (0,0), (1,1), [(2,2)], (0,1), [(0,2), (1,2)].
template <int Dim>
constexpr int n_symmetric = Dim * (Dim + 1) / 2;

template <int Dim>
constexpr std::array<std::pair<int, int>, n_symmetric<Dim>> symmetric_components() {
  if constexpr (Dim == 2) return {{{0, 0}, {1, 1}, {0, 1}}};
  else return {{{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}}};
}

}  // namespace

template <int Dim>
std::vector<MomentSystemInverse<Dim>> diffusion_moment_systems(const InnerRelation<Dim>& relation, std::span<const Real> volume) {
  constexpr int m = n_symmetric<Dim>;
  constexpr auto components = symmetric_components<Dim>();
  using System = Eigen::Matrix<Real, m, m>;
  using Vector = Eigen::Matrix<Real, m, 1>;
  std::vector<MomentSystemInverse<Dim>> systems(relation.n_targets());
  parallel_for(relation.n_targets(), [&](std::size_t i) {
    // K[cd][ab] = sum_j V_j F_ij r_ij e_a e_b e_c e_d, times 2 for an off-diagonal ab (it appears twice in T : A).
    System K = System::Zero();
    for (const auto [k, j] : relation.row(i)) {
      const Vec<Dim>& e = relation.unit_vector[k];
      const Real w = volume[j] * (-relation.kernel_derivative[k]) * relation.distance[k];
      Vector u;
      for (int c = 0; c < m; ++c) u[c] = e[components[c].first] * e[components[c].second];
      K += w * u * u.transpose();
    }
    for (int c = 0; c < m; ++c)
      if (components[c].first != components[c].second) K.col(c) *= Real(2);
    const Eigen::FullPivLU<System> lu(K);
    auto& system = systems[i];
    system.valid = lu.rank() == m && lu.rcond() > Real(1e-8);
    system.inverse = system.valid ? System(lu.inverse()) : System::Zero();
  });
  return systems;
}

template <int Dim>
std::vector<Mat<Dim>> diffusion_moment_matrices(std::span<const MomentSystemInverse<Dim>> moment_systems,
                                                std::span<const Mat<Dim>> diffusion_tensor) {
  constexpr int m = n_symmetric<Dim>;
  constexpr auto components = symmetric_components<Dim>();
  using Vector = Eigen::Matrix<Real, m, 1>;
  const bool uniform = diffusion_tensor.size() == 1;
  std::vector<Mat<Dim>> A(moment_systems.size());
  parallel_for(moment_systems.size(), [&](std::size_t i) {
    const Mat<Dim>& D_i = uniform ? diffusion_tensor[0] : diffusion_tensor[i];
    const auto& system = moment_systems[i];
    Mat<Dim> A_i;
    if (system.valid) {
      Vector rhs;
      for (int c = 0; c < m; ++c) rhs[c] = D_i(components[c].first, components[c].second);
      const Vector a = system.inverse * rhs;
      for (int c = 0; c < m; ++c) {
        A_i(components[c].first, components[c].second) = a[c];
        A_i(components[c].second, components[c].first) = a[c];
      }
    } else {
      A_i = Real(0.5) * (Real(Dim + 2) * D_i - D_i.trace() * Mat<Dim>::Identity());
    }
    A[i] = A_i;
  });
  return A;
}

template <int Dim>
std::vector<Mat<Dim>> diffusion_moment_matrices(const InnerRelation<Dim>& relation, std::span<const Real> volume,
                                                std::span<const Mat<Dim>> diffusion_tensor) {
  const auto systems = diffusion_moment_systems<Dim>(relation, volume);
  return diffusion_moment_matrices<Dim>(std::span<const MomentSystemInverse<Dim>>(systems), diffusion_tensor);
}

template <int Dim>
std::vector<Real> diffusion_pair_coefficients(const InnerRelation<Dim>& relation, std::span<const Real> volume,
                                              std::span<const Mat<Dim>> diffusion_tensor, DiffusionCorrection correction,
                                              std::span<const Mat<Dim>> correction_matrix,
                                              std::span<const Mat<Dim>> moment_matrix) {
  const std::size_t n = relation.n_targets(), n_sources = volume.size();
  const bool uniform = diffusion_tensor.size() == 1;
  if (!uniform && diffusion_tensor.size() != n_sources)
    throw std::invalid_argument("diffusion: need one diffusion tensor or one per particle");
  if (correction == DiffusionCorrection::gradient && correction_matrix.size() != n_sources)
    throw std::invalid_argument("diffusion: need one correction matrix per particle");
  std::vector<Mat<Dim>> computed;
  std::span<const Mat<Dim>> moment = moment_matrix;
  if (correction == DiffusionCorrection::moment && moment.empty()) {
    if (n != n_sources) throw std::invalid_argument("diffusion: a distributed set needs its moment matrices with the ghosts'");
    computed = diffusion_moment_matrices<Dim>(relation, volume, diffusion_tensor);
    moment = computed;
  }
  if (correction == DiffusionCorrection::moment && moment.size() != n_sources)
    throw std::invalid_argument("diffusion: need one moment matrix per particle");

  std::vector<Real> coefficient(relation.n_pairs());
  parallel_for(n, [&](std::size_t i) {
    for (const auto [k, j] : relation.row(i)) {
      const Real r_ij = relation.distance[k];
      if (!(r_ij > 0)) {
        coefficient[k] = 0;
        continue;
      }
      const Vec<Dim>& e_ij = relation.unit_vector[k];
      const Real F_ij = -relation.kernel_derivative[k];
      Real bracket;
      if (correction == DiffusionCorrection::moment) {
        bracket = e_ij.dot((moment[i] + moment[j]) * e_ij);  // 2 e^T Abar e
      } else {
        Mat<Dim> D_ij = uniform ? diffusion_tensor[0] : Mat<Dim>(Real(0.5) * (diffusion_tensor[i] + diffusion_tensor[j]));
        if (correction == DiffusionCorrection::gradient) {
          const Mat<Dim> DB = D_ij * (Real(0.5) * (correction_matrix[i] + correction_matrix[j]));
          D_ij = Real(0.5) * (DB + DB.transpose());
        }
        bracket = Real(Dim + 2) * e_ij.dot(D_ij * e_ij) - D_ij.trace();
      }
      coefficient[k] = volume[j] * F_ij / r_ij * bracket;
    }
  });
  return coefficient;
}

template <int Dim>
void apply_diffusion(const InnerRelation<Dim>& relation, std::span<const Real> pair_coefficient,
                     std::span<const Real> value, std::span<Real> rate) {
  parallel_for(relation.n_targets(), [&](std::size_t i) {
    const Real C_i = value[i];
    Real sum = 0;
    for (const auto [k, j] : relation.row(i))
      sum += pair_coefficient[k] * (value[j] - C_i);
    rate[i] = sum;
  });
}

template <int Dim>
Real diffusion_time_step_limit(const InnerRelation<Dim>& relation, std::span<const Real> pair_coefficient) {
  const Real largest_row = parallel_max(relation.n_targets(), Real(0), [&](std::size_t i) {
    Real row = 0;
    for (const auto [k, j] : relation.row(i)) row += std::abs(pair_coefficient[k]);
    return row;
  });
  return largest_row > 0 ? Real(1) / largest_row : std::numeric_limits<Real>::infinity();
}

template void check_diffusion_tensor<2>(const Mat<2>&, const std::string&);
template void check_diffusion_tensor<3>(const Mat<3>&, const std::string&);
template Mat<2> transversely_isotropic_tensor<2>(Real, Real, const Vec<2>&);
template Mat<3> transversely_isotropic_tensor<3>(Real, Real, const Vec<3>&);
template std::vector<Real> diffusion_pair_coefficients<2>(const InnerRelation<2>&, std::span<const Real>,
                                                          std::span<const Mat<2>>, DiffusionCorrection,
                                                          std::span<const Mat<2>>, std::span<const Mat<2>>);
template std::vector<Real> diffusion_pair_coefficients<3>(const InnerRelation<3>&, std::span<const Real>,
                                                          std::span<const Mat<3>>, DiffusionCorrection,
                                                          std::span<const Mat<3>>, std::span<const Mat<3>>);
template std::vector<MomentSystemInverse<2>> diffusion_moment_systems<2>(const InnerRelation<2>&, std::span<const Real>);
template std::vector<MomentSystemInverse<3>> diffusion_moment_systems<3>(const InnerRelation<3>&, std::span<const Real>);
template std::vector<Mat<2>> diffusion_moment_matrices<2>(std::span<const MomentSystemInverse<2>>, std::span<const Mat<2>>);
template std::vector<Mat<3>> diffusion_moment_matrices<3>(std::span<const MomentSystemInverse<3>>, std::span<const Mat<3>>);
template std::vector<Mat<2>> diffusion_moment_matrices<2>(const InnerRelation<2>&, std::span<const Real>,
                                                          std::span<const Mat<2>>);
template std::vector<Mat<3>> diffusion_moment_matrices<3>(const InnerRelation<3>&, std::span<const Real>,
                                                          std::span<const Mat<3>>);
template void apply_diffusion<2>(const InnerRelation<2>&, std::span<const Real>, std::span<const Real>, std::span<Real>);
template void apply_diffusion<3>(const InnerRelation<3>&, std::span<const Real>, std::span<const Real>, std::span<Real>);
template Real diffusion_time_step_limit<2>(const InnerRelation<2>&, std::span<const Real>);
template Real diffusion_time_step_limit<3>(const InnerRelation<3>&, std::span<const Real>);

}  // namespace sph
