#pragma once
// Pseudo-ECG: the extracellular potential at electrodes in an unbounded homogeneous volume conductor
// of conductivity sigma_b around the tissue, from the monodomain solution. The transmembrane current
// per volume is I_m = div(sigma grad V) (sigma = chi C_m D, the tissue conductivity), and the
// potential of these sources at an electrode x_e is
//   phi_e(x_e) = 1 / (4 pi sigma_b) int I_m / r dv,   r = |x - x_e|,
// which with no flux through the tissue boundary integrates by parts to
//   phi_e(x_e) = 1 / (4 pi sigma_b) int sigma grad V . (x - x_e) / r^3 dv
// (Plonsey & Barr, Bioelectricity, ch. 8; Gima & Rudy 2002, Circ. Res. 90:889, eq. 1, with sigma_i
// there and the monodomain conductivity here). A front moving towards an electrode gives a positive
// deflection. With sigma in S/m, V in mV and lengths in mm, phi_e is in mV; since
// sigma [S/m] = chi [1/mm] C_m [uF/mm^2] D [mm^2/ms] with no further factor, the tissue enters
// through D and the ratio chi C_m / sigma_b.
//
// On a deforming tissue (total-Lagrangian, reference X, deformation gradient F, J = det F) the
// conduction tensor of the monodomain is the pull-back D0 = F^-1 D F^-T (cardio/electromechanics.hpp),
// so D grad_x V = F D0 Grad_X V and dv = J dV:
//   phi_e(x_e) = chi C_m / (4 pi sigma_b) sum_j V0_j J_j (F_j D0_j G_j) . (x_j - x_e) / r_j^3,
// with G_j the corrected SPH gradient of V on the reference relation (Bonet & Lok 1999) and x_j the
// current positions. A fixed tissue has F = I, J = 1, D0 = D.
//
// Leads combine electrode potentials: the standard 12 leads are I = LA - RA, II = LL - RA,
// III = LL - LA, aVR = RA - (LA + LL)/2, aVL = LA - (RA + LL)/2, aVF = LL - (RA + LA)/2 and
// V1..V6 minus Wilson's central terminal (RA + LA + LL)/3.

#include <span>
#include <string>
#include <vector>

#include "libsph/core/neighbour_relation.hpp"
#include "libsph/core/particles.hpp"
#include "libsph/core/types.hpp"

namespace cardio {

using sph::Real;

struct Electrode {
  std::string name;
  sph::Vec<3> position;
};

/// A lead: sum of weight * electrode potential.
struct Lead {
  std::string name;
  std::vector<std::pair<std::size_t, double>> terms;  ///< electrode index, weight
};

/// The standard 12 leads over the electrodes named RA, LA, LL, V1..V6 (in any order among
/// `electrodes`); throws std::invalid_argument naming a missing electrode.
std::vector<Lead> twelve_leads(const std::vector<Electrode>& electrodes);

/// Electrodes of a 12-lead ECG around a heart, in its mesh coordinates, from the heart's frame: its
/// centre, the direction from base to apex and the direction from the LV to the RV cavity. The
/// heart is placed in the body as in an upright adult (its long axis pointing left, anterior and
/// inferior at equal angles, the RV anterior and to the right of the LV); the precordial electrodes
/// lie on a circle of `chest_radius` around the heart centre in the body's transverse plane (V1
/// 20 degrees right of anterior, V2 10 degrees left, V3 35, V4 60, V5 85, V6 110 degrees), the limb
/// electrodes at `limb_distance` towards the right shoulder (RA), left shoulder (LA) and left leg (LL).
std::vector<Electrode> twelve_lead_electrodes(const sph::Vec<3>& centre, const sph::Vec<3>& base_to_apex,
                                              const sph::Vec<3>& lv_to_rv, double chest_radius, double limb_distance);

class PseudoEcg {
 public:
  /// Electrodes around a tissue whose reference positions, volumes and inner relation are given (the
  /// relation and volumes must outlive this). `source_to_bath` = chi C_m / sigma_b [1/(mm^2/ms)].
  /// Throws std::invalid_argument naming an electrode closer than `min_distance` to a particle.
  /// On a distributed tissue, `particles` is its particle set (the arrays are then this rank's
  /// particles, the relation's rows its owned ones, and the potentials the whole tissue's, summed
  /// in global-id order as on one rank).
  PseudoEcg(std::vector<Electrode> electrodes, const sph::NeighbourList<3>& relation,
            std::span<const sph::Vec<3>> reference_positions, std::span<const Real> volumes, double source_to_bath,
            double min_distance, const sph::ParticleSet<3>* particles = nullptr);

  /// Electrode potentials [mV] of the potential V with conduction tensors D0 (one, or one per
  /// particle), at current positions x with deformation gradients F (empty: the reference, F = I).
  std::vector<double> potentials(std::span<const Real> V, std::span<const sph::Mat<3>> D0, std::span<const sph::Vec<3>> x,
                                 std::span<const sph::Mat<3>> F = {}) const;

  const std::vector<Electrode>& electrodes() const { return electrodes_; }

 private:
  std::vector<Electrode> electrodes_;
  const sph::NeighbourList<3>& relation_;
  const sph::ParticleSet<3>* particles_;
  std::span<const sph::Vec<3>> reference_;
  std::span<const Real> volume_;
  double scale_;
  std::vector<sph::Mat<3>> correction_;
  mutable std::vector<sph::Vec<3>> flux_, whole_flux_, whole_x_;
};

/// Lead values from electrode potentials.
std::vector<double> lead_values(const std::vector<Lead>& leads, const std::vector<double>& potentials);

}  // namespace cardio
