#include "cardio/electromechanics.hpp"

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "libsph/core/parallel.hpp"

namespace cardio {

namespace {
template <class Work>
void timed(double& seconds, Work&& work) {
  const auto start = std::chrono::steady_clock::now();
  work();
  seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}
}  // namespace

template <int Dim>
Electromechanics<Dim>::Electromechanics(Monodomain<Dim>& monodomain, ActiveTension<Dim>& tension,
                                        sph::ElasticSolid<Dim>& solid, Settings settings)
    : monodomain_(monodomain), tension_(tension), solid_(solid), settings_(settings) {
  if (!solid_.active_tension_field().valid())
    throw std::invalid_argument("electromechanics: the solid must be built with active stress");
  if (!(settings_.longitudinal_diffusivity > 0 && settings_.transverse_diffusivity > 0))
    throw std::invalid_argument("electromechanics: the diffusivities must be positive");
  if (!(settings_.conduction_update_interval > 0))
    throw std::invalid_argument("electromechanics: the conduction update interval must be positive");
}

template <int Dim>
void Electromechanics<Dim>::update_conduction() {
  timed(own_.conduction, [&] {
    auto& body = solid_.particles();
    solid_.update_deformation_gradient();
    const auto F = body.field(solid_.deformation_gradient_field());
    const auto f0 = body.field(solid_.fiber_field());
    std::vector<sph::Mat<Dim>> D(body.n_particles());
    sph::parallel_for(D.size(), [&](std::size_t i) {
      D[i] = pulled_back_conduction<Dim>(F[i], f0[i], settings_.longitudinal_diffusivity, settings_.transverse_diffusivity);
    });
    monodomain_.set_diffusion_tensor(std::move(D));
  });
  ++conduction_updates_;
}

template <int Dim>
void Electromechanics<Dim>::add_stages(sph::TimeStepper& stepper) {
  stepper.add_stage({"electrophysiology", [this] { return monodomain_.time_step(); },
                     [this](Real t, Real dt) {
                       if (settings_.deformed_conduction &&
                           t - last_conduction_update_ >= settings_.conduction_update_interval * (1 - 1e-9)) {
                         update_conduction();
                         last_conduction_update_ = t;
                       }
                       monodomain_.advance(t, dt);
                       timed(own_.tension, [&] { tension_.advance(t, dt); });
                     },
                     false});
  stepper.add_stage({"mechanics", [this] { return solid_.stable_time_step(); },
                     [this](Real t, Real dt) {
                       timed(own_.mechanics, [&] {
                         const Real fraction = (t + dt / 2 - tension_.step_start()) / tension_.step_size();
                         tension_.interpolate(fraction, solid_.particles().field(solid_.active_tension_field()));
                         solid_.advance(t, dt);
                       });
                       ++mechanics_substeps_;
                     },
                     true});
}

template <int Dim>
typename Electromechanics<Dim>::Timings Electromechanics<Dim>::timings() const {
  Timings t = own_;
  t.reaction = monodomain_.timings().reaction;
  t.diffusion = monodomain_.timings().diffusion;
  return t;
}

template class Electromechanics<2>;
template class Electromechanics<3>;

}  // namespace cardio
