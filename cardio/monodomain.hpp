#pragma once
// Monodomain electrophysiology on a fixed particle set (Zhang et al. 2021, CMAME 381:113847, eq. 1):
//   chi C_m dV/dt = div(sigma grad V) - chi I_ion + I_stim,
// written per unit capacitance as
//   dV/dt = div(D grad V) + R(V, y) + s,   D = sigma / (chi C_m),   s = I_stim / (chi C_m).
// In mm, ms, mV with sigma in S/m, chi in 1/mm and C_m in uF/mm^2, D [mm^2/ms] = sigma / (chi C_m)
// with no further factor (monodomain_diffusivity below).
//
// One step of size dt is Strang operator splitting (reaction / diffusion / reaction), declared as
// the phases of one stage (stage(); libsph/core/time_stepper.hpp):
//   cells over dt/2 (scheme of the cell model, stimulus averaged over the half step),
//   diffusion over dt, a nested stage whose sub-steps are at most the diffusion stability limit,
//   cells over dt/2,
// followed by the activation-time update: the first time V rises through the threshold, found by
// linear interpolation within the step. The diffusion is the anisotropic SPH operator of
// libsph/diffusion with conductivity tensors D_t I + (D_l - D_t) f (x) f from the fibres.

#include <cstdint>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "cardio/ep_maps.hpp"
#include "libsph/core/distribution.hpp"
#include "libsph/core/neighbour_relation.hpp"
#include "libsph/core/particles.hpp"
#include "libsph/core/section_timers.hpp"
#include "libsph/core/time_stepper.hpp"
#include "libsph/diffusion/diffusion_system.hpp"
#include "libsph/reaction/cell_models.hpp"
#include "libsph/reaction/reaction_system.hpp"
#include "libsph/reaction/stimulus.hpp"

namespace cardio {

using sph::Real;

/// D = sigma / (chi C_m) [mm^2/ms] for sigma [S/m], chi [1/mm], C_m [uF/mm^2].
inline Real monodomain_diffusivity(double sigma, double chi, double capacitance) {
  return static_cast<Real>(sigma / (chi * capacitance));
}

/// The numerical choices of the monodomain (independent of the dimension). Scenes bind these members
/// directly as parameters through declare_parameters.
struct MonodomainNumerics {
  sph::ReactionScheme scheme = sph::ReactionScheme::rbr_qss;
  Real time_step = Real(0.05);  ///< splitting step [ms]
  /// The diffusion sub-steps: forward Euler at 0.9 of the stability limit by default.
  sph::DiffusionNumerics diffusion{sph::DiffusionCorrection::moment, sph::DiffusionIntegrator::forward_euler, Real(0.9),
                                   false};
  /// Quiescent cells (libsph/reaction/reaction_system.hpp): blocks of cells whose potential changes
  /// slower than quiescent_rate [mV/ms] take one reaction step per quiescent_step [ms] at most;
  /// 0: every cell at every half step.
  double quiescent_step = 0;
  double quiescent_rate = 0.1;
};

/// Declares reaction_scheme, ep_time_step [time_unit] and the diffusion parameters
/// (sph::declare_parameters of DiffusionNumerics).
void declare_parameters(sph::Parameters& p, MonodomainNumerics& numerics, const std::string& time_unit);

template <int Dim>
class Monodomain {
 public:
  struct StimulusRegion {
    std::string name;                    ///< for messages and reports
    std::vector<std::size_t> particles;  ///< the stimulated particles
    sph::StimulusProtocol protocol;      ///< strength as dV/dt [mV/ms]
  };
  struct Settings {
    sph::AnyCellModel cell_model = sph::AlievPanfilov{};
    /// A heterogeneous tissue: particle i takes cell_variants[cell_variant[i]] (all of the same
    /// model; e.g. cardio/cell_heterogeneity.hpp), and cell_model is unused. Empty: cell_model everywhere.
    std::vector<sph::AnyCellModel> cell_variants;
    std::vector<std::uint16_t> cell_variant;
    MonodomainNumerics numerics;
    std::vector<sph::Mat<Dim>> diffusion_tensor;   ///< D [mm^2/ms], one (uniform) or one per particle
    /// D_l along and D_t across the fibres [mm^2/ms], for conduction that follows a deforming
    /// tissue (the interaction with the solid, cardio/electromechanics.hpp); 0 when unused.
    Real longitudinal_diffusivity = 0, transverse_diffusivity = 0;
    /// Per particle, a factor on D_l and D_t of the deforming tissue (e.g. a fast endocardial layer
    /// standing for the Purkinje network); empty: 1 everywhere.
    std::vector<Real> conduction_scale;
    Real activation_threshold = 0;                 ///< V of the upstroke that marks activation [mV]
    std::vector<StimulusRegion> stimuli;
    bool write_states = false;                     ///< write every cell state variable to output
    /// Action potential maps (cardio/ep_maps.hpp) at this repolarisation percentage, e.g. 90 for
    /// APD90; 0: none (no bookkeeping beyond the first activation time).
    Real repolarisation_percent = 0;
  };
  /// Seconds spent in each part of the step, for run reports.
  struct Timings {
    double reaction = 0, diffusion = 0, maps = 0;
  };

  /// The relation must be the inner relation of `particles` and outlive the system.
  Monodomain(sph::ParticleSet<Dim>& particles, const sph::InnerRelation<Dim>& relation, Settings settings);
  Monodomain(const Monodomain&) = delete;  // its stage refers to it
  Monodomain& operator=(const Monodomain&) = delete;

  /// The splitting step (the reaction schemes of the cell models are stable at any step).
  Real time_step() const { return settings_.numerics.time_step; }
  /// The diffusion sub-step limit (cfl times the forward-Euler limit of the assembled operator).
  Real diffusion_time_step() const { return diffusion_.stable_time_step(); }
  /// The diffusion tensors in use (one, or one per particle) [mm^2/ms].
  const std::vector<sph::Mat<Dim>>& diffusion_tensor() const { return diffusion_.settings().diffusion_tensor; }
  /// Replaces the diffusion tensors (one, or one per particle) and reassembles the operator.
  void set_diffusion_tensor(std::vector<sph::Mat<Dim>> diffusion_tensor) {
    diffusion_.set_diffusion_tensor(std::move(diffusion_tensor));
  }
  /// The Strang step as a stage (stable step: the splitting step) to run in a time stepper or to
  /// nest in a coupled stage; later phases (e.g. the active tension) may be appended to it.
  sph::Stage stage(std::string name = "electrophysiology");
  /// One Strang step from `time` by dt (the phases of stage()).
  void advance(Real time, Real dt) { step_.run_step(time, dt); }

  sph::FieldHandle<Real> potential_field() const { return potential_; }
  sph::FieldHandle<Real> activation_field() const { return activation_; }
  /// The free cytosolic calcium Ca_i [mM] of a cell model that has one (ten Tusscher-Panfilov 2006);
  /// an invalid handle otherwise.
  sph::FieldHandle<Real> calcium_field() const;
  /// The action potential maps, or null when Settings::repolarisation_percent is 0.
  const ActionPotentialMaps<Dim>* maps() const { return maps_.get(); }
  /// With maps: the field `conduction_velocity` from the first activation times (cardio/ep_maps.hpp)
  /// over the monodomain's relation; call before writing it. Without maps: nothing.
  void update_conduction_velocity();
  sph::FieldHandle<Real> conduction_velocity_field() const { return conduction_velocity_; }
  /// True when every particle has been activated.
  bool all_activated() const;
  /// Latest activation time over the particles [ms], or -1 if some particle is not activated.
  Real latest_activation() const;
  Timings timings() const { return {timers_.seconds("reaction"), timers_.seconds("diffusion"), timers_.seconds("maps")}; }
  std::size_t diffusion_substeps() const { return timers_.calls("diffusion"); }
  /// Splitting steps taken (two reaction half steps each).
  std::size_t steps() const { return timers_.calls("reaction") / 2; }
  /// The share of the cells' reaction half steps taken (1 unless quiescent cells skip steps).
  double reaction_steps_taken() const {
    const auto* comm = sph::communicator_of(particles_);  // (on several ranks, every rank's blocks)
    auto total = [comm](std::size_t count) { return comm ? std::size_t(comm->sum(count)) : count; };
    const auto blocks = total(std::visit([](const auto& r) { return r.n_blocks(); }, reaction_));
    const std::size_t possible = blocks * timers_.calls("reaction");
    return possible ? double(total(std::visit([](const auto& r) { return r.block_steps(); }, reaction_))) / double(possible) : 1.0;
  }
  const Settings& settings() const { return settings_; }
  const sph::ParticleSet<Dim>& particles() const { return particles_; }
  /// The stimulus regions, which may be changed between steps (e.g. a pulse timed by the state).
  std::vector<StimulusRegion>& stimuli() { return settings_.stimuli; }
  /// Saves or loads what changes besides the particle fields (checkpoints): the diffusion tensors
  /// (which follow the deformation, cardio/electromechanics.hpp; loading reassembles the operator),
  /// the potential of the last step, the stimulus and the step counters. Stimuli changed during a run
  /// (stimuli()) are not saved.
  void checkpoint(sph::StateArchive& archive) {
    std::vector<sph::Mat<Dim>> tensor = diffusion_tensor();
    archive.io("diffusion_tensor", tensor);
    if (archive.loading()) set_diffusion_tensor(std::move(tensor));
    archive.io("stimulus", stimulus_);
    archive.io("previous_potential", previous_potential_);
    std::visit([&](auto& r) { r.checkpoint(archive); }, reaction_);
    timers_.checkpoint(archive);
  }

 private:
  using Reaction = std::variant<sph::ReactionSystem<Dim, sph::FitzHughNagumo>, sph::ReactionSystem<Dim, sph::AlievPanfilov>,
                                sph::ReactionSystem<Dim, sph::TenTusscherPanfilov2006>>;
  static Reaction make_reaction(sph::ParticleSet<Dim>& particles, const Settings& settings);
  void react(Real time, Real dt);
  void record_activation(Real time, Real dt);

  sph::ParticleSet<Dim>& particles_;
  Settings settings_;
  Reaction reaction_;
  const sph::InnerRelation<Dim>& relation_;
  sph::ScalarDiffusionSystem<Dim> diffusion_;  // after reaction_: it diffuses reaction_'s potential, passed by handle
  sph::FieldHandle<Real> potential_, activation_;
  std::unique_ptr<ActionPotentialMaps<Dim>> maps_;
  sph::FieldHandle<Real> conduction_velocity_;
  std::vector<Real> stimulus_, previous_potential_;
  sph::SectionTimers timers_;  // reaction and diffusion, for run reports
  sph::Stage step_;
};

extern template class Monodomain<2>;
extern template class Monodomain<3>;

}  // namespace cardio
