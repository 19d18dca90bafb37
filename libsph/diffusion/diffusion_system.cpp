#include "libsph/diffusion/diffusion_system.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "libsph/core/correction_matrix.hpp"
#include "libsph/core/distribution.hpp"
#include "libsph/core/numerical_failure.hpp"
#include "libsph/core/parallel.hpp"
#include "libsph/diffusion/diffusion_operator.hpp"
#include "libsph/io/parameters.hpp"

namespace sph {

const std::vector<std::pair<std::string, DiffusionIntegrator>>& diffusion_integrator_names() {
  static const std::vector<std::pair<std::string, DiffusionIntegrator>> names{
      {"heun", DiffusionIntegrator::heun}, {"forward_euler", DiffusionIntegrator::forward_euler}};
  return names;
}

void declare_parameters(Parameters& p, DiffusionNumerics& n) {
  p.add_enum("diffusion_correction", n.correction, diffusion_correction_names(),
             "correction of the diffusion operator (moment: exact on quadratics; gradient: kernel-correction matrix B; "
             "libsph/diffusion/diffusion_operator.hpp)");
  p.add_enum("diffusion_integrator", n.integrator, diffusion_integrator_names(),
             "explicit integrator of the diffusion (heun: second order; forward_euler: first order, same stability limit)");
  p.add("diffusion_cfl", n.cfl, "-", "diffusion step as a fraction of its explicit stability limit", {0, 1, true, false});
  p.add("clip_negative_coefficients", n.clip_negative_coefficients,
        "clip negative pair coefficients of an anisotropic diffusion (monotone and stable; widens cross-fibre conduction)");
}

template <int Dim>
ScalarDiffusionSystem<Dim>::ScalarDiffusionSystem(ParticleSet<Dim>& particles, const InnerRelation<Dim>& relation,
                                                  Settings settings)
    : particles_(particles), relation_(relation), settings_(std::move(settings)) {
  const std::size_t n = particles_.n_owned();
  if (relation_.n_targets() != n)
    throw std::invalid_argument("diffusion on '" + particles_.name() + "': relation does not match the particles");
  if (!(settings_.numerics.cfl > 0 && settings_.numerics.cfl <= 1))
    throw std::invalid_argument("diffusion on '" + particles_.name() + "': cfl must lie in (0, 1]");
  for (const auto& D : settings_.diffusion_tensor) check_diffusion_tensor<Dim>(D, "diffusion on '" + particles_.name() + "'");

  if (settings_.field.valid()) {
    if (settings_.field.slot >= particles_.fields().size())
      throw std::invalid_argument("diffusion on '" + particles_.name() + "': the field handle is not of these particles");
    value_ = settings_.field;
    settings_.field_name = particles_.fields()[value_.slot]->name();
  } else {
    value_ = particles_.template register_field<Real>(settings_.field_name, Real(0));
  }
  if (settings_.numerics.correction == DiffusionCorrection::gradient) {
    const auto handle = particles_.template register_field<Mat<Dim>>("correction_matrix", Mat<Dim>::Identity(), false);
    compute_correction_matrix<Dim>(relation_, particles_.volume, particles_.field(handle));
    update_ghosts(particles_, particles_.field(handle));
    const auto B = particles_.field(handle);
    correction_matrix_.assign(B.begin(), B.end());
  }
  assemble();
  rate_.resize(n);
  if (settings_.numerics.integrator == DiffusionIntegrator::heun) {
    predicted_.resize(particles_.n_particles());
    predicted_rate_.resize(n);
  }
}

template <int Dim>
void ScalarDiffusionSystem<Dim>::set_diffusion_tensor(std::vector<Mat<Dim>> diffusion_tensor) {
  if (diffusion_tensor.size() != 1 && diffusion_tensor.size() != particles_.n_particles())
    throw std::invalid_argument("diffusion on '" + particles_.name() + "': need one diffusion tensor or one per particle");
  settings_.diffusion_tensor = std::move(diffusion_tensor);
  assemble();
}

template <int Dim>
void ScalarDiffusionSystem<Dim>::assemble() {
  std::vector<Mat<Dim>> moment;
  if (settings_.numerics.correction == DiffusionCorrection::moment) {
    if (moment_systems_.empty()) moment_systems_ = diffusion_moment_systems<Dim>(relation_, particles_.volume);
    moment = diffusion_moment_matrices<Dim>(std::span<const MomentSystemInverse<Dim>>(moment_systems_), settings_.diffusion_tensor);
    moment.resize(particles_.n_particles());  // the ghosts' from their owners
    update_ghosts(particles_, std::span<Mat<Dim>>(moment));
  }
  pair_coefficient_ = diffusion_pair_coefficients<Dim>(relation_, particles_.volume, settings_.diffusion_tensor,
                                                       settings_.numerics.correction, correction_matrix_, moment);
  if (settings_.numerics.clip_negative_coefficients)
    parallel_for(pair_coefficient_.size(), [&](std::size_t k) { pair_coefficient_[k] = std::max(pair_coefficient_[k], Real(0)); });
  step_limit_ = global_min(particles_, diffusion_time_step_limit<Dim>(relation_, pair_coefficient_));
}

template <int Dim>
void ScalarDiffusionSystem<Dim>::advance(Real time, Real dt) {
  auto C = particles_.field(value_);
  const std::size_t n = particles_.n_owned();
  apply_diffusion<Dim>(relation_, pair_coefficient_, C, rate_);
  if (settings_.numerics.integrator == DiffusionIntegrator::forward_euler) {
    parallel_for(n, [&](std::size_t i) { C[i] += dt * rate_[i]; });
  } else {
    // Heun: predictor C* = C + dt L(C), corrector C += dt/2 (L(C) + L(C*)).
    parallel_for(n, [&](std::size_t i) { predicted_[i] = C[i] + dt * rate_[i]; });
    update_ghosts(particles_, std::span<Real>(predicted_));
    apply_diffusion<Dim>(relation_, pair_coefficient_, predicted_, predicted_rate_);
    parallel_for(n, [&](std::size_t i) { C[i] += Real(0.5) * dt * (rate_[i] + predicted_rate_[i]); });
  }
  update_ghosts(particles_, C);
  check_finite(time + dt);
}

template <int Dim>
void ScalarDiffusionSystem<Dim>::evaluate_rate() {
  apply_diffusion<Dim>(relation_, pair_coefficient_, particles_.field(value_), rate_);
}

template <int Dim>
void ScalarDiffusionSystem<Dim>::update(Real time, Real dt) {
  auto C = particles_.field(value_);
  parallel_for(particles_.n_owned(), [&](std::size_t i) { C[i] += dt * rate_[i]; });
  update_ghosts(particles_, C);
  check_finite(time + dt);
}

template <int Dim>
void ScalarDiffusionSystem<Dim>::check_finite(Real time) const {
  const auto C = particles_.field(value_);
  const std::size_t n = particles_.n_owned();
  const std::size_t bad = first_index_where(n, [&](std::size_t i) { return !std::isfinite(C[i]); });
  const auto first = first_over_ranks(particles_, bad);
  if (first.found)
    throw NumericalFailure(particles_.name(), first.id, NumericalFailure::format_position(first.position), time,
                           settings_.field_name, "is not finite");
}

template class ScalarDiffusionSystem<2>;
template class ScalarDiffusionSystem<3>;

}  // namespace sph
