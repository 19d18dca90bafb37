#pragma once
// Fibre and sheet fields on particles.
//
// Rule-based (LDRB, Bayer, Blake, Plank & Trayanova 2012, Ann. Biomed. Eng. 40:2243): four
// Laplace problems on the particles, each a sparse linear system of the SPH Laplacian
//   sum_j V_i V_j 2 |dW/dr| / r_ij (u_i - u_j) = 0       (symmetric; no-flux where no value is set)
// with Dirichlet values on labelled surface particles, solved by conjugate gradients:
//   phi_epi: 1 on the epicardium, 0 on both endocardia    (transmural coordinate e)
//   phi_lv:  1 on the LV endocardium, 0 on the epicardium and the RV endocardium
//   phi_rv:  1 on the RV endocardium, 0 on the epicardium and the LV endocardium
//   psi:     1 on the base, 0 at the apex (epicardial particles within 2 dp of the point farthest
//            from the base plane)                       (apico-basal coordinate)
// Gradients by the kernel-corrected SPH gradient. At each particle, with d = phi_rv / (phi_lv + phi_rv)
// and e = phi_epi, frames axis(u, v) = [e0 e1 e2] with e1 = u/|u| (apex to base), e2 = v
// orthogonalised (transmural), e0 = e1 x e2 (circumferential) are blended as in Bayer et al.:
//   A_endo = bislerp(axis(grad psi, -grad phi_lv), axis(grad psi, grad phi_rv), d)
//   A      = bislerp(A_endo, axis(grad psi, grad phi_epi), e)
// and then rotated: e0 by alpha about e2 (towards e1) gives the fibre, the frame by beta about the
// fibre gives the sheet, with
//   alpha = s alpha_s(d) (1 - e) + alpha_epi e,   alpha_s(d) = alpha_endo (1 - 2d)   (beta alike)
// (s = -1 where A was flipped to face the epicardium, i.e. the RV free wall, whose axis points into
// its cavity). The septum belongs to the LV: across it the angle turns from alpha_endo on the LV
// side to -alpha_endo on the RV side, as in Bayer's alpha_s. bislerp is the quaternion slerp that
// first picks, among the four equivalent frames (axes flipped in pairs), the one nearest the first.
// Deviation from Bayer et al.: they rotate before blending, Q = bislerp(Q_endo, Q_epi, e) with the
// epicardial frame at alpha_w(e) = alpha_endo (1 - e) + alpha_epi e. Blending rotated frames makes
// the angle quadratic in e (30 degrees off mid-wall for +-60), and once the endo and epi fibres
// differ by more than 90 degrees the nearest equivalent frame turns them through the longitudinal
// direction instead of the circumferential one. Blending the unrotated frames and interpolating the
// angle keeps the prescribed linear law.
//
// Output per particle: fibre f = the rotated e0, sheet s = the rotated e2 (across the wall), and
// the normal n = f x s.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "geometry/heart_meshes.hpp"
#include "geometry/shape.hpp"
#include "geometry/tet_mesh.hpp"

namespace cardio {

struct FibreField {
  std::vector<geometry::Vec3> fibre, sheet;
  /// Laplace coordinates (LDRB only; empty otherwise).
  std::vector<double> transmural, apicobasal, lv, rv;
  long solver_iterations = 0;
  double solver_seconds = 0, total_seconds = 0;
  std::size_t matrix_nonzeros = 0;
};

struct LdrbSettings {
  double alpha_endo_deg = 60, alpha_epi_deg = -60;  ///< helix angle at the endo- and epicardium
  double beta_endo_deg = 0, beta_epi_deg = 0;       ///< sheet angle at the endo- and epicardium
  double smoothing_ratio = 1.3;                     ///< h / dp for the Laplacian and gradients
  std::string kernel = "wendland_c2";
  double tolerance = 1e-8;                          ///< relative residual of the linear solves
};

/// LDRB fibres for particles with volumes and surface labels (cardio/surface_labels.hpp);
/// `base_normal` is the outward normal of the base plane (to find the apex). Throws
/// std::invalid_argument when a label the rule needs is missing (epicardium, LV endocardium, base).
FibreField ldrb_fibres(const std::vector<geometry::Vec3>& positions, const std::vector<double>& volumes,
                       const std::vector<std::int8_t>& labels, const geometry::Vec3& base_normal, double spacing,
                       const LdrbSettings& settings);

/// The same fibre and sheet everywhere (sheet orthogonalised against the fibre).
FibreField uniform_fibres(std::size_t n, const geometry::Vec3& fibre, const geometry::Vec3& sheet);

/// Fibres from a text file of lines "x y z fx fy fz [sx sy sz]" (commas or blanks; '#' comments),
/// each particle taking the vectors of its nearest point. Throws std::invalid_argument naming the
/// file and line on a malformed line, a zero vector or an empty file.
FibreField fibres_from_file(const std::vector<geometry::Vec3>& positions, const std::filesystem::path& path);

/// Fibres interpolated from a tetrahedral mesh (geometry/tet_mesh.hpp, checked) to the particles.
/// Each particle takes the tetrahedron that holds it (the nearest for a particle just outside):
/// point fibres are blended with its barycentric weights after their signs are aligned with the
/// first vertex's (fibres have no sign), cell fibres are taken as they are; the fibre is
/// normalised and the sheet orthogonalised against it. Without sheets in the mesh, `sheet` is
/// left empty (the caller chooses one). `outside` (optional) receives the number of particles
/// that lay outside every tetrahedron.
FibreField fibres_from_tet_mesh(const std::vector<geometry::Vec3>& positions, const geometry::TetMesh& mesh,
                                std::size_t* outside = nullptr);

/// The helix angle of `fibre` [degrees, in (-90, 90]]: its angle from `circumferential` in the plane
/// of `circumferential` and `longitudinal` (orthonormal, tangent to the wall), positive towards
/// `longitudinal`. Fibres have no sign, so f and -f give the same angle.
double helix_angle_deg(const geometry::Vec3& fibre, const geometry::Vec3& circumferential,
                       const geometry::Vec3& longitudinal);

/// The analytic frame of the truncated ellipsoidal LV at p: the transmural coordinate t (0 on the
/// endocardium, 1 on the epicardium) of the ellipsoid with radii interpolated between endo- and
/// epicardium that passes through p (r_s(t) = r_s,endo + t (r_s,epi - r_s,endo), same for r_l),
/// its outward normal, the circumferential direction (-y, x, 0)/r and the longitudinal direction
/// (z projected orthogonally to the normal).
struct LvEllipsoidFrame {
  double t = 0;
  geometry::Vec3 normal, circumferential, longitudinal;
};
LvEllipsoidFrame lv_ellipsoid_frame(const geometry::Vec3& p, const geometry::LvEllipsoid& lv);

/// The fibre angle on the truncated ellipsoidal LV against the prescribed law
/// alpha(e) = alpha_endo (1 - e) + alpha_epi e, with e the transmural coordinate of the field.
/// Directions are analytic (lv_ellipsoid_frame) and independent of the fibre rule. Particles within `rim` of the base plane or within `axis` of the long axis
/// (where the circumferential direction is undefined) are left out.
struct FibreAngleCheck {
  double mad_deg = 0;   ///< mean absolute deviation
  double max_deg = 0;   ///< largest absolute deviation
  std::size_t particles = 0;
};
FibreAngleCheck check_lv_ellipsoid_fibres(const std::vector<geometry::Vec3>& positions, const FibreField& field,
                                          const geometry::LvEllipsoid& lv, const LdrbSettings& settings, double rim,
                                          double axis);

}  // namespace cardio
