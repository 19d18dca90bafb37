#pragma once
// Active tension of the myocardium, one of two models (ActiveTensionSettings::model):
// - land_2017: calcium- and stretch-driven crossbridge model of Land et al. 2017 (cardio/land_2017.hpp),
//   driven by the free cytosolic calcium of the cell model (ten Tusscher-Panfilov 2006) and by the
//   fibre stretch lambda = |F f0| of the solid. Over a step [t, t + dt] the calcium is taken at its
//   mean over the step (the value before and after the electrophysiology step), lambda at its value
//   set before the step (set_fibre_stretch; the solid's F of the last mechanics sub-step) and
//   dlambda/dt as the change of lambda since the previous step over dt; T_a is the model's tension
//   at the end of the step. T_a may not fall below zero unless allow_negative.
//   The velocity dependence (the crossbridge distortions zeta, which answer a stretch change with
//   dzeta = A dlambda at once) makes T_a stiff in lambda: k = dT/dlambda = h T_ref / r_s A (XS + XW),
//   about ten times T_a. Lagged by a coupling step, this stiffness drives an oscillation that grows
//   (the heart inverts within tens of ms). So the tension also hands the solid k and the stretch
//   lambda_0 it was computed at (stiffness(), reference_stretch()), and the solid applies
//   T_a + k (lambda - lambda_0) at every sub-step (ElasticSolid::Settings::active_stiffness); the
//   next step starts from that value, T_a + k (lambda - lambda_0) at the step's end, so the tension
//   is continuous, and the model's states take up the stretch change through dlambda/dt. Unless
//   allow_negative, that sum too is kept >= 0, in the solid and where the next step starts
//   (ElasticSolid::Settings::active_tension_non_negative).
// - nash_panfilov: phenomenological tension driven by the transmembrane potential (Nash & Panfilov 2004,
// Prog. Biophys. Mol. Biol. 85:501, eq. 4), with the smooth activation function of Wong et al. 2011
// (CMAME 200:3139):
//   dT_a/dt = eps(V) (k_a (V - V_r) - T_a),
//   eps(V)  = eps_0 + (eps_inf - eps_0) exp(-exp(-xi (V - V_th))).
// eps switches from eps_0 (slow relaxation at rest) to eps_inf (fast development) as V rises
// through V_th over about 1/xi. Units: V [mV], T_a [kPa], k_a [kPa/mV], eps [1/ms].
// The rates default to those of the SPHinXsys heart case in physical units (Zhang et al. 2021, CMAME
// 381:113847, with V = 100 u - 80 mV and t = 12.9 tau ms of the Aliev-Panfilov scaling): eps_0 =
// 0.1 and eps_inf = 1 per model time unit, xi = 1 per mV. Its tension constant is 100 k_a V with
// k_a = 1e-4 in its stress unit g mm^-1 ms^-2 = MPa, i.e. 10 kPa per unit of u or k_a = 0.1 kPa/mV.
//
// Time integration: over a step [t, t + dt] the potential is taken at its mean V_m over the step
// (the value before and after the electrophysiology step), and the linear ODE is solved exactly:
//   T_a(t + dt) = T* + (T_a(t) - T*) exp(-eps(V_m) dt),  T* = k_a (V_m - V_r),
// which is stable and positive-preserving at any dt. Tension only: T_a is kept >= 0 unless
// allow_negative (the target k_a (V - V_r) is negative where V dips below the rest potential).
// The tension at the start and end of the last step is kept, so the mechanics sub-steps inside it
// see T_a interpolated linearly in time (no lag between the fields).
// On a distributed body the cells of the owned particles advance (the solid reads the tension of
// its owned particles only).

#include <cmath>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "cardio/land_2017.hpp"
#include "libsph/core/particles.hpp"

namespace cardio {

using sph::Real;

enum class TensionModel { nash_panfilov, land_2017 };

struct ActiveTensionSettings {
  TensionModel model = TensionModel::nash_panfilov;
  // Nash-Panfilov.
  double k_a = 0.001;             ///< [kPa/mV] tension per mV above rest
  double rest_potential = -80;    ///< V_r [mV]
  double eps_rest = 0.1 / 12.9;   ///< eps_0 [1/ms]
  double eps_active = 1.0 / 12.9; ///< eps_inf [1/ms]
  double steepness = 1;           ///< xi [1/mV]
  double threshold = -80 + 100 * 0.01;  ///< V_th [mV] (u = a = 0.01 of the Nash-Panfilov model)
  bool allow_negative = false;    ///< let T_a fall below zero
  // Land 2017.
  Land2017::Parameters land;
  double calcium_scale = 1000;    ///< uM per unit of the calcium field (1000: the cell model's mM)
  bool velocity_dependence = true;  ///< pass dlambda/dt to the model (false: 0, the length dependence only)

  /// eps(V) [1/ms].
  double rate(double V) const { return eps_rest + (eps_active - eps_rest) * std::exp(-std::exp(-steepness * (V - threshold))); }
  /// Throws std::invalid_argument naming the bad setting.
  void check() const {
    auto require = [](bool ok, const char* what) {
      if (!ok) throw std::invalid_argument(std::string("active tension: ") + what);
    };
    require(k_a >= 0 && std::isfinite(k_a), "k_a must be >= 0");
    require(eps_rest > 0 && eps_active > 0 && std::isfinite(eps_rest) && std::isfinite(eps_active),
            "the rates eps_0 and eps_inf must be positive");
    require(steepness > 0 && std::isfinite(steepness), "the steepness xi must be positive");
    require(std::isfinite(rest_potential) && std::isfinite(threshold), "V_r and V_th must be finite");
    require(calcium_scale > 0 && std::isfinite(calcium_scale), "the calcium scale must be positive");
    if (model == TensionModel::land_2017) land.check();
  }
};

template <int Dim>
class ActiveTension {
 public:
  /// Reads the driving field of `particles`: the potential (nash_panfilov) or the free calcium
  /// (land_2017). T_a starts at zero (nash_panfilov) or at the resting tension of the calcium at
  /// construction with lambda = 1 (land_2017).
  ActiveTension(const sph::ParticleSet<Dim>& particles, sph::FieldHandle<Real> driver, ActiveTensionSettings settings);

  /// Advances T_a over [time, time + dt] with the mean of the driving field at the previous call
  /// (or construction) and now.
  void advance(Real time, Real dt);
  /// The fibre stretch lambda per particle for the next step (land_2017), to be written by the
  /// caller or the interaction with the solid (cardio/electromechanics.hpp).
  std::span<Real> fibre_stretch() { return stretch_; }
  /// k = dT/dlambda of the crossbridge distortions and the stretch lambda_0 of the last step
  /// (land_2017 with velocity_dependence; empty otherwise).
  const std::vector<Real>& stiffness() const { return stiffness_; }
  const std::vector<Real>& reference_stretch() const { return previous_stretch_; }
  bool needs_fibre_stretch() const { return settings_.model == TensionModel::land_2017; }

  /// T_a at time + fraction * dt of the last step (fraction in [0, 1]) into `tension`.
  void interpolate(Real fraction, std::span<Real> tension) const;
  /// T_a at the end of the last step.
  const std::vector<Real>& tension() const { return end_; }
  Real step_start() const { return step_start_; }
  Real step_size() const { return step_size_; }
  const ActiveTensionSettings& settings() const { return settings_; }
  /// Saves or loads the tension, the driving field at the last call, the crossbridge states and the
  /// stretches (checkpoints).
  void checkpoint(sph::StateArchive& archive) {
    archive.io("synced_driver", synced_driver_);
    archive.io("start", start_);
    archive.io("end", end_);
    archive.io("states", states_);
    archive.io("stretch", stretch_);
    archive.io("previous_stretch", previous_stretch_);
    archive.io("stiffness", stiffness_);
    archive.io("step_start", step_start_);
    archive.io("step_size", step_size_);
  }

 private:
  const sph::ParticleSet<Dim>& particles_;
  sph::FieldHandle<Real> driver_;
  ActiveTensionSettings settings_;
  std::vector<Real> synced_driver_, start_, end_;
  // Land 2017: the crossbridge states and the stretch now and at the previous step.
  Land2017 land_;
  std::vector<Land2017::State> states_;
  std::vector<Real> stretch_, previous_stretch_, stiffness_;
  Real step_start_ = 0, step_size_ = 0;
};

extern template class ActiveTension<2>;
extern template class ActiveTension<3>;

}  // namespace cardio
