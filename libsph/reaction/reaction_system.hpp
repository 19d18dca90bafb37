#pragma once
// A cell model at every particle of a particle set, or one of several parameter sets of the same
// model per particle (a heterogeneous tissue: cell types, regions, drug block). The transmembrane potential is the field
// "transmembrane_potential" (shared with the diffusion of the monodomain); every other state
// variable is a field named after it (written to output only on request). One step advances each
// particle's cell independently with the chosen scheme (cell_integrators.hpp; a model with a step in
// SIMD lanes, lanes.hpp, takes rbr_qss steps eight particles at a time), then checks the
// state: a non-finite value or a potential outside the model's valid range stops the run with a
// NumericalFailure naming the particle, its position, the time and the value.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>
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
      : ReactionSystem(particles, std::vector<M>{std::move(model)}, {}, settings) {}

  /// Particle i takes models[group[i]] (group empty: models[0] everywhere) and starts from its
  /// resting state. Throws std::invalid_argument if a group has no model or the sizes differ.
  ReactionSystem(ParticleSet<Dim>& particles, std::vector<M> models, std::vector<std::uint16_t> group, Settings settings)
      : particles_(particles), models_(std::move(models)), group_(std::move(group)), settings_(settings) {
    const std::size_t n = particles_.n_particles();
    if (models_.empty()) throw std::invalid_argument("reaction on '" + particles_.name() + "': no cell model");
    if (!group_.empty() && group_.size() != n)
      throw std::invalid_argument("reaction on '" + particles_.name() + "': " + std::to_string(group_.size()) +
                                  " cell groups for " + std::to_string(n) + " particles");
    for (std::size_t i = 0; i < group_.size(); ++i)
      if (group_[i] >= models_.size())
        throw std::invalid_argument("reaction on '" + particles_.name() + "': particle " + std::to_string(i) + " is in group " +
                                    std::to_string(group_[i]) + " of " + std::to_string(models_.size()));
    const auto rest = models_[0].initial_state();
    for (std::size_t k = 0; k < n_states; ++k)
      fields_[k] = particles_.template register_field<Real>(std::string(M::state_names[k]), static_cast<Real>(rest[k]),
                                                            k == 0 || settings_.write_states);
    if (group_.empty() || models_.size() == 1) {
      group_.clear();
      return;
    }
    // Every particle at its own model's resting state; the lane blocks run within each group, in
    // the order of the particle indices (fixed, whatever the thread count).
    std::vector<typename M::State> rests;
    for (const auto& m : models_) rests.push_back(m.initial_state());
    for (std::size_t k = 0; k < n_states; ++k) {
      auto column = particles_.field(fields_[k]);
      for (std::size_t i = 0; i < n; ++i) column[i] = static_cast<Real>(rests[group_[i]][k]);
    }
    members_.resize(models_.size());
    for (std::size_t i = 0; i < n; ++i) members_[group_[i]].push_back(i);
    for (std::size_t g = 0; g < members_.size(); ++g)
      for (std::size_t first = 0; first < members_[g].size(); first += lane_count)
        blocks_.push_back({g, first, std::min<std::size_t>(lane_count, members_[g].size() - first)});
  }

  /// The model of group 0 (the only one of a homogeneous tissue).
  const M& model() const { return models_[0]; }
  std::size_t n_groups() const { return models_.size(); }
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
      advance_cell(models_[group_.empty() ? 0 : group_[i]], y, stimulus.empty() ? 0.0 : double(stimulus[i]), double(dt),
                   settings_.scheme);
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
    if (!group_.empty()) {
      parallel_for(blocks_.size(), [&](std::size_t b) {
        const Block& block = blocks_[b];
        const std::size_t* index = members_[block.group].data() + block.first;
        advance_block(columns, stimulus, dt, models_[block.group], [&](std::size_t l) { return index[l]; }, block.count);
      });
      return;
    }
    const std::size_t n = particles_.n_particles();
    const std::size_t blocks = (n + lane_count - 1) / lane_count;
    parallel_for(blocks, [&](std::size_t b) {
      const std::size_t first = b * lane_count;
      advance_block(columns, stimulus, dt, models_[0], [&](std::size_t l) { return first + l; },
                    std::min<std::size_t>(lane_count, n - first));
    });
  }
  /// One block of `count` cells, the l-th at particle index(l); the lanes past count repeat the last.
  template <class Index>
  static void advance_block(const std::array<std::span<Real>, n_states>& columns, std::span<const Real> stimulus, double dt,
                            const M& model, Index&& index, std::size_t count) {
    std::array<Lanes, n_states> y;
    Lanes s = Lanes::Zero();
    for (int l = 0; l < lane_count; ++l) {
      const std::size_t i = index(std::min<std::size_t>(static_cast<std::size_t>(l), count - 1));
      for (std::size_t k = 0; k < n_states; ++k) y[k][l] = columns[k][i];
      if (!stimulus.empty()) s[l] = stimulus[i];
    }
    rbr_qss_step_in_lanes(model, y, s, dt);
    for (std::size_t l = 0; l < count; ++l)
      for (std::size_t k = 0; k < n_states; ++k) columns[k][index(l)] = static_cast<Real>(y[k][static_cast<int>(l)]);
  }

  void check(const std::array<std::span<Real>, n_states>& columns, Real time) const {
    const std::size_t n = particles_.n_particles();
    const VoltageRange range = models_[0].valid_voltage();
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

  struct Block {
    std::size_t group, first, count;  ///< members_[group][first, first + count)
  };
  ParticleSet<Dim>& particles_;
  std::vector<M> models_;
  std::vector<std::uint16_t> group_;            ///< empty: models_[0] everywhere
  std::vector<std::vector<std::size_t>> members_;  ///< particles of each group, in index order
  std::vector<Block> blocks_;
  Settings settings_;
  std::array<FieldHandle<Real>, n_states> fields_;
};

}  // namespace sph
