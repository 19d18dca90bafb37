#pragma once
// SPH discretisation of the (an)isotropic diffusion operator div(D grad C) for a constant or slowly
// varying tensor D, on an inner relation:
//
//   div(D grad C)_i ~= sum_j a_ij (C_j - C_i),
//   a_ij = V_j F_ij / r_ij [ (d + 2) e_ij^T D_ij e_ij - tr D_ij ],   F_ij = -dW/dr(r_ij) >= 0,
//
// with d the dimension and D_ij = (D_i + D_j) / 2. For D = kappa I this is the Brookshaw (1985)
// Laplacian 2 kappa sum_j V_j F_ij / r_ij (C_j - C_i). The bracket is the weighting that makes the
// sum reproduce D : grad grad C for an isotropic kernel (Espanol & Revenga 2003, Phys. Rev. E
// 67:026705; derived from the fourth moment of the kernel in docs/diffusion.md). Tran-Duc,
// Phan-Thien & Khoo 2016 (Int. J. Numer. Meth. Fluids 82:730, doi:10.1002/fld.4238) obtain
// anisotropic SPH diffusion by the coordinate transform x' = D^{-1/2} x.
//
// Corrections (DiffusionCorrection):
// - none: D_ij as above.
// - gradient: D_ij is replaced by the symmetric part of D_ij Bbar_ij, Bbar_ij = (B_i + B_j) / 2, with
//   B the kernel-correction matrix (correction_matrix.hpp), the way SPHinXsys brings B into its
//   diffusion (Zhang et al. 2021, CMAME 381:113847). B restores the second moment where the support
//   is truncated, but not the fourth moment that the weighting above relies on.
// - moment (default): the bracket is replaced by 2 e_ij^T Abar_ij e_ij, Abar_ij = (A_i + A_j) / 2, with
//   A_i the symmetric matrix solving  sum_j V_j F_ij r_ij (e^T A_i e)(e^T H e) = D_i : H  for every
//   symmetric H, i.e. the operator is exact on quadratic fields (grad C = 0 at i) for the particle
//   distribution at hand. For an isotropic moment tensor A_i = ((d + 2) D - tr D I) / 2 and the
//   bracket above is recovered. On a square or cubic lattice with h = 1.3 dp the discrete fourth
//   moment is not isotropic, which leaves an O(1) error for anisotropic D that does not fall with
//   resolution (measured: 3.7 % on the diffusion-aniso scene); the moment correction removes it.
//   A_i is found from a 3x3 (2D) or 6x6 (3D) system per particle; where it is singular (too few
//   neighbours) the uncorrected bracket is used for that particle.
// The pair averages keep a_ij = a_ji for equal volumes, so the operator conserves sum_i V_i C_i.
//
// With a fixed relation (particles that do not move, or a total-Lagrangian reference configuration)
// a_ij is computed once and every evaluation is one multiply-add per pair.

#include <span>
#include <string>
#include <utility>
#include <vector>

#include "libsph/core/neighbour_relation.hpp"
#include "libsph/core/types.hpp"

namespace sph {

/// Throws std::invalid_argument naming `what` unless D is finite, symmetric and positive definite.
template <int Dim>
void check_diffusion_tensor(const Mat<Dim>& D, const std::string& what);

/// D = d_t I + (d_l - d_t) f (x) f for a unit direction f.
template <int Dim>
Mat<Dim> transversely_isotropic_tensor(Real longitudinal, Real transverse, const Vec<Dim>& direction);

enum class DiffusionCorrection { none, gradient, moment };
/// The names of the corrections as parameters take them.
const std::vector<std::pair<std::string, DiffusionCorrection>>& diffusion_correction_names();

/// The geometric part of the moment correction of one particle: the inverse of its moment system
/// (3x3 in 2D, 6x6 in 3D), which depends on the relation and the volumes only, so that a fixed
/// relation computes it once and a new tensor D costs one small matrix-vector product per particle.
/// `valid` is false where the system is singular (the uncorrected bracket is used there).
template <int Dim>
struct MomentSystemInverse {
  static constexpr int size = Dim * (Dim + 1) / 2;
  Eigen::Matrix<Real, size, size> inverse;
  bool valid = false;
};

/// The inverted moment systems of every particle (see above).
template <int Dim>
std::vector<MomentSystemInverse<Dim>> diffusion_moment_systems(const InnerRelation<Dim>& relation, std::span<const Real> volume);

/// Pair coefficients a_ij of the operator above, stored along the relation's pairs.
/// `diffusion_tensor` holds one tensor (uniform) or one per particle; `correction_matrix` (one per
/// particle) is needed for DiffusionCorrection::gradient only; `moment_matrix` (one per particle,
/// from diffusion_moment_matrices) may be passed for DiffusionCorrection::moment, else it is
/// computed here. Per-particle arrays cover every source of the relation: on a distributed set the
/// ghosts too (their values updated from their owners), so it must be passed there.
template <int Dim>
std::vector<Real> diffusion_pair_coefficients(const InnerRelation<Dim>& relation, std::span<const Real> volume,
                                              std::span<const Mat<Dim>> diffusion_tensor, DiffusionCorrection correction,
                                              std::span<const Mat<Dim>> correction_matrix = {},
                                              std::span<const Mat<Dim>> moment_matrix = {});

/// The matrices A_i of the moment correction (see above), one per particle.
template <int Dim>
std::vector<Mat<Dim>> diffusion_moment_matrices(const InnerRelation<Dim>& relation, std::span<const Real> volume,
                                                std::span<const Mat<Dim>> diffusion_tensor);
/// The same from the inverted moment systems.
template <int Dim>
std::vector<Mat<Dim>> diffusion_moment_matrices(std::span<const MomentSystemInverse<Dim>> moment_systems,
                                                std::span<const Mat<Dim>> diffusion_tensor);

/// rate_i = sum_j a_ij (C_j - C_i).
template <int Dim>
void apply_diffusion(const InnerRelation<Dim>& relation, std::span<const Real> pair_coefficient,
                     std::span<const Real> value, std::span<Real> rate);

/// Largest forward-Euler step of dC/dt = sum_j a_ij (C_j - C_i): the operator's eigenvalues lie
/// in the Gershgorin discs, |lambda| <= 2 max_i sum_j |a_ij|, and forward Euler (and Heun's RK2)
/// is stable for real lambda in [-2/dt, 0], so dt <= 1 / max_i sum_j |a_ij|.
template <int Dim>
Real diffusion_time_step_limit(const InnerRelation<Dim>& relation, std::span<const Real> pair_coefficient);

}  // namespace sph
