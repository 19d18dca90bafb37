#pragma once
// Active tension of the myocardium driven by the transmembrane potential (Nash & Panfilov 2004,
// Prog. Biophys. Mol. Biol. 85:501, eq. 4), with the smooth activation function of Wong et al. 2011
// (CMAME 200:3139):
//   dT_a/dt = eps(V) (k_a (V - V_r) - T_a),
//   eps(V)  = eps_0 + (eps_inf - eps_0) exp(-exp(-xi (V - V_th))).
// eps switches from eps_0 (slow relaxation at rest) to eps_inf (fast development) as V rises
// through V_th over about 1/xi. Units: V [mV], T_a [kPa], k_a [kPa/mV], eps [1/ms].
// The defaults are those of the SPHinXsys heart case in physical units (Zhang et al. 2021, CMAME
// 381:113847, with V = 100 u - 80 mV and t = 12.9 tau ms of the Aliev-Panfilov scaling): eps_0 =
// 0.1 and eps_inf = 1 per model time unit, xi = 1 per mV, and k_a = 100 Pa per unit of u.
//
// Time integration: over a step [t, t + dt] the potential is taken at its mean V_m over the step
// (the value before and after the electrophysiology step), and the linear ODE is solved exactly:
//   T_a(t + dt) = T* + (T_a(t) - T*) exp(-eps(V_m) dt),  T* = k_a (V_m - V_r),
// which is stable and positive-preserving at any dt. Tension only: T_a is kept >= 0 unless
// allow_negative (the target k_a (V - V_r) is negative where V dips below the rest potential).
// The tension at the start and end of the last step is kept, so the mechanics sub-steps inside it
// see T_a interpolated linearly in time (no lag between the fields).

#include <cmath>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "libsph/core/particles.hpp"

namespace cardio {

using sph::Real;

struct ActiveTensionSettings {
  double k_a = 0.001;             ///< [kPa/mV] tension per mV above rest (0.1 kPa per unit of u)
  double rest_potential = -80;    ///< V_r [mV]
  double eps_rest = 0.1 / 12.9;   ///< eps_0 [1/ms]
  double eps_active = 1.0 / 12.9; ///< eps_inf [1/ms]
  double steepness = 1;           ///< xi [1/mV]
  double threshold = -80 + 100 * 0.01;  ///< V_th [mV] (u = a = 0.01 of the Nash-Panfilov model)
  bool allow_negative = false;    ///< let T_a fall below zero

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
  }
};

template <int Dim>
class ActiveTension {
 public:
  /// Reads the potential field of `particles`; T_a starts at zero.
  ActiveTension(const sph::ParticleSet<Dim>& particles, sph::FieldHandle<Real> potential, ActiveTensionSettings settings)
      : particles_(particles), potential_(potential), settings_(settings) {
    settings_.check();
    const auto V = particles_.field(potential_);
    synced_potential_.assign(V.begin(), V.end());
    start_.assign(V.size(), 0);
    end_.assign(V.size(), 0);
  }

  /// Advances T_a over [time, time + dt] with the mean of the potential at the previous call (or
  /// construction) and now.
  void advance(Real time, Real dt);

  /// T_a at time + fraction * dt of the last step (fraction in [0, 1]) into `tension`.
  void interpolate(Real fraction, std::span<Real> tension) const;
  /// T_a at the end of the last step.
  const std::vector<Real>& tension() const { return end_; }
  Real step_start() const { return step_start_; }
  Real step_size() const { return step_size_; }
  const ActiveTensionSettings& settings() const { return settings_; }

 private:
  const sph::ParticleSet<Dim>& particles_;
  sph::FieldHandle<Real> potential_;
  ActiveTensionSettings settings_;
  std::vector<Real> synced_potential_, start_, end_;
  Real step_start_ = 0, step_size_ = 0;
};

extern template class ActiveTension<2>;
extern template class ActiveTension<3>;

}  // namespace cardio
