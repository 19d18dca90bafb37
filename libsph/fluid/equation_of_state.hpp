#pragma once
// Equations of state of a weakly-compressible fluid (Monaghan 1994, J. Comput. Phys. 110:399;
// Morris, Fox & Zhu 1997, J. Comput. Phys. 136:214):
//   linear (isothermal):  p = c0^2 (rho - rho0),
//   Tait:                 p = rho0 c0^2 / gamma ((rho / rho0)^gamma - 1),  c = c0 (rho / rho0)^((gamma - 1) / 2).
// c0 is an artificial sound speed, about ten times the largest flow speed, so that density varies by
// about 1 % (Mach 0.1).

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "libsph/core/types.hpp"

namespace sph {

enum class EquationOfStateKind { linear, tait };

inline const std::vector<std::pair<std::string, EquationOfStateKind>>& equation_of_state_names() {
  static const std::vector<std::pair<std::string, EquationOfStateKind>> names{{"linear", EquationOfStateKind::linear},
                                                                              {"tait", EquationOfStateKind::tait}};
  return names;
}

struct EquationOfState {
  EquationOfStateKind kind = EquationOfStateKind::linear;
  Real reference_density = 1;  ///< rho0
  Real sound_speed = 10;       ///< c0
  Real tait_exponent = 7;      ///< gamma (Tait only)

  Real pressure(Real density) const {
    if (kind == EquationOfStateKind::linear) return sound_speed * sound_speed * (density - reference_density);
    return reference_density * sound_speed * sound_speed / tait_exponent *
           (std::pow(density / reference_density, tait_exponent) - Real(1));
  }
  /// The density at which the pressure is p (the inverse of pressure()).
  Real density(Real p) const {
    if (kind == EquationOfStateKind::linear) return reference_density + p / (sound_speed * sound_speed);
    return reference_density *
           std::pow(Real(1) + tait_exponent * p / (reference_density * sound_speed * sound_speed), Real(1) / tait_exponent);
  }
  /// Compression energy per unit mass, e(rho) = int_rho0^rho p(s) / s^2 ds (for energy budgets).
  double internal_energy(Real density) const {
    const double r = density / reference_density, c2 = double(sound_speed) * sound_speed;
    if (kind == EquationOfStateKind::linear) return c2 * (std::log(r) + 1 / r - 1);
    const double g = tait_exponent;
    return c2 / g * ((std::pow(r, g - 1) - 1) / (g - 1) + 1 / r - 1);
  }
};

}  // namespace sph
