#include "libsph/impact/updated_lagrangian.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <span>

#include <Eigen/Eigenvalues>
#include <stdexcept>
#include <vector>

#include "libsph/core/numerical_failure.hpp"
#include "libsph/core/parallel.hpp"
#include "libsph/impact/damage.hpp"

namespace sph {

namespace {

// Pressure and sound speed of one state. Tillotson's c^2 may fall below zero in tension; it is kept
// at least (0.1 c0)^2 with c0 = sqrt(A / rho0), so that the time step and the viscosity stay defined.
struct PressureAndSoundSpeed {
  double pressure, sound_speed;
};
PressureAndSoundSpeed evaluate(const ImpactEquationOfState& eos, double rho, double e) {
  if (const auto* gas = std::get_if<IdealGas>(&eos)) {
    const double p = (gas->gamma - 1) * rho * e;
    return {p, std::sqrt(std::max(0.0, gas->gamma * p / rho))};
  }
  if (const auto* linear = std::get_if<LinearPressure>(&eos))
    return {linear->sound_speed * linear->sound_speed * (rho - linear->reference_density), linear->sound_speed};
  const auto& m = std::get<TillotsonParameters>(eos);
  const auto s = tillotson(m, rho, e);
  const double floor = 0.01 * m.A / m.reference_density;
  return {s.pressure, std::sqrt(std::max(s.sound_speed_squared(rho), floor))};
}

}  // namespace

template <int Dim>
UpdatedLagrangianBody<Dim>::UpdatedLagrangianBody(ParticleSet<Dim>& particles, Settings settings)
    : particles_(particles), settings_(std::move(settings)) {
  const std::string body = "updated-Lagrangian body '" + particles.name() + "'";
  if (!(settings_.smoothing_length > 0)) throw std::invalid_argument(body + ": smoothing length must be > 0");
  if (!(settings_.alpha >= 0) || !(settings_.beta >= 0))
    throw std::invalid_argument(body + ": artificial viscosity alpha and beta must be >= 0");
  if (!(settings_.epsilon > 0)) throw std::invalid_argument(body + ": artificial viscosity epsilon must be > 0");
  if (!(settings_.cfl > 0 && settings_.cfl <= 1)) throw std::invalid_argument(body + ": CFL number must be in (0, 1]");
  if (const auto* gas = std::get_if<IdealGas>(&settings_.equation_of_state); gas && !(gas->gamma > 1))
    throw std::invalid_argument(body + ": ideal gas gamma = " + std::to_string(gas->gamma) + " must be > 1");
  if (const auto* m = std::get_if<TillotsonParameters>(&settings_.equation_of_state)) m->check();
  if (const auto* m = std::get_if<PorousTillotson>(&settings_.equation_of_state)) {
    m->matrix.check();
    m->porosity.check();
  }
  if (const auto* l = std::get_if<LinearPressure>(&settings_.equation_of_state); l && !(l->reference_density > 0 && l->sound_speed > 0))
    throw std::invalid_argument(body + ": linear pressure needs a positive reference density and sound speed");
  if (!(settings_.shear_modulus >= 0)) throw std::invalid_argument(body + ": shear modulus must be >= 0");
  if (!(settings_.yield_strength >= 0)) throw std::invalid_argument(body + ": yield strength must be >= 0 (0: elastic)");
  if (settings_.yield_strength > 0 && !(settings_.shear_modulus > 0))
    throw std::invalid_argument(body + ": a yield strength needs strength (shear modulus > 0)");
  if (!(settings_.smoothing_length_factor >= 0))
    throw std::invalid_argument(body + ": smoothing length factor eta must be >= 0 (0: constant h)");
  if (settings_.smoothing_length_factor > 0 && (settings_.periodic.any() || settings_.artificial_stress))
    throw std::invalid_argument(body + ": variable smoothing lengths work without periodic axes and without artificial stress");
  if (settings_.gravity) {
    if (Dim != 3) throw std::invalid_argument(body + ": self-gravity is three-dimensional");
    settings_.gravity->check();
  }
  if (settings_.yield_model == YieldModel::drucker_prager &&
      !(settings_.yield_limit > settings_.yield_strength && settings_.internal_friction >= 0 && settings_.damaged_friction >= 0))
    throw std::invalid_argument(body + ": Drucker-Prager needs a strength limit above the cohesion and friction coefficients >= 0");
  if (settings_.damage) {
    if (!(settings_.shear_modulus > 0)) throw std::invalid_argument(body + ": damage needs strength (shear modulus > 0)");
    if (!(settings_.damage->youngs_modulus > 0)) throw std::invalid_argument(body + ": damage needs Young's modulus > 0");
    settings_.damage->weibull.check();
  }
  if (!(settings_.hardening_modulus >= 0)) throw std::invalid_argument(body + ": hardening modulus must be >= 0");
  if (!(settings_.xsph >= 0 && settings_.xsph <= 1)) throw std::invalid_argument(body + ": XSPH factor must be in [0, 1]");
  if (!(settings_.artificial_stress_factor >= 0) || !(settings_.artificial_stress_exponent > 0))
    throw std::invalid_argument(body + ": artificial stress factor must be >= 0 and its exponent > 0");
  if (settings_.artificial_stress && !(settings_.shear_modulus > 0 && settings_.particle_spacing > 0))
    throw std::invalid_argument(body + ": artificial stress needs strength (shear modulus > 0) and the particle spacing");
  mass_ = particles.template register_field<Real>("mass", 0);
  density_ = particles.template register_field<Real>("density", 0);
  velocity_ = particles.template register_field<Vec<Dim>>("velocity", Vec<Dim>::Zero());
  energy_ = particles.template register_field<Real>("specific_internal_energy", 0);
  pressure_ = particles.template register_field<Real>("pressure", 0);
  sound_speed_ = particles.template register_field<Real>("sound_speed", 0);
  acceleration_ = particles.template register_field<Vec<Dim>>("acceleration", Vec<Dim>::Zero(), false);
  density_rate_ = particles.template register_field<Real>("density_rate", 0, false);
  energy_rate_ = particles.template register_field<Real>("energy_rate", 0, false);
  if (settings_.shear_modulus > 0) {
    deviatoric_stress_ = particles.template register_field<Mat<Dim>>("deviatoric_stress", Mat<Dim>::Zero());
    stress_rate_ = particles.template register_field<Mat<Dim>>("deviatoric_stress_rate", Mat<Dim>::Zero(), false);
  }
  if (settings_.yield_strength > 0) plastic_strain_ = particles.template register_field<Real>("plastic_strain", 0);
  if (settings_.smoothing_length_factor > 0)
    smoothing_length_ = particles.template register_field<Real>("smoothing_length", settings_.smoothing_length);
  if (settings_.xsph > 0) xsph_correction_ = particles.template register_field<Vec<Dim>>("xsph_correction", Vec<Dim>::Zero(), false);
  if (const auto* m = std::get_if<PorousTillotson>(&settings_.equation_of_state))
    distension_ = particles.template register_field<Real>("distension", Real(m->porosity.alpha0));
  if (settings_.damage) {
    damage_ = particles.template register_field<Real>("damage", 0);
    // The rate a step starts from is state, like the other rates (checkpoints).
    damage_rate_ = particles.template register_field<Real>("damage_cube_root_rate", 0, false);
    damage_cap_ = particles.template register_field<Real>("damage_cube_root_cap", 0, false);
    fracture_area_ = particles.template register_field<Real>("fracture_area", 0);
    fracture_area_rate_ = particles.template register_field<Real>("fracture_area_rate", 0, false);
  }
  if (settings_.gravity) {
    potential_ = particles.template register_field<Real>("gravitational_potential", 0);
    gravity_ = std::make_unique<BarnesHutGravity>(*settings_.gravity);
  }
}

template <int Dim>
void UpdatedLagrangianBody<Dim>::hold(std::vector<Index> particles) {
  is_held_.assign(particles_.n_particles(), 0);
  for (const Index i : particles) {
    if (i >= particles_.n_particles()) throw std::invalid_argument("hold: particle " + std::to_string(i) + " does not exist");
    is_held_[i] = 1;
  }
  held_ = std::move(particles);
}

template <int Dim>
void UpdatedLagrangianBody<Dim>::initialise() {
  auto m = particles_.field(mass_);
  const auto rho = particles_.field(density_);
  for (std::size_t i = 0; i < particles_.n_particles(); ++i) m[i] = rho[i] * particles_.volume[i];
  if (settings_.damage) {
    // Flaws by the particles' volumes, from the seeded generator: the same for any thread count.
    std::vector<Real> volume(particles_.n_particles());
    for (std::size_t i = 0; i < volume.size(); ++i) volume[i] = m[i] / rho[i];
    flaws_ = assign_weibull_flaws(volume, settings_.damage->weibull, settings_.damage->seed);
  }
  check_state(0);
  compute_rates();
  initial_time_step_ = stable_time_step();
}

template <int Dim>
void UpdatedLagrangianBody<Dim>::update_equation_of_state() {
  const auto rho = particles_.field(density_);
  const auto e = particles_.field(energy_);
  auto p = particles_.field(pressure_);
  auto c = particles_.field(sound_speed_);
  const auto& eos = settings_.equation_of_state;
  const double shear_wave_term = 4.0 / 3.0 * settings_.shear_modulus;  // c^2 = c_eos^2 + 4 mu / (3 rho)
  std::span<const Real> D;
  if (settings_.damage) D = particles_.field(damage_);
  const auto* porous = std::get_if<PorousTillotson>(&eos);
  std::span<Real> alpha;
  if (porous) alpha = particles_.field(distension_);
  parallel_for(particles_.n_particles(), [&](std::size_t i) {
    PressureAndSoundSpeed s{};
    if (porous) {
      // The distension only falls (compaction is irreversible); the step's prediction may compact a
      // particle a little before the final state does.
      const auto state = porous_tillotson(porous->matrix, porous->porosity, rho[i], e[i], alpha[i]);
      alpha[i] = static_cast<Real>(state.distension);
      s = {state.pressure, std::sqrt(state.sound_speed_squared)};
    } else {
      s = evaluate(eos, rho[i], e[i]);
    }
    // Damage removes the tensile part of the pressure (Benz & Asphaug 1994).
    p[i] = D.empty() ? static_cast<Real>(s.pressure) : damaged_pressure(static_cast<Real>(s.pressure), D[i]);
    c[i] = static_cast<Real>(std::sqrt(s.sound_speed * s.sound_speed + shear_wave_term / rho[i]));
  });
}

template <int Dim>
void UpdatedLagrangianBody<Dim>::compute_rates() {
  update_neighbours();
  update_density_and_pressure();
  compute_stress_rates();
  compute_forces();
  add_self_gravity();
}

template <int Dim>
void UpdatedLagrangianBody<Dim>::update_neighbours() {
  const Real h = settings_.smoothing_length;
  const std::size_t n = particles_.n_particles();
  const auto m = particles_.field(mass_);
  const auto rho = particles_.field(density_);
  const bool variable_h = settings_.smoothing_length_factor > 0;
  std::span<Real> h_of;
  if (variable_h) {
    // h_i = eta (m_i / rho_i)^(1/Dim), following the density (Benz 1990); pairs interact with
    // h_ij = (h_i + h_j) / 2 (Hernquist & Katz 1989), found by the k-d tree.
    h_of = particles_.field(smoothing_length_);
    const Real eta = settings_.smoothing_length_factor;
    parallel_for(n, [&](std::size_t i) { h_of[i] = eta * std::pow(m[i] / rho[i], Real(1) / Real(Dim)); });
    rebuild_inner_relation_variable_h<Dim>(relation_, particles_.position, h_of, settings_.kernel, tree_);
  } else if (settings_.periodic.any()) {
    rebuild_inner_relation<Dim>(relation_, particles_.position, settings_.kernel, h, settings_.periodic);
  } else {
    rebuild_inner_relation<Dim>(relation_, particles_.position, settings_.kernel, h);
  }
}

template <int Dim>
void UpdatedLagrangianBody<Dim>::update_density_and_pressure() {
  const Real h = settings_.smoothing_length;
  const std::size_t n = particles_.n_particles();
  const auto m = particles_.field(mass_);
  const bool variable_h = settings_.smoothing_length_factor > 0;
  std::span<const Real> h_of;
  if (variable_h) h_of = particles_.field(smoothing_length_);
  if (settings_.density_summation) {
    // rho_i = m_i W(0, h_i) + sum_j m_j W(r_ij, h_ij), at the h set from the previous density.
    auto rho_sum = particles_.field(density_);
    const auto& R = relation_;
    parallel_for(n, [&](std::size_t i) {
      const Real h_i = variable_h ? h_of[i] : h;
      Real sum = m[i] * std::visit([&](const auto& kernel) { return kernel.value(Real(0), h_i); }, settings_.kernel);
      for (const auto [k, j] : R.row(i)) sum += m[j] * R.kernel_value[k];
      rho_sum[i] = sum;
    });
  }
  update_equation_of_state();
}

template <int Dim>
void UpdatedLagrangianBody<Dim>::compute_stress_rates() {
  const std::size_t n = particles_.n_particles();
  const auto m = particles_.field(mass_);
  const auto rho = particles_.field(density_);
  const auto v = particles_.field(velocity_);
  const auto p = particles_.field(pressure_);
  const auto c = particles_.field(sound_speed_);
  const auto& R = relation_;
  const bool strength = settings_.shear_modulus > 0;
  const bool artificial_stress = settings_.artificial_stress;
  std::span<const Real> D;
  if (settings_.damage) D = particles_.field(damage_);
  const Real mu = settings_.shear_modulus, I3 = Real(1) / Real(3);
  // 1. With strength: each particle's corrected velocity gradient, the Jaumann stress rate, the
  // stress power S : eps' / rho, and the artificial stress R_i.
  std::span<Mat<Dim>> S, dS;
  if (strength) {
    S = particles_.field(deviatoric_stress_);
    dS = particles_.field(stress_rate_);
    tension_.resize(artificial_stress ? n : 0);
    if (!D.empty()) stress_.resize(n);
    parallel_for(n, [&](std::size_t i) {
      Mat<Dim> B = Mat<Dim>::Zero(), G = Mat<Dim>::Zero();
      for (const auto [k, j] : R.row(i)) {
        const Real volume = m[j] / rho[j];
        const Vec<Dim> grad = R.kernel_derivative[k] * R.unit_vector[k];
        B -= volume * R.distance[k] * R.unit_vector[k] * grad.transpose();  // x_j - x_i = -r e_ij
        G += volume * (v[j] - v[i]) * grad.transpose();
      }
      const Real det = B.determinant();
      const Mat<Dim> grad_v = std::abs(det) > Real(1e-6) ? Mat<Dim>(G * B.inverse()) : G;
      const Mat<Dim> strain_rate = Real(0.5) * (grad_v + grad_v.transpose());
      const Mat<Dim> spin = Real(0.5) * (grad_v - grad_v.transpose());
      dS[i] = 2 * mu * (strain_rate - I3 * strain_rate.trace() * Mat<Dim>::Identity()) + S[i] * spin.transpose() + spin * S[i];
      const Real intact = D.empty() ? Real(1) : 1 - D[i];  // the deviator carried: (1 - D) S
      if (!D.empty()) stress_[i] = intact * S[i] - p[i] * Mat<Dim>::Identity();
      if (artificial_stress) {
        const Mat<Dim> sigma = intact * S[i] - p[i] * Mat<Dim>::Identity();
        Eigen::SelfAdjointEigenSolver<Mat<Dim>> eigen;
        eigen.computeDirect(sigma);  // closed form for 2x2 and 3x3
        Vec<Dim> r = Vec<Dim>::Zero();
        for (int d = 0; d < Dim; ++d)
          if (eigen.eigenvalues()[d] > 0) r[d] = -settings_.artificial_stress_factor * eigen.eigenvalues()[d] / (rho[i] * rho[i]);
        tension_[i] = eigen.eigenvectors() * r.asDiagonal() * eigen.eigenvectors().transpose();
      }
    });
  }
  if (settings_.damage) {
    // Grady-Kipp: each particle's rate of D^(1/3) from its largest principal stress
    // (libsph/impact/damage.hpp), the crack-growth radius that of the particle's volume.
    radius_.resize(n);
    parallel_for(n, [&](std::size_t i) { radius_[i] = equivalent_radius<Dim>(m[i] / rho[i]); });
    grady_kipp_damage_rate<Dim>(flaws_, stress_, D, settings_.damage->youngs_modulus, c, radius_,
                                particles_.field(damage_rate_), particles_.field(damage_cap_));
    // The fracture area per unit volume grows with the strain until the particle is fully damaged
    // (Grady & Kipp 1980; the rate in libsph/impact/damage.hpp).
    auto area_rate = particles_.field(fracture_area_rate_);
    const auto& weibull = settings_.damage->weibull;
    const Real E = settings_.damage->youngs_modulus;
    parallel_for(n, [&](std::size_t i) {
      const Real intact = 1 - D[i];
      const Real strain = intact > 0 ? largest_principal_stress<Dim>(stress_[i]) / (intact * E) : Real(0);
      area_rate[i] = intact > 0 ? Real(fracture_area_rate(weibull, crack_speed_fraction * c[i], strain, D[i])) : Real(0);
    });
  }
}

template <int Dim>
void UpdatedLagrangianBody<Dim>::compute_forces() {
  const Real h = settings_.smoothing_length;
  const std::size_t n = particles_.n_particles();
  const auto m = particles_.field(mass_);
  const auto rho = particles_.field(density_);
  const bool variable_h = settings_.smoothing_length_factor > 0;
  std::span<const Real> h_of;
  if (variable_h) h_of = particles_.field(smoothing_length_);
  const auto v = particles_.field(velocity_);
  const auto p = particles_.field(pressure_);
  const auto c = particles_.field(sound_speed_);
  auto a = particles_.field(acceleration_);
  auto drho = particles_.field(density_rate_);
  auto de = particles_.field(energy_rate_);
  const auto& R = relation_;
  const bool strength = settings_.shear_modulus > 0;
  const bool artificial_stress = settings_.artificial_stress;
  std::span<const Real> D;
  if (settings_.damage) D = particles_.field(damage_);
  std::span<const Mat<Dim>> S;
  if (strength) S = particles_.field(deviatoric_stress_);
  // 2. The pair sums. Gather over each particle's own row: every sum is in a fixed order, whatever
  // the thread count.
  const Real alpha = settings_.alpha, beta = settings_.beta, epsilon = settings_.epsilon;
  const Real w_dx = artificial_stress ? std::visit([&](const auto& kernel) { return kernel.value(settings_.particle_spacing, h); },
                                                   settings_.kernel)
                                      : Real(1);
  const Real exponent = settings_.artificial_stress_exponent;
  const bool xsph = settings_.xsph > 0;
  std::span<Vec<Dim>> xsph_correction;
  if (xsph) xsph_correction = particles_.field(xsph_correction_);
  parallel_for(n, [&](std::size_t i) {
    const Real pi_term = p[i] / (rho[i] * rho[i]);
    Mat<Dim> s_i = Mat<Dim>::Zero();
    if (strength) s_i = (D.empty() ? Real(1) : 1 - D[i]) * S[i] / (rho[i] * rho[i]);
    Vec<Dim> acc = Vec<Dim>::Zero(), smoothed = Vec<Dim>::Zero();
    Real rate_rho = 0, rate_e = 0;
    for (const auto [k, j] : R.row(i)) {
      const Vec<Dim> grad = R.kernel_derivative[k] * R.unit_vector[k];
      const Vec<Dim> v_ij = v[i] - v[j];
      const Real vr = v_ij.dot(R.unit_vector[k]) * R.distance[k];  // v_ij . x_ij
      Real viscosity = 0;
      if (vr < 0) {
        const Real h_ij = variable_h ? Real(0.5) * (h_of[i] + h_of[j]) : h;
        const Real phi = h_ij * vr / (R.distance[k] * R.distance[k] + epsilon * h_ij * h_ij);
        viscosity = (-alpha * Real(0.5) * (c[i] + c[j]) * phi + beta * phi * phi) / (Real(0.5) * (rho[i] + rho[j]));
      }
      const Real term = pi_term + p[j] / (rho[j] * rho[j]) + viscosity;
      const Real v_grad = v_ij.dot(grad);
      acc -= m[j] * term * grad;
      if (strength) {
        Mat<Dim> pair = s_i + (D.empty() ? Real(1) : 1 - D[j]) * S[j] / (rho[j] * rho[j]);
        Real f_n = 0;  // (W(r_ij) / W(dx))^n, n = 4 by default (squared twice: std::pow would cost more than the pair)
        if (artificial_stress) {
          const Real f = R.kernel_value[k] / w_dx;
          f_n = exponent == 4 ? (f * f) * (f * f) : std::pow(f, exponent);
          pair += (tension_[i] + tension_[j]) * f_n;
        }
        acc += m[j] * (pair * grad);
        // The work of particle i's own deviator, and half the artificial stress's.
        rate_e -= m[j] * v_ij.dot(s_i * grad);
        if (artificial_stress)
          rate_e -= Real(0.5) * m[j] * v_ij.dot((tension_[i] + tension_[j]) * grad) * f_n;
      }
      // The work of particle i's own pressure, and half the viscous heating of the pair.
      rate_e += m[j] * (pi_term + Real(0.5) * viscosity) * v_grad;
      rate_rho += m[j] / rho[j] * v_grad;
      if (xsph) smoothed -= m[j] / (Real(0.5) * (rho[i] + rho[j])) * R.kernel_value[k] * v_ij;
    }
    if (xsph) xsph_correction[i] = settings_.xsph * smoothed;

    // A held particle keeps its density, energy and stress rates (so a clamp carries load and
    // moment); only its motion is fixed.
    a[i] = !is_held_.empty() && is_held_[i] ? Vec<Dim>::Zero() : acc;
    de[i] = rate_e;
    drho[i] = rho[i] * rate_rho;
  });
}

template <int Dim>
void UpdatedLagrangianBody<Dim>::add_self_gravity() {
  if (gravity_) {
    const Real h = settings_.smoothing_length;
    const std::size_t n = particles_.n_particles();
    const auto m = particles_.field(mass_);
    const bool variable_h = settings_.smoothing_length_factor > 0;
    std::span<const Real> h_of;
    if (variable_h) h_of = particles_.field(smoothing_length_);
    auto a = particles_.field(acceleration_);
    // Self-gravity (libsph/impact/gravity.hpp), softened with each particle's h.
    if constexpr (Dim == 3) {
      gravity_h_.resize(n);
      const Real fixed = settings_.gravitational_softening;
      parallel_for(n, [&](std::size_t i) { gravity_h_[i] = fixed > 0 ? fixed : variable_h ? h_of[i] : h; });
      gravity_acceleration_.resize(n);
      gravity_->compute(particles_.position, m, gravity_h_, gravity_acceleration_, particles_.field(potential_));
      parallel_for(n, [&](std::size_t i) { a[i] += gravity_acceleration_[i]; });
    }
  }
}

template <int Dim>
Real UpdatedLagrangianBody<Dim>::stable_time_step() const {
  const auto v = particles_.field(velocity_);
  const auto c = particles_.field(sound_speed_);
  if (settings_.smoothing_length_factor > 0) {
    // dt = CFL min_i h_i / (c_i + |v_i|), and with gravity also CFL sqrt(h_i / |a_i|).
    const auto h = particles_.field(smoothing_length_);
    const auto acc = particles_.field(acceleration_);
    const bool gravity = gravity_ != nullptr;
    const Real step = parallel_reduce(
        particles_.n_particles(), std::numeric_limits<Real>::infinity(),
        [&](std::size_t i) {
          Real rate = (c[i] + v[i].norm()) / h[i];
          if (gravity) rate = std::max(rate, std::sqrt(acc[i].norm() / h[i]));
          return rate > 0 ? settings_.cfl / rate : std::numeric_limits<Real>::infinity();
        },
        [](Real x, Real y) { return std::min(x, y); });
    return step;
  }
  const Real fastest = parallel_max(particles_.n_particles(), Real(0), [&](std::size_t i) { return c[i] + v[i].norm(); });
  return fastest > 0 ? settings_.cfl * settings_.smoothing_length / fastest : std::numeric_limits<Real>::infinity();
}

template <int Dim>
Mat<Dim> UpdatedLagrangianBody<Dim>::yield(const Mat<Dim>& S, Real plastic_strain, Real pressure, Real damage,
                                           Real& plastic_increment) const {
  // The deviator is scaled back radially onto the yield surface (Wilkins 1964), f = min(Y / sigma_eq, 1)
  // with sigma_eq = sqrt(3/2 S:S); in 2D (plane strain) S_zz = -(S_xx + S_yy) enters S:S.
  //   von Mises with linear isotropic hardening: Y = Y0 + H eps_p, and the equivalent plastic strain
  //     grows by (sigma_eq - Y) / (3 mu + H), which puts the scaled deviator on the hardened surface
  //     (Simo & Hughes 1998, Computational Inelasticity, box 3.2);
  //   Drucker-Prager (Collins, Melosh & Ivanov 2004, Meteorit. Planet. Sci. 39:217): intact
  //     Y_i = Y0 + mu_i p / (1 + mu_i p / (Y_m - Y0)), damaged Y_d = mu_d p, Y = (1 - D) Y_i + D Y_d,
  //     none below zero (no strength in tension beyond the cohesion's share).
  plastic_increment = 0;
  const Real Y0 = settings_.yield_strength;
  if (!(Y0 > 0)) return S;
  Real J = S.squaredNorm();
  if constexpr (Dim == 2) J += (S(0, 0) + S(1, 1)) * (S(0, 0) + S(1, 1));
  const Real equivalent = std::sqrt(Real(1.5) * J);
  if (settings_.yield_model == YieldModel::drucker_prager) {
    const Real mu_i = settings_.internal_friction, mu_d = settings_.damaged_friction;
    const Real intact = Y0 + mu_i * pressure / (1 + mu_i * pressure / (settings_.yield_limit - Y0));
    const Real Y = std::max(Real(0), (1 - damage) * std::max(Real(0), intact) + damage * std::max(Real(0), mu_d * pressure));
    if (!(equivalent > Y)) return S;
    plastic_increment = (equivalent - Y) / (3 * settings_.shear_modulus);
    return S * (Y / equivalent);
  }
  const Real Y = Y0 + settings_.hardening_modulus * plastic_strain;
  if (!(equivalent > Y)) return S;
  plastic_increment = (equivalent - Y) / (3 * settings_.shear_modulus + settings_.hardening_modulus);
  return S * ((Y + settings_.hardening_modulus * plastic_increment) / equivalent);
}

template <int Dim>
Stage UpdatedLagrangianBody<Dim>::stage(std::string name) {
  Stage step{std::move(name), [this] { return stable_time_step(); }, {}};
  step.then("kick and drift", [this](Real t, Real dt) { kick_and_drift(t, dt); })
      .then("neighbours", [this](Real, Real) { update_neighbours(); })
      .then("density and pressure", [this](Real, Real) { update_density_and_pressure(); })
      .then("stress rates", [this](Real, Real) { compute_stress_rates(); })
      .then("forces", [this](Real, Real) { compute_forces(); })
      .then("self-gravity", [this](Real, Real) { add_self_gravity(); })
      .then("second kick", [this](Real t, Real dt) { second_kick(t, dt); });
  return step;
}

template <int Dim>
void UpdatedLagrangianBody<Dim>::advance(Real time, Real dt) {
  kick_and_drift(time, dt);
  compute_rates();
  second_kick(time, dt);
}

template <int Dim>
typename UpdatedLagrangianBody<Dim>::KickViews UpdatedLagrangianBody<Dim>::kick_views(Real half) {
  KickViews k{particles_.field(velocity_), particles_.field(density_), particles_.field(energy_), particles_.field(acceleration_),
              particles_.field(density_rate_), particles_.field(energy_rate_), particles_.field(pressure_),
              {}, {}, {}, {}, settings_.shear_modulus > 0, settings_.yield_strength > 0, settings_.density_summation};
  if (k.strength) {
    k.S = particles_.field(deviatoric_stress_);
    k.dS = particles_.field(stress_rate_);
  }
  if (k.plastic) k.eps_p = particles_.field(plastic_strain_);
  if (settings_.damage) {
    k.D = particles_.field(damage_);
    advance_damage(k.D, particles_.field(damage_rate_), particles_.field(damage_cap_), half);
    kick_fracture_area(half);
  }
  return k;
}

template <int Dim>
void UpdatedLagrangianBody<Dim>::kick_and_drift(Real time, Real dt) {
  // Kick to the half step and drift; the rates are then evaluated at the drifted positions with the
  // state predicted to the full step by the old rates.
  const std::size_t n = particles_.n_particles();
  v_half_.resize(n);
  rho_half_.resize(n);
  e_half_.resize(n);
  if (settings_.shear_modulus > 0) s_half_.resize(n);
  if (settings_.yield_strength > 0) eps_p_half_.resize(n);
  const Real half = Real(0.5) * dt;
  auto [v, rho, e, a, drho, de, p, S, dS, eps_p, D, strength, plastic, summation] = kick_views(half);  // first half kick of D^(1/3)
  auto& x = particles_.position;
  auto& v_half = v_half_;
  auto& rho_half = rho_half_;
  auto& e_half = e_half_;
  const bool xsph = settings_.xsph > 0;
  std::span<const Vec<Dim>> xsph_correction;
  if (xsph) xsph_correction = particles_.field(xsph_correction_);
  const auto& box = settings_.periodic;
  parallel_for(n, [&](std::size_t i) {
    v_half[i] = v[i] + half * a[i];
    rho_half[i] = summation ? rho[i] : rho[i] + half * drho[i];
    e_half[i] = e[i] + half * de[i];
    x[i] += dt * (xsph ? Vec<Dim>(v_half[i] + xsph_correction[i]) : v_half[i]);
    if (box.any()) x[i] = box.wrap(x[i]);
    v[i] = v_half[i] + half * a[i];
    if (!summation) rho[i] = rho_half[i] + half * drho[i];
    e[i] = e_half[i] + half * de[i];
    if (strength) {
      // The plastic strain accumulates in the two kicks; the prediction between them only borrows it.
      Real yielded = 0;
      s_half_[i] = yield(S[i] + half * dS[i], plastic ? eps_p[i] : Real(0), p[i], D.empty() ? Real(0) : D[i], yielded);
      if (plastic) eps_p[i] = eps_p_half_[i] = eps_p[i] + yielded;
      S[i] = yield(s_half_[i] + half * dS[i], plastic ? eps_p[i] : Real(0), p[i], D.empty() ? Real(0) : D[i], yielded);
    }
  });
  check_state(time + dt);
  {
    // A particle that crossed its whole kernel support in one step was stepped past stability.
    const bool variable = settings_.smoothing_length_factor > 0;
    std::span<const Real> h_of;
    if (variable) h_of = particles_.field(smoothing_length_);
    const Real support = std::visit([](const auto& kernel) { return kernel.support_radius(Real(1)); }, settings_.kernel);
    const std::size_t jumped = first_index_where(n, [&](std::size_t i) {
      return dt * v_half[i].norm() > support * (variable ? h_of[i] : settings_.smoothing_length);
    });
    if (jumped < n) {
      char problem[160];
      std::snprintf(problem, sizeof problem, "%.3g in one step of %.3g is beyond its kernel support (the step is unstable)",
                    double(dt * v_half[jumped].norm()), double(dt));
      throw NumericalFailure(particles_.name(), jumped, NumericalFailure::format_position(x[jumped]), time + dt, "displacement", problem);
    }
  }
}

template <int Dim>
void UpdatedLagrangianBody<Dim>::second_kick(Real time, Real dt) {
  const std::size_t n = particles_.n_particles();
  const Real half = Real(0.5) * dt;
  auto [v, rho, e, a, drho, de, p, S, dS, eps_p, D, strength, plastic, summation] = kick_views(half);  // second half kick of D^(1/3)
  const auto& x = particles_.position;
  const auto& v_half = v_half_;
  const auto& rho_half = rho_half_;
  const auto& e_half = e_half_;
  // Second kick with the new rates.
  parallel_for(n, [&](std::size_t i) {
    v[i] = v_half[i] + half * a[i];
    if (!summation) rho[i] = rho_half[i] + half * drho[i];
    e[i] = e_half[i] + half * de[i];
    if (strength) {
      Real yielded = 0;
      S[i] = yield(s_half_[i] + half * dS[i], plastic ? eps_p_half_[i] : Real(0), p[i], D.empty() ? Real(0) : D[i], yielded);
      if (plastic) eps_p[i] = eps_p_half_[i] + yielded;
    }
  });
  check_state(time + dt);
  update_equation_of_state();
  ++steps_;
  // An exploding state shrinks the step without bound: stop where it happens.
  const Real next = stable_time_step();
  if (next < Real(1e-6) * initial_time_step_) {
    const auto c = particles_.field(sound_speed_);
    std::size_t fastest = 0;
    for (std::size_t i = 1; i < n; ++i)
      if (c[i] + v[i].norm() > c[fastest] + v[fastest].norm()) fastest = i;
    char problem[200];
    std::snprintf(problem, sizeof problem, "%.3g is below 1e-6 of the initial %.3g (sound speed %.3g, speed %.3g)", double(next),
                  double(initial_time_step_), double(c[fastest]), double(v[fastest].norm()));
    throw NumericalFailure(particles_.name(), fastest, NumericalFailure::format_position(x[fastest]), time + dt, "time step", problem);
  }
}

template <int Dim>
void UpdatedLagrangianBody<Dim>::kick_fracture_area(Real dt) {
  auto area = particles_.field(fracture_area_);
  const auto rate = particles_.field(fracture_area_rate_);
  parallel_for(particles_.n_particles(), [&](std::size_t i) { area[i] += dt * rate[i]; });
}

template <int Dim>
void UpdatedLagrangianBody<Dim>::check_state(Real time) const {
  const auto rho = particles_.field(density_);
  const auto v = particles_.field(velocity_);
  const auto e = particles_.field(energy_);
  const bool gas = std::holds_alternative<IdealGas>(settings_.equation_of_state);
  const auto& x = particles_.position;
  const std::size_t bad = first_index_where(particles_.n_particles(), [&](std::size_t i) {
    return !(rho[i] > 0) || !v[i].allFinite() || !x[i].allFinite() || !std::isfinite(e[i]) || (gas && !(e[i] >= 0));
  });
  if (bad == particles_.n_particles()) return;
  const std::string where = NumericalFailure::format_position(x[bad]);
  if (!v[bad].allFinite() || !x[bad].allFinite())
    throw NumericalFailure(particles_.name(), bad, where, time, "velocity", "is not finite");
  if (!(rho[bad] > 0))
    throw NumericalFailure(particles_.name(), bad, where, time, "density", std::to_string(rho[bad]) + " is not positive");
  throw NumericalFailure(particles_.name(), bad, where, time, "specific internal energy",
                         std::to_string(e[bad]) + (gas ? " is negative (an ideal gas needs e >= 0)" : " is not finite"));
}

template <int Dim>
typename UpdatedLagrangianBody<Dim>::Energies UpdatedLagrangianBody<Dim>::energies() const {
  const auto m = particles_.field(mass_);
  const auto v = particles_.field(velocity_);
  const auto e = particles_.field(energy_);
  Energies out;
  out.kinetic = parallel_sum(particles_.n_particles(), 0.0, [&](std::size_t i) { return 0.5 * m[i] * v[i].squaredNorm(); });
  out.internal = parallel_sum(particles_.n_particles(), 0.0, [&](std::size_t i) { return double(m[i]) * e[i]; });
  if (gravity_) out.potential = gravitational_energy(m, particles_.field(potential_));
  return out;
}

template class UpdatedLagrangianBody<2>;
template class UpdatedLagrangianBody<3>;

}  // namespace sph
