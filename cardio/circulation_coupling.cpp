#include "cardio/circulation_coupling.hpp"

#include <algorithm>
#include <string>

#include "libsph/io/parameters.hpp"

namespace cardio {

CirculationSettings CirculationCoupling::coupled_settings(CirculationSettings settings, double heart_period) {
  settings.lv_mode = settings.rv_mode = VentricleMode::coupled;
  settings.heart_period = heart_period;
  return settings;
}

void CirculationCoupling::require_cavities(const Cavities& cavities) {
  const bool lv = cavities.find(label_lv_endo).has_value(), rv = cavities.find(label_rv_endo).has_value();
  if (!lv || !rv)
    throw sph::ParameterError(std::string("cavity_pressure = circulation needs the LV and the RV endocardium of the mesh; no ") +
                              (lv ? "RV" : "LV") + " endocardium is labelled, so its volume cannot be computed "
                              "(use cavity_pressure = none, constant or ramp)");
}

CirculationCoupling::CirculationCoupling(const CirculationSettings& settings, double heart_period,
                                         const CavityPressureSettings& preload, double start_time, Cavities& cavities)
    : circulation_(coupled_settings(settings, heart_period)), preload_(preload), start_(start_time) {
  require_cavities(cavities);
  for (std::size_t c = 0; c < cavities.size(); ++c)
    (cavities.surface(c).label == label_lv_endo ? lv_ : rv_) = c;
  targets_ = {preload.lv_pressure, preload.rv_pressure};
  const std::array<double, 2> v{cavities.volume(lv_), cavities.volume(rv_)};
  if (start_ == 0) {
    start(v, cavities.pressure(lv_).at(start_), cavities.pressure(rv_).at(start_));
    interact(cavities, *this, sph::same_particles, 0, 0);
  } else {  // until the start the circulation follows the unloaded cavities
    circulation_.initialise(0, v[0], v[1], 0, 0);
  }
}

double CirculationCoupling::preload_pressure(std::size_t c, double t) const {
  // The ramp to the end-diastolic pressures, then rest (CavityPressure in ramp form).
  const double rise = preload_.ramp_time > 0 ? std::min(1.0, t / preload_.ramp_time) : 1.0;
  return rise * targets_[c == lv_ ? 0 : 1];
}

void CirculationCoupling::start(const std::array<double, 2>& volumes, double lv_pressure, double rv_pressure) {
  circulation_.initialise(0, volumes[0], volumes[1], lv_pressure, rv_pressure);
  initial_blood_ = circulation_.total_blood_volume();
  started_ = true;
}

void CirculationCoupling::preload_step(double t, const std::array<double, 2>& volumes) {
  const double tolerance = 1e-9 * circulation_.settings().heart_period;
  advanced_ = false;
  if (t >= start_ - tolerance)
    start(volumes, preload_pressure(lv_, t), preload_pressure(rv_, t));
  else  // the circulation follows the cavities at the preload pressures (its output)
    circulation_.initialise(0, volumes[0], volumes[1], preload_pressure(lv_, t), preload_pressure(rv_, t));
}

void CirculationCoupling::coupled_step(double t, double dt, const std::array<double, 2>& volumes) {
  circulation_.advance(t - dt - start_, dt, volumes[0], volumes[1]);
  advanced_ = true;
}

void CirculationCoupling::checkpoint(sph::StateArchive& archive) {
  auto model = archive.part("model");
  circulation_.checkpoint(model);
  archive.io("started", started_);
  archive.io("initial_blood", initial_blood_);
}

void interact(CirculationCoupling& on, const Cavities& by, sph::SameParticles, Real time, Real dt) {
  const double t = double(time + dt);
  const std::array<double, 2> volumes{by.volume(on.lv()), by.volume(on.rv())};
  if (on.started())
    on.coupled_step(t, double(dt), volumes);
  else
    on.preload_step(t, volumes);
}

void interact(Cavities& on, const CirculationCoupling& by, sph::SameParticles, Real time, Real dt) {
  if (!by.started()) {
    const double t = double(time + dt);
    for (std::size_t c = 0; c < on.size(); ++c) on.pressure(c).set(by.preload_pressure(c, t));
    return;
  }
  const auto& circulation = by.circulation();
  const auto& settings = circulation.settings();
  for (const auto& [c, ventricle] : {std::pair{by.lv(), Ventricle::left}, std::pair{by.rv(), Ventricle::right}}) {
    on.pressure(c).set(circulation.pressure(ventricle));
    // p_ref + (V_b - V) / C_c, Circulation::pressure_at_volume with the circulation's current state.
    on.couple(c, {circulation.reference_pressure(ventricle), circulation.ventricle_blood_volume(ventricle),
                  settings.cavity_compliance});
  }
}

void add_circulation_coupling(sph::TimeStepper& stepper, CirculationCoupling& coupling, Cavities& cavities) {
  if (coupling.start_time() > 0)  // a step ends where the circulation starts
    stepper.add_event("end of preload", {stepper.end_time(), true, true, false, Real(coupling.start_time())},
                      [](const sph::StepInfo&) {});
  sph::Stage stage{"circulation", {}, {}};
  stage.then("circulation <- cavities", sph::coupling(coupling, cavities, sph::same_particles))
      .then("cavity pressure <- circulation", sph::coupling(cavities, coupling, sph::same_particles));
  stepper.add_stage(std::move(stage));
}

}  // namespace cardio
