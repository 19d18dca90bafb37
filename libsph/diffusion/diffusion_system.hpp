#pragma once
// A scalar field that diffuses on a fixed particle set: dC/dt = div(D grad C), no-flux wherever the
// particle set ends (the pairwise form exchanges C only between particles), explicit time stepping
// at a fraction `cfl` of the forward-Euler stability limit (diffusion_operator.hpp).
// Fields it adds to the particle set: the scalar (named by the caller, unless the caller passes the
// handle of an existing field), and with the gradient correction the correction matrix (not
// written to output).
//
// Coupled to other bodies (libsph/diffusion/diffusion_contact.hpp), a step is split into phases
// across the systems: evaluate_rate() on each, the interactions add their exchange to rate(), then
// update() on each (forward Euler).

#include <string>
#include <utility>
#include <vector>

#include "libsph/core/neighbour_relation.hpp"
#include "libsph/core/particles.hpp"
#include "libsph/diffusion/diffusion_operator.hpp"

namespace sph {

enum class DiffusionIntegrator {
  forward_euler,  ///< C += dt L(C); first order in time
  heun,           ///< explicit trapezoidal (RK2); second order in time, same stability limit
};
/// The names of the integrators as parameters take them.
const std::vector<std::pair<std::string, DiffusionIntegrator>>& diffusion_integrator_names();

class Parameters;

/// The numerical choices of a diffusing field (independent of the dimension). Scenes bind these
/// members directly as parameters through declare_parameters.
struct DiffusionNumerics {
  DiffusionCorrection correction = DiffusionCorrection::moment;
  DiffusionIntegrator integrator = DiffusionIntegrator::heun;
  Real cfl = Real(0.5);  ///< fraction of the stability limit, in (0, 1]
  /// Set negative pair coefficients to zero. For a strongly anisotropic D (D_l > 3 D_t in 3D) some
  /// pairs get a_ij < 0 (anti-diffusion along them); on irregular particles or a distorted
  /// pulled-back tensor the operator can then have growing modes. Clipping makes it an M-matrix
  /// (monotone, no new extrema) at the cost of a larger effective cross-fibre diffusion.
  bool clip_negative_coefficients = false;
};

/// Declares diffusion_correction, diffusion_integrator, diffusion_cfl and clip_negative_coefficients.
void declare_parameters(Parameters& p, DiffusionNumerics& numerics);

template <int Dim>
class ScalarDiffusionSystem {
 public:
  struct Settings {
    std::string field_name = "concentration";  ///< the field registered for the scalar
    FieldHandle<Real> field;                    ///< or an existing field of the particle set (then field_name is unused)
    std::vector<Mat<Dim>> diffusion_tensor;  ///< one (uniform) or one per particle [length^2/time]
    DiffusionNumerics numerics;
  };

  /// The relation must be the inner relation of `particles` and outlive the system.
  ScalarDiffusionSystem(ParticleSet<Dim>& particles, const InnerRelation<Dim>& relation, Settings settings);

  FieldHandle<Real> value_field() const { return value_; }
  /// Stable step: cfl times the forward-Euler limit of the assembled operator.
  Real stable_time_step() const { return settings_.numerics.cfl * step_limit_; }
  /// Replaces the diffusion tensors (one, or one per particle) and reassembles the operator and its
  /// step limit, e.g. for a tensor pulled back through a deformation.
  void set_diffusion_tensor(std::vector<Mat<Dim>> diffusion_tensor);
  /// Advances the field from `time` by dt; throws NumericalFailure if a value becomes non-finite.
  void advance(Real time, Real dt);
  const Settings& settings() const { return settings_; }
  const ParticleSet<Dim>& particles() const { return particles_; }

  // The split step of a system coupled to others (forward Euler).
  /// rate() = the operator of this body applied to its field.
  void evaluate_rate();
  /// dC/dt per particle, to which interactions add.
  std::span<Real> rate() { return rate_; }
  /// C += dt rate(); throws NumericalFailure if a value becomes non-finite.
  void update(Real time, Real dt);

 private:
  ParticleSet<Dim>& particles_;
  const InnerRelation<Dim>& relation_;
  Settings settings_;
  FieldHandle<Real> value_;
  void assemble();
  void check_finite(Real time) const;

  std::vector<Mat<Dim>> correction_matrix_;  // gradient correction only
  std::vector<MomentSystemInverse<Dim>> moment_systems_;  // moment correction only (the relation is fixed)
  std::vector<Real> pair_coefficient_;
  Real step_limit_ = 0;
  std::vector<Real> rate_, predicted_, predicted_rate_;  // scratch, allocated once
};

extern template class ScalarDiffusionSystem<2>;
extern template class ScalarDiffusionSystem<3>;

}  // namespace sph
