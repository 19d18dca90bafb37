#pragma once
// What the solid scenes share: their numerical parameters and the run of one elastic body (its
// stage and energy series on the run harness of libsph/io/run_harness.hpp, which writes the
// particles, the observers, progress and, on numerical failure, the last good state).

#include <functional>
#include <string>
#include <vector>

#include "apps/scenes/discretisation.hpp"
#include "apps/scenes/run_plan.hpp"
#include "apps/scenes/scene.hpp"
#include "libsph/core/point_probes.hpp"
#include "libsph/core/time_stepper.hpp"
#include "libsph/io/run_harness.hpp"
#include "libsph/solid/elastic_solid.hpp"
#include "libsph/solid/quasi_static.hpp"

namespace cardiosph {

/// Numerical settings shared by the solid scenes: the discretisation, and the solid's own choices
/// bound directly (sph::SolidNumerics: hourglass control and time step).
struct SolidSceneNumerics {
  Discretisation discretisation{1.3, "wendland_c4", 0};
  sph::SolidNumerics solid;
};

void declare_solid_numerics(sph::Parameters& p, SolidSceneNumerics& n, const std::string& time_unit);

/// Throws ParameterError naming `name` unless extent / spacing is a whole number.
void check_whole_spacings(double extent, double spacing, const std::string& name);

struct SolidRunPlan : RunPlan {  // sample_interval 0: end_time / 100 (also the energies)
  using RunPlan::RunPlan;
  std::function<void(sph::Real time, sph::Real dt)> before_step;  ///< before each step (may be empty)
  /// Couplings that load the solid, in its loads slot (sph::ElasticSolid::stage), in this order.
  std::vector<std::pair<std::string, sph::StepAction>> loads;
  double converge_after = 0;  ///< with a quasi-static relaxation: residual checks from this time on (the loads' ramp)
};

struct SolidRunSummary {
  std::size_t steps = 0;
  double initial_energy = 0;
  double max_energy_drift = 0;  ///< max |E(t) - E(0)| / max(E(0), max E) over the samples
  double min_jacobian = 1, max_jacobian = 1;
  bool converged = true;  ///< with a quasi-static relaxation: whether it converged before the end time
};

/// Runs the solid from t = 0 to the end time. Writes, named after its particle set,
/// <body>_*.vtu + <body>.pvd, <body>_energy.csv
/// (time, kinetic, strain, total, J range) and observers.csv into ctx.output_dir; fills steps,
/// particles, memory and time step in ctx.report. On NumericalFailure the restored last good state
/// is written, then the error is rethrown (the run ends as failed, exit code 1).
/// With a quasi-static `relaxation` (of the same solid), its steps replace the solid's and the run
/// stops at the first converged check after plan.converge_after (or at the end time, not converged);
/// residual_relative, converged and relaxation_steps go into the report.
template <int Dim>
SolidRunSummary run_solid(sph::ElasticSolid<Dim>& solid, const sph::NeighbourList<Dim>& relation,
                          const SolidRunPlan& plan, RunContext& ctx, sph::QuasiStaticRelaxation<Dim>* relaxation = nullptr);

/// Declares the quasi-static settings and `solver` (quasi_static or dynamic) of a quasi-static scene.
void declare_quasi_static(sph::Parameters& p, std::string& solver, sph::RelaxationSettings& settings);

/// Declares `clamp`: how the held particles behind a clamped face hold it (reflection or fixed).
void declare_clamp(sph::Parameters& p, std::string& clamp);
/// Holds the particles with X_0 < 0 against the face x = 0: by odd reflection (clamp = "reflection",
/// ElasticSolid::clamp_by_reflection) or at rest ("fixed").
template <int Dim>
void hold_face_x0(sph::ElasticSolid<Dim>& solid, const std::string& clamp);

/// Where the material points of `probes` (built on the solid's reference positions; for a
/// distributed solid, on the whole set before distribution) are now: F is brought to the current
/// positions, then each point is sampled with it (exact on quadratic motion,
/// libsph/core/point_probes.hpp). Collective for a distributed solid.
template <int Dim>
std::vector<sph::Vec<Dim>> material_point_positions(const sph::PointProbes<Dim>& probes, sph::ElasticSolid<Dim>& solid);

/// Particles whose reference position satisfies `inside`.
template <int Dim>
std::vector<sph::Index> select_particles(const sph::ParticleSet<Dim>& body,
                                         const std::function<bool(const sph::Vec<Dim>&)>& inside);

}  // namespace cardiosph
