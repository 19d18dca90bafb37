#pragma once
// Diffusion between two bodies in contact: the interaction of one ScalarDiffusionSystem on another
// across a contact relation (libsph/core/interaction.hpp).
//
// For particle i of `on` and its neighbours j in `by`, the exchange is the Brookshaw (1985)
// Laplacian across the interface with the harmonic mean of the two coefficients (Cleary & Monaghan
// 1999, J. Comput. Phys. 148:227, eq. 15, which makes the flux continuous where D jumps):
//   dC_i/dt += sum_j a_ij (C_j - C_i),   a_ij = 2 D_ij V_j F_ij / r_ij,   F_ij = -dW/dr(r_ij),
//   D_ij = 2 D_i D_j / (D_i + D_j).
// Inside one body with D_i = D_j this is the body's own operator without correction
// (diffusion_operator.hpp), so two bodies of equal D in contact diffuse as one body does.
// Restrictions, checked: isotropic tensors (D = kappa I, one per body) and no operator correction
// in either body (the moment and gradient corrections treat the contact face as a free surface,
// which the exchange would then count twice). The pair terms use the cached W' and r of the
// relation, so the particles must not move, or the relation must be rebuilt when they do.
// With equal volumes a_ij = a_ji, so the exchange conserves sum V C over both bodies when both
// sides are evaluated from the same state.
//
// Multi-rate: when `by` sub-cycles inside each step of `on` (by diffuses faster), the sub-steps of
// `by` see `on` held at the start of the step, and `on` then takes its step against the average of
// by's field over those sub-steps (SubStepAverage below): sum_k ds_k a (C_i - C_j^k) = dt a (C_i - Cbar_j),
// so what one body gives the other takes, to round-off, whatever the sub-step sizes.
// Stability: the exchange restores, for the particles at the interface, the part of the kernel
// support cut off by the body's edge, and D_ij <= max(D_i, D_j); each body's stable step
// (its interior particles have the full support) therefore still bounds the step.

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "libsph/core/interaction.hpp"
#include "libsph/core/parallel.hpp"
#include "libsph/core/neighbour_relation.hpp"
#include "libsph/diffusion/diffusion_system.hpp"

namespace sph {

/// kappa of an isotropic tensor kappa I; throws std::invalid_argument naming `body` otherwise.
template <int Dim>
Real isotropic_diffusivity(const std::vector<Mat<Dim>>& tensor, const std::string& body) {
  if (tensor.size() != 1 || !(tensor[0] - tensor[0](0, 0) * Mat<Dim>::Identity()).isZero(Real(0)))
    throw std::invalid_argument("diffusion contact: body '" + body + "' needs one isotropic tensor kappa I");
  return tensor[0](0, 0);
}

/// The worker: rate[i] += sum_j a_ij (C_by[j] - C_on[i]) over the relation's rows.
template <int Dim>
void add_contact_diffusion(const ContactRelation<Dim>& relation, Real diffusivity, std::span<const Real> source_volume,
                           std::span<const Real> value_on, std::span<const Real> value_by, std::span<Real> rate) {
  parallel_for(relation.n_targets(), [&](std::size_t i) {
    Real sum = 0;
    for (const auto [k, j] : relation.row(i)) {
      const Real r = relation.distance[k];
      if (!(r > 0)) continue;
      sum += 2 * diffusivity * source_volume[j] * (-relation.kernel_derivative[k]) / r * (value_by[j] - value_on[i]);
    }
    rate[i] += sum;
  });
}

/// Diffusion from `by` into `on` across the contact relation from on's particles to by's; adds to
/// on.rate() (call between on.evaluate_rate() and on.update()).
/// The harmonic-mean coefficient D_ij of two bodies, after checking the restrictions above.
template <int Dim>
Real contact_diffusivity(const ScalarDiffusionSystem<Dim>& on, const ScalarDiffusionSystem<Dim>& by,
                         const ContactRelation<Dim>& relation) {
  const auto& on_body = on.particles();
  const auto& by_body = by.particles();
  if (on.settings().numerics.correction != DiffusionCorrection::none || by.settings().numerics.correction != DiffusionCorrection::none)
    throw std::invalid_argument("diffusion contact between '" + on_body.name() + "' and '" + by_body.name() +
                                "': both bodies need correction none");
  if (relation.n_targets() != on_body.n_particles())
    throw std::invalid_argument("diffusion contact: the relation does not start at body '" + on_body.name() + "'");
  const Real D_on = isotropic_diffusivity<Dim>(on.settings().diffusion_tensor, on_body.name());
  const Real D_by = isotropic_diffusivity<Dim>(by.settings().diffusion_tensor, by_body.name());
  return 2 * D_on * D_by / (D_on + D_by);
}

template <int Dim>
void interact(ScalarDiffusionSystem<Dim>& on, const ScalarDiffusionSystem<Dim>& by, const ContactRelation<Dim>& relation,
              Real /*time*/, Real /*dt*/) {
  const Real D_ij = contact_diffusivity(on, by, relation);
  add_contact_diffusion<Dim>(relation, D_ij, by.particles().volume, on.particles().field(on.value_field()),
                             by.particles().field(by.value_field()), on.rate());
}

/// The time average of a diffusing body's field over the sub-steps it takes within one step of
/// another body: reset() before the sub-steps, add(ds) at the start of each (the state a
/// forward-Euler sub-step evaluates its exchange at), finish() after the last.
template <int Dim>
class SubStepAverage {
 public:
  explicit SubStepAverage(const ScalarDiffusionSystem<Dim>& system)
      : system_(system), sum_(system.particles().n_particles()), mean_(sum_.size()) {}
  const ScalarDiffusionSystem<Dim>& system() const { return system_; }
  void reset() {
    std::fill(sum_.begin(), sum_.end(), Real(0));
    duration_ = 0;
  }
  void add(Real ds) {
    const auto C = system_.particles().field(system_.value_field());
    parallel_for(sum_.size(), [&](std::size_t j) { sum_[j] += ds * C[j]; });
    duration_ += ds;
  }
  void finish() {
    if (!(duration_ > 0)) throw std::logic_error("sub-step average: no sub-step was added");
    parallel_for(sum_.size(), [&](std::size_t j) { mean_[j] = sum_[j] / duration_; });
  }
  std::span<const Real> mean() const { return mean_; }

 private:
  const ScalarDiffusionSystem<Dim>& system_;
  std::vector<Real> sum_, mean_;
  Real duration_ = 0;
};

/// Diffusion from the sub-step average of a faster body into `on` (the conservative partner of
/// the exchange the faster body took in its sub-steps); adds to on.rate().
template <int Dim>
void interact(ScalarDiffusionSystem<Dim>& on, const SubStepAverage<Dim>& by, const ContactRelation<Dim>& relation,
              Real /*time*/, Real /*dt*/) {
  const auto& on_body = on.particles();
  const auto& by_body = by.system().particles();
  const Real D_ij = contact_diffusivity(on, by.system(), relation);
  add_contact_diffusion<Dim>(relation, D_ij, by_body.volume, on_body.field(on.value_field()), by.mean(), on.rate());
}

}  // namespace sph
