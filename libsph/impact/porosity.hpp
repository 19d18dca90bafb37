#pragma once
// The p-alpha model of porous materials under impact (Herrmann 1969, J. Appl. Phys. 40:2490;
// Carroll & Holt 1972, J. Appl. Phys. 43:759; in SPH, Jutzi, Benz & Michel 2008, Icarus 198:242;
// the equations as collected in the impact SPH theory notes, impact_sph_theory.rst, "P-alpha
// Porosity") over the Tillotson equation of state of the matrix (tillotson.hpp).
//
// A porous material of bulk density rho holds a solid matrix of density rho_s = alpha rho; the
// distension alpha >= 1 is 1 / (1 - porosity). Herrmann's pressure: the matrix carries the load
// over a fraction 1 / alpha of the area, so with p_s the matrix equation of state,
//
//   p = p_s(rho_s, e) / alpha = p_s(alpha rho, e) / alpha                             (Herrmann 1969)
//
// (e the specific internal energy, the same per unit mass for the bulk and the matrix: the pores
// are empty). The distension follows the quadratic crush curve (Jutzi et al. 2008, eq. for the
// "quadratic" compaction model; the theory notes), p_e the elastic limit, p_s the pressure of full
// compaction:
//
//   alpha_crush(p) = alpha0                                        for p <= p_e
//                  = 1 + (alpha0 - 1) ((p_s - p) / (p_s - p_e))^2   for p_e < p < p_s
//                  = 1                                             for p >= p_s
//
// Compaction is irreversible (Herrmann 1969; Carroll & Holt 1972): the distension only decreases,
//
//   alpha_new = min(alpha_old, alpha_crush(p(alpha_new))),
//
// so below the crush curve (the elastic regime, and any unloading after compaction) the
// distension stays, and the pressure is p_s(alpha rho, e) / alpha at the stored alpha.
//
// The state (p, alpha) is found consistently, not by the rate form d alpha / dt = (d alpha / dp)
// (dp / dt) of Jutzi et al. 2008: with g(alpha) = alpha - min(alpha_old, alpha_crush(p(alpha))),
// g(1) <= 0 (min(...) >= 1) and g(alpha_old) >= 0 (min(...) <= alpha_old), and g is continuous (the
// Tillotson pressure and the crush curve are continuous), so [1, alpha_old] brackets a root; it is
// found by Newton's method with the analytic g' kept inside the bracket, falling back to bisection
// ("rtsafe", Press et al., Numerical Recipes), until the Newton correction is below 4 ulps of alpha
// (typically 6-13 Tillotson evaluations; at most 200). Where p(alpha) increases with alpha (a more
// compressed matrix pushes harder, true of the Tillotson compressed branch for B <= A and of every
// published set in tillotson_materials()),
// g is strictly increasing and the root is unique.
//
// Sound speed. At a frozen distension p(rho, e) = p_s(alpha rho, e) / alpha gives
//   dp/drho|_e = dp_s/drho_s,   dp/de|_rho = (1 / alpha) dp_s/de,
// and the isentropic c^2 = dp/drho + p / rho^2 dp/de = dp_s/drho_s + p_s / rho_s^2 dp_s/de
// = c_s^2(rho_s, e) exactly: the bulk sound speed of this model is the matrix's at the matrix
// density. This is the speed of elastic (and unloading) waves, the fastest signal of the model, and
// so the one for the time step and the artificial viscosity. It is higher than the measured
// elastic wave speed of real porous rock, which Jutzi et al. 2008 model with an extra parameter
// c_e and an elastic slope of the crush curve; this module has neither. On the crush curve the
// loading (plastic) wave is slower: c^2 = c_s^2 / (1 - alpha' (rho dp_s/drho_s - p) / alpha) with
// alpha' = d alpha_crush / dp <= 0; it is reported as crush_sound_speed_squared. Tillotson's c_s^2
// falls below zero in tension; both are floored at 0.01 A / rho0, the floor of the non-porous
// impact body (updated_lagrangian.cpp).

#include "libsph/impact/tillotson.hpp"

namespace sph {

struct PAlphaParameters {
  double alpha0 = 1;            ///< initial distension rho_s0 / rho_0 >= 1 (1: not porous)
  double elastic_pressure = 0;  ///< p_e [Pa]: the crush curve starts
  double solid_pressure = 0;    ///< p_s [Pa]: full compaction, p_s > p_e

  /// Throws std::invalid_argument naming the first impossible value (alpha0 < 1, p_e < 0,
  /// p_s <= p_e, or any not finite).
  void check() const;
};

/// alpha_crush(p) of the quadratic crush curve above (no irreversibility: see porous_tillotson).
double crush_curve(const PAlphaParameters& porosity, double pressure);

/// d alpha_crush / dp: 0 outside (p_e, p_s), -2 (alpha0 - 1) (p_s - p) / (p_s - p_e)^2 inside.
double crush_curve_slope(const PAlphaParameters& porosity, double pressure);

struct PorousState {
  double pressure = 0;             ///< bulk pressure p = p_s(alpha rho, e) / alpha
  double distension = 1;           ///< alpha = min(previous, alpha_crush(p)), in [1, previous]
  double sound_speed_squared = 0;  ///< max(c_s^2(alpha rho, e), floor): elastic / unloading waves
  double crush_sound_speed_squared = 0;  ///< on the crush curve, the slower loading wave (floored)
  int iterations = 0;              ///< root-finding steps (0: the state was settled without a solve)
};

/// The consistent porous state at bulk density rho > 0 and specific energy e, given the particle's
/// stored distension previous_distension >= 1 (alpha0 at the start). The caller stores the returned
/// distension. Throws std::invalid_argument for rho <= 0 or previous_distension < 1 (or not finite).
/// Parameters are not checked here (call check() once).
PorousState porous_tillotson(const TillotsonParameters& matrix, const PAlphaParameters& porosity, double density,
                             double energy, double previous_distension);

/// The bulk density of the uncompressed porous material at rest, rho0 / alpha0, where p = 0 at e = 0.
double porous_reference_density(const TillotsonParameters& matrix, const PAlphaParameters& porosity);

}  // namespace sph
