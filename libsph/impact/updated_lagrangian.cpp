#include "libsph/impact/updated_lagrangian.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <vector>

#include "libsph/core/numerical_failure.hpp"
#include "libsph/core/parallel.hpp"

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
  mass_ = particles.template register_field<Real>("mass", 0);
  density_ = particles.template register_field<Real>("density", 0);
  velocity_ = particles.template register_field<Vec<Dim>>("velocity", Vec<Dim>::Zero());
  energy_ = particles.template register_field<Real>("specific_internal_energy", 0);
  pressure_ = particles.template register_field<Real>("pressure", 0);
  sound_speed_ = particles.template register_field<Real>("sound_speed", 0);
  acceleration_ = particles.template register_field<Vec<Dim>>("acceleration", Vec<Dim>::Zero(), false);
  density_rate_ = particles.template register_field<Real>("density_rate", 0, false);
  energy_rate_ = particles.template register_field<Real>("energy_rate", 0, false);
}

template <int Dim>
void UpdatedLagrangianBody<Dim>::initialise() {
  auto m = particles_.field(mass_);
  const auto rho = particles_.field(density_);
  for (std::size_t i = 0; i < particles_.n_particles(); ++i) m[i] = rho[i] * particles_.volume[i];
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
  parallel_for(particles_.n_particles(), [&](std::size_t i) {
    const auto s = evaluate(eos, rho[i], e[i]);
    p[i] = static_cast<Real>(s.pressure);
    c[i] = static_cast<Real>(s.sound_speed);
  });
}

template <int Dim>
void UpdatedLagrangianBody<Dim>::compute_rates() {
  const Real h = settings_.smoothing_length;
  if (settings_.periodic.any())
    rebuild_inner_relation<Dim>(relation_, particles_.position, settings_.kernel, h, settings_.periodic);
  else
    rebuild_inner_relation<Dim>(relation_, particles_.position, settings_.kernel, h);
  update_equation_of_state();
  const auto m = particles_.field(mass_);
  const auto rho = particles_.field(density_);
  const auto v = particles_.field(velocity_);
  const auto p = particles_.field(pressure_);
  const auto c = particles_.field(sound_speed_);
  auto a = particles_.field(acceleration_);
  auto drho = particles_.field(density_rate_);
  auto de = particles_.field(energy_rate_);
  const Real alpha = settings_.alpha, beta = settings_.beta, eps_h2 = settings_.epsilon * h * h;
  const auto& R = relation_;
  // Gather over each particle's own row: every sum is in a fixed order, whatever the thread count.
  parallel_for(particles_.n_particles(), [&](std::size_t i) {
    const Real pi_term = p[i] / (rho[i] * rho[i]);
    Vec<Dim> acc = Vec<Dim>::Zero();
    Real rate_rho = 0, rate_e = 0;
    for (std::size_t k = R.offsets[i]; k < R.offsets[i + 1]; ++k) {
      const std::size_t j = R.neighbour[k];
      const Vec<Dim> grad = R.kernel_derivative[k] * R.unit_vector[k];
      const Vec<Dim> v_ij = v[i] - v[j];
      const Real vr = v_ij.dot(R.unit_vector[k]) * R.distance[k];  // v_ij . x_ij
      Real viscosity = 0;
      if (vr < 0) {
        const Real phi = h * vr / (R.distance[k] * R.distance[k] + eps_h2);
        viscosity = (-alpha * Real(0.5) * (c[i] + c[j]) * phi + beta * phi * phi) / (Real(0.5) * (rho[i] + rho[j]));
      }
      const Real term = pi_term + p[j] / (rho[j] * rho[j]) + viscosity;
      const Real v_grad = v_ij.dot(grad);
      acc -= m[j] * term * grad;
      rate_e += Real(0.5) * m[j] * term * v_grad;
      rate_rho += m[j] / rho[j] * v_grad;
    }
    a[i] = acc;
    de[i] = rate_e;
    drho[i] = rho[i] * rate_rho;
  });
}

template <int Dim>
Real UpdatedLagrangianBody<Dim>::stable_time_step() const {
  const auto v = particles_.field(velocity_);
  const auto c = particles_.field(sound_speed_);
  const Real fastest = parallel_max(particles_.n_particles(), Real(0), [&](std::size_t i) { return c[i] + v[i].norm(); });
  return fastest > 0 ? settings_.cfl * settings_.smoothing_length / fastest : std::numeric_limits<Real>::infinity();
}

template <int Dim>
void UpdatedLagrangianBody<Dim>::advance(Real time, Real dt) {
  const std::size_t n = particles_.n_particles();
  auto v = particles_.field(velocity_);
  auto rho = particles_.field(density_);
  auto e = particles_.field(energy_);
  const auto a = particles_.field(acceleration_);
  const auto drho = particles_.field(density_rate_);
  const auto de = particles_.field(energy_rate_);
  auto& x = particles_.position;
  const Real half = Real(0.5) * dt;
  // Kick to the half step and drift; the rates are then evaluated at the drifted positions with the
  // state predicted to the full step by the old rates.
  auto& v_half = v_half_;
  auto& rho_half = rho_half_;
  auto& e_half = e_half_;
  v_half.resize(n);
  rho_half.resize(n);
  e_half.resize(n);
  const auto& box = settings_.periodic;
  parallel_for(n, [&](std::size_t i) {
    v_half[i] = v[i] + half * a[i];
    rho_half[i] = rho[i] + half * drho[i];
    e_half[i] = e[i] + half * de[i];
    x[i] += dt * v_half[i];
    if (box.any()) x[i] = box.wrap(x[i]);
    v[i] = v_half[i] + half * a[i];
    rho[i] = rho_half[i] + half * drho[i];
    e[i] = e_half[i] + half * de[i];
  });
  check_state(time + dt);
  compute_rates();
  // Second kick with the new rates.
  parallel_for(n, [&](std::size_t i) {
    v[i] = v_half[i] + half * a[i];
    rho[i] = rho_half[i] + half * drho[i];
    e[i] = e_half[i] + half * de[i];
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
  return out;
}

template class UpdatedLagrangianBody<2>;
template class UpdatedLagrangianBody<3>;

}  // namespace sph
