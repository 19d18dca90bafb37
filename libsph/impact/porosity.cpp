#include "libsph/impact/porosity.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace sph {

void PAlphaParameters::check() const {
  auto fail = [](const std::string& what) { throw std::invalid_argument("p-alpha parameters: " + what); };
  if (!std::isfinite(alpha0) || !(alpha0 >= 1)) fail("alpha0 = " + std::to_string(alpha0) + " (the initial distension) must be finite and >= 1");
  if (!std::isfinite(elastic_pressure) || !(elastic_pressure >= 0))
    fail("elastic_pressure p_e = " + std::to_string(elastic_pressure) + " must be finite and >= 0");
  if (!std::isfinite(solid_pressure) || !(solid_pressure > elastic_pressure))
    fail("solid_pressure p_s = " + std::to_string(solid_pressure) + " must be finite and > elastic_pressure p_e = " +
         std::to_string(elastic_pressure));
}

// The quadratic crush curve (Jutzi, Benz & Michel 2008, Icarus 198:242; impact_sph_theory.rst,
// "P-alpha Porosity"): alpha0 up to p_e, 1 + (alpha0 - 1) ((p_s - p) / (p_s - p_e))^2 between, 1 from p_s.
double crush_curve(const PAlphaParameters& m, double p) {
  if (p <= m.elastic_pressure) return m.alpha0;
  if (p >= m.solid_pressure) return 1;
  const double x = (m.solid_pressure - p) / (m.solid_pressure - m.elastic_pressure);
  return 1 + (m.alpha0 - 1) * x * x;
}

double crush_curve_slope(const PAlphaParameters& m, double p) {
  if (p <= m.elastic_pressure || p >= m.solid_pressure) return 0;
  const double span = m.solid_pressure - m.elastic_pressure;
  return -2 * (m.alpha0 - 1) * (m.solid_pressure - p) / (span * span);
}

double porous_reference_density(const TillotsonParameters& matrix, const PAlphaParameters& porosity) {
  return matrix.reference_density / porosity.alpha0;
}

namespace {

// The matrix state at distension alpha and its bulk pressure p = p_s(alpha rho, e) / alpha (Herrmann 1969).
struct Trial {
  double alpha;
  TillotsonState matrix;
  double pressure;
};
Trial trial(const TillotsonParameters& m, double rho, double e, double alpha) {
  const auto s = tillotson(m, alpha * rho, e);
  return {alpha, s, s.pressure / alpha};
}

PorousState finish(const TillotsonParameters& m, const PAlphaParameters& porosity, double rho, const Trial& t, int iterations) {
  const double rho_s = t.alpha * rho, floor = 0.01 * m.A / m.reference_density;
  // Frozen distension: c^2 = c_s^2(rho_s, e) (derivation in porosity.hpp).
  const double c2 = t.matrix.sound_speed_squared(rho_s);
  // On the crush curve: c^2 = c_s^2 / (1 - alpha' (rho dp_s/drho_s - p) / alpha).
  const double slope = crush_curve_slope(porosity, t.pressure);
  const double denominator = 1 - slope * (rho * t.matrix.dp_drho - t.pressure) / t.alpha;
  const double c2_crush = denominator > 1 ? c2 / denominator : c2;
  PorousState out;
  out.pressure = t.pressure;
  out.distension = t.alpha;
  out.sound_speed_squared = std::max(c2, floor);
  out.crush_sound_speed_squared = std::max(c2_crush, floor);
  out.iterations = iterations;
  return out;
}

}  // namespace

PorousState porous_tillotson(const TillotsonParameters& m, const PAlphaParameters& porosity, double rho, double e,
                             double previous) {
  if (!std::isfinite(rho) || !(rho > 0)) throw std::invalid_argument("porous_tillotson: density " + std::to_string(rho) + " must be > 0");
  if (!std::isfinite(previous) || !(previous >= 1))
    throw std::invalid_argument("porous_tillotson: previous distension " + std::to_string(previous) + " must be >= 1");
  // g(alpha) = alpha - min(previous, alpha_crush(p(alpha))): g(1) <= 0 <= g(previous) (porosity.hpp).
  auto g = [&](const Trial& t) { return t.alpha - std::min(previous, crush_curve(porosity, t.pressure)); };

  // Not porous (any more): the matrix itself, p = p_s(rho, e) exactly.
  if (previous == 1) return finish(m, porosity, rho, trial(m, rho, e, 1), 0);
  // Elastic, or unloading after compaction: alpha_crush(p(previous)) >= previous keeps the distension.
  const Trial top = trial(m, rho, e, previous);
  if (g(top) <= 0) return finish(m, porosity, rho, top, 0);
  // Fully compacted: even the solid matrix at rho pushes beyond p_s.
  const Trial bottom = trial(m, rho, e, 1);
  const double g_bottom = g(bottom);
  if (g_bottom >= 0) return finish(m, porosity, rho, bottom, 0);

  // Compaction: g(lo) < 0 < g(hi). Newton's method on g kept inside the bracket, in the form of "rtsafe"
  // (Press et al., Numerical Recipes, 3rd ed., section 9.4): a Newton step that leaves the bracket or does
  // not at least halve the step before last is replaced by bisection. With dp/dalpha at fixed rho and e,
  //   dp/dalpha = (rho dp_s/drho_s - p) / alpha          (differentiating p = p_s(alpha rho, e) / alpha),
  // g' = 1 - alpha_crush'(p) dp/dalpha where the crush curve is below previous, 1 where min() takes previous.
  // It starts from alpha = previous, where the crush curve is active (g > 0).
  Trial lo = bottom, hi = top, x = top;
  double g_x = g(top), step = hi.alpha - lo.alpha, step_before = step;
  int iterations = 0;
  const int max_iterations = 200;
  const double tolerance = 4 * std::numeric_limits<double>::epsilon();
  while (iterations < max_iterations) {
    const double crush = crush_curve(porosity, x.pressure);
    const double dp_dalpha = (rho * x.matrix.dp_drho - x.pressure) / x.alpha;
    const double slope = crush < previous ? 1 - crush_curve_slope(porosity, x.pressure) * dp_dalpha : 1.0;
    // Converged: the Newton correction is within a few ulps of alpha (g is known to rounding only).
    if (slope > 0 && std::abs(g_x / slope) <= tolerance * x.alpha) break;
    const double newton = x.alpha - g_x / slope;
    step_before = step;
    double alpha;
    if (!(slope > 0) || !(newton > lo.alpha && newton < hi.alpha) || std::abs(2 * g_x) > std::abs(step_before * slope)) {
      step = 0.5 * (hi.alpha - lo.alpha);
      alpha = lo.alpha + step;
    } else {
      step = g_x / slope;
      alpha = newton;
    }
    ++iterations;
    x = trial(m, rho, e, alpha);
    g_x = g(x);
    // Converged: a root hit, or a bracket of a few ulps.
    if (g_x == 0) break;
    (g_x < 0 ? lo : hi) = x;
    if (hi.alpha - lo.alpha <= tolerance * hi.alpha) break;
  }
  return finish(m, porosity, rho, x, iterations);
}

}  // namespace sph
