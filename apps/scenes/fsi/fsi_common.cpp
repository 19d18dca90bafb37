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
  body->solid = std::make_unique<sph::ElasticSolid<2>>(body->particles, body->relation, settings);
  if (spec.clamped) {
    std::vector<sph::Index> clamped;
    for (std::size_t i = 0; i < body->particles.n_particles(); ++i)
      if (spec.clamped(body->particles.position[i])) clamped.push_back(static_cast<sph::Index>(i));
    body->solid->clamp(std::move(clamped));
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
  return o;
}

}  // namespace cardiosph
