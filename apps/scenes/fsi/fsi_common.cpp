#include "apps/scenes/fsi/fsi_common.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "libsph/io/parameters.hpp"

namespace cardiosph {

void declare_fsi_solid_numerics(sph::Parameters& p, FsiSolidNumerics& n) {
  p.add_choice("solid_kernel", n.kernel, std::vector<std::string>(std::begin(sph::kernel_names), std::end(sph::kernel_names)),
               "the solid's smoothing kernel (the fluid-solid contact uses the fluid's)");
  p.add("solid_smoothing_length_ratio", n.smoothing_length_ratio, "-",
        "the solid's smoothing length over the solid spacing", sph::Range::closed(1.0, 2.5));
  p.add("hourglass_coefficient", n.hourglass_coefficient, "-",
        "alpha of the solid's hourglass penalty force (Ganzenmueller 2015); 0 turns it off", sph::Range::non_negative());
  p.add("solid_acoustic_cfl", n.acoustic_cfl, "-", "solid time step as a fraction of its acoustic limit",
        {0, 1, true, false});
  p.add("sub_cycling", n.sub_cycling,
        "multi time stepping: the solid sub-cycles in each fluid acoustic step (false: the solid's step bounds the fluid's)");
  p.add("acceleration_relaxation", n.acceleration_relaxation, "-",
        "theta: the weight of the newest step-mean solid acceleration in the one the fluid's wall pressure uses (1: no relaxation)",
        {0, 1, true, false});
  p.add("solid_mass_scaling", n.mass_scaling, "-",
        "factor on the solid's inertia for quasi-static scenes (its weight stays physical): the solid's step grows by its "
        "square root; 1 = physical inertia",
        sph::Range::closed(1, 1e6));
  p.add_enum("hourglass_control", n.hourglass_control, sph::hourglass_control_names(),
             "the solid's zero-energy-mode control: penalty (Ganzenmueller 2015) or energy (conservative)");
  p.add_enum("deformation_gradient", n.deformation_gradient, sph::deformation_gradient_names(),
             "the solid's reconstruction of F: corrected (exact for linear motion) or quadratic (weighted least squares, "
             "exact for quadratic motion, also at free surfaces)");
  p.add_enum("quadrature", n.quadrature, sph::quadrature_names(),
             "integration of each solid particle's energy: nodal or gauss (needs deformation_gradient = quadratic)");
  p.add_choice("clamp", n.clamp, {"fixed", "reflection"},
               "hold of the solid's clamped particles: fixed (at rest) or reflection (odd reflection of the displacement "
               "across the flat clamp face; where the scene's clamp has flat faces on half-spacings)");
}

void FsiBody::add_to(sph::RunHarness& run, sph::Stage& fluid_step, sph::Real output_interval) {
  run.add_body(particles, output_interval, [this](double) { solid->update_output_fields(); });
  coupling->fill(fluid_step, run.timers());
  run.keep("fsi/" + particles.name(), *this);
}

std::unique_ptr<FsiBody> make_fsi_body(sph::ParticleSet<2> particles, const std::vector<sph::Vec<2>>& normals,
                                       const FsiBodySpec& spec,
                                       const FsiSolidNumerics& numerics, sph::WeaklyCompressibleFluid<2>& fluid,
                                       const std::string& thickness_parameter) {
  auto body = std::make_unique<FsiBody>();
  body->particles = std::move(particles);
  const auto kernel = sph::make_kernel<2>(numerics.kernel);
  const auto h = static_cast<sph::Real>(numerics.smoothing_length_ratio * spec.spacing);
  body->relation = sph::build_inner_relation<2>(body->particles.position, kernel, h);
  sph::ElasticSolid<2>::Settings settings;
  sph::Real lambda = 0, mu = 0;
  sph::lame_constants(static_cast<sph::Real>(spec.young_modulus), static_cast<sph::Real>(spec.poisson_ratio), lambda, mu);
  settings.material = sph::SaintVenantKirchhoff<2>{lambda, mu};
  settings.density = static_cast<sph::Real>(spec.density);
  settings.damping_rate = static_cast<sph::Real>(spec.damping_rate);
  settings.body_force = spec.gravity;
  settings.numerics.hourglass_coefficient = static_cast<sph::Real>(numerics.hourglass_coefficient);
  settings.numerics.cfl = static_cast<sph::Real>(numerics.acoustic_cfl);
  settings.numerics.mass_scaling = static_cast<sph::Real>(numerics.mass_scaling);
  settings.numerics.hourglass_control = numerics.hourglass_control;
  settings.numerics.deformation_gradient = numerics.deformation_gradient;
  settings.numerics.quadrature = numerics.quadrature;
  try {
    body->solid = std::make_unique<sph::ElasticSolid<2>>(body->particles, body->relation, settings);
  } catch (const std::invalid_argument& e) {
    throw sph::ParameterError(e.what());
  }
  if (numerics.clamp == "reflection" && spec.clamp_faces.empty())
    throw sph::ParameterError("parameter 'clamp' = reflection: the clamp of body '" + body->particles.name() +
                              "' has no flat face to reflect across; use 'fixed'");
  if (spec.clamped) {
    std::vector<sph::Index> clamped;
    std::vector<std::vector<sph::Index>> behind(spec.clamp_faces.size());
    for (std::size_t i = 0; i < body->particles.n_particles(); ++i) {
      const auto& x = body->particles.position[i];
      if (!spec.clamped(x)) continue;
      if (numerics.clamp == "fixed") {
        clamped.push_back(static_cast<sph::Index>(i));
        continue;
      }
      std::size_t f = 0;
      while (f < spec.clamp_faces.size() && (x - spec.clamp_faces[f].point).dot(spec.clamp_faces[f].normal) >= 0) ++f;
      if (f == spec.clamp_faces.size())
        throw std::logic_error("clamped particle of body '" + body->particles.name() + "' behind none of its clamp faces");
      behind[f].push_back(static_cast<sph::Index>(i));
    }
    if (!clamped.empty()) body->solid->clamp(std::move(clamped));
    try {
      for (std::size_t f = 0; f < behind.size(); ++f)
        if (!behind[f].empty())
          body->solid->clamp_by_reflection(std::move(behind[f]), spec.clamp_faces[f].point, spec.clamp_faces[f].normal);
    } catch (const std::invalid_argument& e) {
      throw sph::ParameterError(std::string("parameter 'clamp' = reflection: ") + e.what());
    }
  }
  try {
    body->coupling = std::make_unique<sph::SolidFluidCoupling<2>>(
        fluid, *body->solid, normals,
        sph::SolidFluidCoupling<2>::Settings{static_cast<sph::Real>(spec.spacing), numerics.sub_cycling,
                                             static_cast<sph::Real>(numerics.acceleration_relaxation)});
  } catch (const std::invalid_argument& e) {
    throw sph::ParameterError("parameter '" + thickness_parameter + "': " + e.what());
  }
  return body;
}

Oscillation analyse_oscillation(const std::vector<double>& t, const std::vector<double>& y, double t_start) {
  Oscillation o;
  std::vector<double> ts, ys;
  double lo = 1e300, hi = -1e300, sum = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    if (t[k] < t_start) continue;
    ts.push_back(t[k]);
    ys.push_back(y[k]);
    lo = std::min(lo, y[k]);
    hi = std::max(hi, y[k]);
    sum += y[k];
  }
  if (ts.size() < 8) return o;
  o.mean = 0.5 * (lo + hi);
  o.amplitude = 0.5 * (hi - lo);
  const double mean = sum / double(ts.size());
  const double span = ts.back() - ts.front();
  // The dominant frequency: the peak of |sum_k (y_k - mean) exp(-2 pi i f t_k) dt_k| over f from two
  // cycles per window to a quarter of the sampling rate, on a grid of 1/8 of the resolution 1/span.
  auto power = [&](double f) {
    double re = 0, im = 0;
    for (std::size_t k = 1; k < ts.size(); ++k) {
      const double dt = ts[k] - ts[k - 1], phase = 2 * M_PI * f * ts[k];
      re += (ys[k] - mean) * std::cos(phase) * dt;
      im -= (ys[k] - mean) * std::sin(phase) * dt;
    }
    return std::hypot(re, im);
  };
  const double f_max = 0.25 * double(ts.size() - 1) / span, df = 1 / (8 * span);
  double best = 0, best_f = 0;
  for (double f = 2 / span; f <= f_max; f += df) {
    const double q = power(f);
    if (q > best) {
      best = q;
      best_f = f;
    }
  }
  o.frequency = best_f;
  o.cycles = static_cast<std::size_t>(best_f * span);
  o.harmonic_amplitude = 2 * best / span;
  if (o.cycles > 0) {
    const double period = 1 / best_f;
    double means = 0, halves = 0;
    for (std::size_t c = 0; c < o.cycles; ++c) {
      const double to = ts.back() - double(c) * period, from = to - period;
      double period_lo = 1e300, period_hi = -1e300;
      for (std::size_t k = 0; k < ts.size(); ++k)
        if (ts[k] > from && ts[k] <= to) {
          period_lo = std::min(period_lo, ys[k]);
          period_hi = std::max(period_hi, ys[k]);
        }
      means += 0.5 * (period_hi + period_lo);
      halves += 0.5 * (period_hi - period_lo);
    }
    o.period_mean = means / double(o.cycles);
    o.period_amplitude = halves / double(o.cycles);
  }
  return o;
}

}  // namespace cardiosph
