#include "cardio/electromechanics.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "libsph/core/distribution.hpp"
#include "libsph/core/parallel.hpp"

namespace cardio {

template <int Dim>
void interact(ActiveTension<Dim>& on, const Monodomain<Dim>&, sph::SameParticles, Real time, Real dt) {
  on.advance(time, dt);
}

template <int Dim>
void interact(ActiveTension<Dim>& on, const sph::ElasticSolid<Dim>& by, sph::SameParticles, Real, Real) {
  const auto& body = by.particles();
  const auto F = body.field(by.deformation_gradient_field());
  const auto f0 = body.field(by.fibre_field());
  const auto stretch = on.fibre_stretch();
  sph::parallel_for(body.n_owned(), [&](std::size_t i) { stretch[i] = (F[i] * f0[i]).norm(); });
}

template <int Dim>
void interact(sph::ElasticSolid<Dim>& on, const ActiveTension<Dim>& by, sph::SameParticles, Real time, Real dt) {
  const Real fraction = (time + dt / 2 - by.step_start()) / by.step_size();
  by.interpolate(fraction, on.particles().field(on.active_tension_field()));
  if (on.active_stiffness_field().valid() && !by.stiffness().empty()) {
    const auto k = on.particles().field(on.active_stiffness_field());
    const auto l0 = on.particles().field(on.active_reference_stretch_field());
    std::copy(by.stiffness().begin(), by.stiffness().end(), k.begin());
    std::copy(by.reference_stretch().begin(), by.reference_stretch().end(), l0.begin());
  }
}

template <int Dim>
void interact(Monodomain<Dim>& on, const sph::ElasticSolid<Dim>& by, sph::SameParticles, Real, Real) {
  const auto& body = by.particles();
  const auto F = body.field(by.deformation_gradient_field());
  const auto f0 = body.field(by.fibre_field());
  const Real D_l = on.settings().longitudinal_diffusivity, D_t = on.settings().transverse_diffusivity;
  std::vector<sph::Mat<Dim>> D(body.n_particles());
  const auto& scale = on.settings().conduction_scale;
  // Owned particles from their F; the ghosts' tensors (which the diffusion's pairs average) from their owners.
  sph::parallel_for(body.n_owned(), [&](std::size_t i) {
    const Real k = scale.empty() ? Real(1) : scale[i];
    D[i] = pulled_back_conduction<Dim>(F[i], f0[i], k * D_l, k * D_t);
  });
  sph::update_ghosts(body, std::span<sph::Mat<Dim>>(D));
  on.set_diffusion_tensor(std::move(D));
}

template <int Dim>
void add_electromechanics(sph::TimeStepper& stepper, Monodomain<Dim>& monodomain, ActiveTension<Dim>& tension,
                          sph::ElasticSolid<Dim>& solid, const ElectromechanicsSettings& settings,
                          sph::SectionTimers& timers) {
  if (!solid.active_tension_field().valid())
    throw std::invalid_argument("electromechanics: the solid must be built with active stress");
  if (&solid.particles() != &monodomain.particles())
    throw std::invalid_argument("electromechanics: the monodomain and the solid must share one particle set");
  const Real D_l = monodomain.settings().longitudinal_diffusivity, D_t = monodomain.settings().transverse_diffusivity;
  if (settings.deformed_conduction && !(D_l > 0 && D_t > 0))
    throw std::invalid_argument("electromechanics: deformed conduction needs positive fibre diffusivities");
  if (!(settings.conduction_update_interval > 0))
    throw std::invalid_argument("electromechanics: the conduction update interval must be positive");

  // The coupling step: the largest whole number K of EP steps that one mechanics sub-step covers
  // (K = 1 when the mechanics step is the shorter; it then sub-cycles inside the EP step).
  const Real ep_step = monodomain.time_step();
  auto coupling_step = [&solid, ep_step] {
    const Real K = std::floor(solid.stable_time_step() / ep_step * (1 + Real(1e-9)));
    return std::max(Real(1), K) * ep_step;
  };
  // The solid's own phases, with the active stress before them; its loads slot stays open for the
  // scene's couplings (cavity pressure, boundary springs).
  sph::Stage mechanics = solid.stage("mechanics");
  mechanics.phases.insert(mechanics.phases.begin(), sph::Phase{"active stress", sph::coupling(solid, tension, sph::same_particles), {}});
  mechanics = timers.timed("mechanics", std::move(mechanics));
  sph::Stage step{"electromechanics", coupling_step, {}, ep_step};
  // The EP steps inside a coupling step: K of them, also when the accumulated time leaves the
  // coupling step a rounding error longer than K EP steps.
  sph::Stage electrophysiology = monodomain.stage("electrophysiology");
  electrophysiology.stable_time_step = [ep_step] { return ep_step * (1 + Real(1e-9)); };
  step.sub_cycle(std::move(electrophysiology));
  if (tension.needs_fibre_stretch())
    step.then("fibre stretch", timers.timed("active_tension", sph::coupling(tension, solid, sph::same_particles)));
  step.then("active tension", timers.timed("active_tension", sph::coupling(tension, monodomain, sph::same_particles)))
      .sub_cycle(std::move(mechanics));
  stepper.add_stage(std::move(step));

  if (settings.deformed_conduction)
    stepper.add_event("conduction update", {settings.conduction_update_interval, false, false, false},
                      [&monodomain, &solid, &timers](const sph::StepInfo& s) {
                        timers.measure("conduction_update", [&] {
                          solid.update_deformation_gradient();
                          interact(monodomain, solid, sph::same_particles, s.time, Real(0));
                        });
                      });
}

template void interact<2>(ActiveTension<2>&, const Monodomain<2>&, sph::SameParticles, Real, Real);
template void interact<3>(ActiveTension<3>&, const Monodomain<3>&, sph::SameParticles, Real, Real);
template void interact<2>(ActiveTension<2>&, const sph::ElasticSolid<2>&, sph::SameParticles, Real, Real);
template void interact<3>(ActiveTension<3>&, const sph::ElasticSolid<3>&, sph::SameParticles, Real, Real);
template void interact<2>(sph::ElasticSolid<2>&, const ActiveTension<2>&, sph::SameParticles, Real, Real);
template void interact<3>(sph::ElasticSolid<3>&, const ActiveTension<3>&, sph::SameParticles, Real, Real);
template void interact<2>(Monodomain<2>&, const sph::ElasticSolid<2>&, sph::SameParticles, Real, Real);
template void interact<3>(Monodomain<3>&, const sph::ElasticSolid<3>&, sph::SameParticles, Real, Real);
template void add_electromechanics<2>(sph::TimeStepper&, Monodomain<2>&, ActiveTension<2>&, sph::ElasticSolid<2>&,
                                      const ElectromechanicsSettings&, sph::SectionTimers&);
template void add_electromechanics<3>(sph::TimeStepper&, Monodomain<3>&, ActiveTension<3>&, sph::ElasticSolid<3>&,
                                      const ElectromechanicsSettings&, sph::SectionTimers&);

}  // namespace cardio
