#pragma once
// A cell model at every particle of a particle set. The transmembrane potential is the field
// "transmembrane_potential" (shared with the diffusion of the monodomain); every other state
// variable is a field named after it (written to output only on request). One step advances each
// particle's cell independently with the chosen scheme (cell_integrators.hpp; a model with a step in
// SIMD lanes, lanes.hpp, takes rbr_qss steps eight particles at a time), then checks the
// state: a non-finite value or a potential outside the model's valid range stops the run with a
// NumericalFailure naming the particle, its position, the time and the value.

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <sstream>
#include <string>

#include "libsph/core/numerical_failure.hpp"
#include "libsph/core/parallel.hpp"
#include "libsph/core/particles.hpp"
#include "libsph/reaction/cell_integrators.hpp"
#include "libsph/reaction/reaction_model.hpp"

namespace sph {

template <int Dim, ReactionModel M>
class ReactionSystem {
 public:
  static constexpr std::size_t n_states = M::n_states;
  struct Settings {
    ReactionScheme scheme = ReactionScheme::rbr_qss;
    bool write_states = false;  ///< write the state variables other than the potential to output
  };

  /// Registers the state fields and sets every particle to the model's resting state.
  ReactionSystem(ParticleSet<Dim>& particles, M model, Settings settings)
      : particles_(particles), model_(std::move(model)), settings_(settings) {
    const auto rest = model_.initial_state();
    for (std::size_t k = 0; k < n_states; ++k)
      fields_[k] = particles_.template register_field<Real>(std::string(M::state_names[k]), static_cast<Real>(rest[k]),
                                                            k == 0 || settings_.write_states);
  }

  const M& model() const { return model_; }
  FieldHandle<Real> potential_field() const { return fields_[0]; }
  FieldHandle<Real> state_field(std::size_t k) const { return fields_[k]; }

  /// Advances every cell from `time` by dt. stimulus[i] is the applied dV/dt of particle i averaged
  /// over the step; an empty span means no stimulus anywhere.
  void advance(Real time, Real dt, std::span<const Real> stimulus = {}) {
    std::array<std::span<Real>, n_states> columns;
    for (std::size_t k = 0; k < n_states; ++k) columns[k] = particles_.field(fields_[k]);
    const std::size_t n = particles_.n_particles();
    if constexpr (HasLanesRbrQssStep<M>) {
      if (settings_.scheme == ReactionScheme::rbr_qss) {
        advance_in_lanes(columns, stimulus, double(dt));
        check(columns, time + dt);
        return;
      }
    }
    parallel_for(n, [&](std::size_t i) {
      typename M::State y;
      for (std::size_t k = 0; k < n_states; ++k) y[k] = columns[k][i];
      advance_cell(model_, y, stimulus.empty() ? 0.0 : double(stimulus[i]), double(dt), settings_.scheme);
      for (std::size_t k = 0; k < n_states; ++k) columns[k][i] = static_cast<Real>(y[k]);
    });
    check(columns, time + dt);
  }

 private:
  /// The cells in blocks of lane_count consecutive particles, the blocks fixed by the particle index
  /// (so that every thread count gives the same blocks); the last block is filled up with copies of
  /// its last particle, whose results are dropped.
  void advance_in_lanes(const std::array<std::span<Real>, n_states>& columns, std::span<const Real> stimulus,
                        double dt) const {
    const std::size_t n = particles_.n_particles();
    const std::size_t blocks = (n + lane_count - 1) / lane_count;
    parallel_for(blocks, [&](std::size_t b) {
      const std::size_t first = b * lane_count;
      const std::size_t count = std::min<std::size_t>(lane_count, n - first);
      std::array<Lanes, n_states> y;
      Lanes s = Lanes::Zero();
      for (int l = 0; l < lane_count; ++l) {
        const std::size_t i = first + std::min<std::size_t>(static_cast<std::size_t>(l), count - 1);
        for (std::size_t k = 0; k < n_states; ++k) y[k][l] = columns[k][i];
        if (!stimulus.empty()) s[l] = stimulus[i];
      }
      rbr_qss_step_in_lanes(model_, y, s, dt);
      for (std::size_t l = 0; l < count; ++l)
        for (std::size_t k = 0; k < n_states; ++k) columns[k][first + l] = static_cast<Real>(y[k][static_cast<int>(l)]);
    });
  }

  void check(const std::array<std::span<Real>, n_states>& columns, Real time) const {
    const std::size_t n = particles_.n_particles();
    const VoltageRange range = model_.valid_voltage();
    const std::size_t bad = first_index_where(n, [&](std::size_t i) {
      for (std::size_t k = 0; k < n_states; ++k)
        if (!std::isfinite(columns[k][i])) return true;
      return !(columns[0][i] >= range.lower && columns[0][i] <= range.upper);
    });
    if (bad >= n) return;
    std::ostringstream problem;
    for (std::size_t k = 0; k < n_states; ++k)
      if (!std::isfinite(columns[k][bad])) {
        problem << "is not finite";
        throw NumericalFailure(particles_.name(), bad, NumericalFailure::format_position(particles_.position[bad]), time,
                               std::string(M::state_names[k]), problem.str());
      }
    problem << "= " << columns[0][bad] << " lies outside the valid range [" << range.lower << ", " << range.upper
            << "] of the cell model (stimulus too strong or reaction step too large)";
    throw NumericalFailure(particles_.name(), bad, NumericalFailure::format_position(particles_.position[bad]), time,
                           std::string(M::state_names[0]), problem.str());
  }

  ParticleSet<Dim>& particles_;
  M model_;
  Settings settings_;
  std::array<FieldHandle<Real>, n_states> fields_;
};

}  // namespace sph
