#pragma once
// The Tillotson equation of state of solids under impact (Tillotson 1962, General Atomic report
// GA-3216; in the form of Melosh 1989, "Impact cratering", and Benz & Asphaug 1999, Icarus 142:5).
// With eta = rho / rho0, mu = eta - 1, nu = 1 / eta - 1 and z = e / (e0 eta^2):
//
//   compressed (eta >= 1), or expanded and cold (e <= e_iv):
//     p_c = (a + b / (1 + z)) rho e + A mu + B mu^2
//   expanded and hot (eta < 1, e >= e_cv):
//     p_e = a rho e + (b rho e / (1 + z) + A mu exp(-beta nu)) exp(-alpha nu^2)
//   expanded, partly vaporised (eta < 1, e_iv < e < e_cv): the linear interpolation in e
//     p = (p_e (e - e_iv) + p_c (e_cv - e)) / (e_cv - e_iv)
//
// The sound speed is the isentropic one, c^2 = dp/drho|_e + p / rho^2 dp/de|_rho (de = p / rho^2
// drho along an isentrope), with the partial derivatives of each branch in closed form. At rest
// (rho0, e = 0) it is sqrt(A / rho0): A is the bulk modulus.
//
// Units: SI (kg/m^3, J/kg, Pa) in the published sets; any consistent set works.

#include <string>
#include <vector>

namespace sph {

struct TillotsonParameters {
  double reference_density = 0;  ///< rho0
  double A = 0, B = 0;           ///< [pressure] A: bulk modulus
  double e0 = 0;                 ///< [energy / mass]
  double a = 0, b = 0, alpha = 0, beta = 0;  ///< dimensionless
  double e_iv = 0, e_cv = 0;     ///< specific energies of incipient and complete vaporisation

  /// Throws std::invalid_argument naming the first impossible value (rho0, A, e0 <= 0; a, b, alpha,
  /// beta or B < 0; e_cv <= e_iv or e_iv < 0).
  void check() const;
};

/// A published material set with its source.
struct TillotsonMaterial {
  std::string name, source;
  TillotsonParameters parameters;
};

/// The sets of Benz & Asphaug 1999 (Icarus 142:5, table II): basalt, granite, ice (SI units).
const std::vector<TillotsonMaterial>& tillotson_materials();
/// The named set; std::invalid_argument listing the names if there is none.
const TillotsonMaterial& tillotson_material(const std::string& name);

/// Pressure and its partial derivatives at one state.
struct TillotsonState {
  double pressure = 0;
  double dp_drho = 0;  ///< at constant e
  double dp_de = 0;    ///< at constant rho
  enum class Branch { compressed, cold_expanded, interpolated, hot_expanded } branch = Branch::compressed;
  /// c^2 = dp/drho + p / rho^2 dp/de; may be negative in tension, where the material has no sound speed.
  double sound_speed_squared(double density) const { return dp_drho + pressure / (density * density) * dp_de; }
};

/// The Tillotson state at density rho > 0 and specific internal energy e.
TillotsonState tillotson(const TillotsonParameters& m, double density, double energy);

}  // namespace sph
