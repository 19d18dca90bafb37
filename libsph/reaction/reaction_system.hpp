#pragma once
// A cell model at every particle of a particle set, or one of several parameter sets of the same
// model per particle (a heterogeneous tissue: cell types, regions, drug block). The transmembrane potential is the field
// "transmembrane_potential" (shared with the diffusion of the monodomain); every other state
// variable is a field named after it (written to output only on request). One step advances each
// particle's cell independently with the chosen scheme (cell_integrators.hpp; a model with a step in
// SIMD lanes, lanes.hpp, takes rbr_qss steps eight particles at a time), then checks the
// state: a non-finite value or a potential outside the model's valid range stops the run with a
// NumericalFailure naming the particle, its position, the time and the value.
//
// Quiescent cells (Settings::quiescent_step > 0) take longer steps, in the spirit of the per-cell
// adaptive steps of Qu & Garfinkel 1999 (IEEE Trans. Biomed. Eng. 46:1166): the cells go in fixed
// blocks of lane_count consecutive particles (per cell group), and a block whose last reaction step
// changed no potential faster than quiescent_rate skips its steps, keeping the skipped time, until
//   - the skipped time would exceed quiescent_step, or
//   - a potential of the block has moved by more than quiescent_rate x quiescent_step since the
//     block's last step (diffusion bringing a wavefront), or a stimulus acts on the block;
// it then takes one step over the skipped time and the current one (a stimulus averaged over that
// whole interval). Diastole, about 60 % of a beat, costs one reaction step per quiescent_step instead
// of one per splitting half step. The state of a skipping block lags by at most quiescent_step.
// The decisions depend on the block alone, so that results do not depend on the thread count.

#include <algorithm>
#include <array>
#include <numeric>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>
#include <span>
#include <sstream>
#include <string>

#include "libsph/core/distribution.hpp"
#include "libsph/core/numerical_failure.hpp"
#include "libsph/core/parallel.hpp"
#include "libsph/core/particles.hpp"
#include "libsph/core/state_archive.hpp"
#include "libsph/reaction/cell_integrators.hpp"
#include "libsph/reaction/reaction_model.hpp"

namespace sph {

/// The lane blocks in which a reaction system steps the cells of a whole set on one rank: lane_count
/// consecutive particles of each cell group (group[i]; empty: one group), in index order. Returns
/// per particle the index of the first particle of its block: the units to keep together when the
/// set is distributed (sph::distribute) with quiescent cells.
inline std::vector<Index> reaction_blocks(std::span<const std::uint16_t> group, std::size_t n = 0) {
  const std::size_t size = group.empty() ? n : group.size();
  std::vector<Index> first(size);
  std::vector<std::pair<std::size_t, Index>> open;  // per group: members so far, first of the open block
  for (std::size_t i = 0; i < size; ++i) {
    const std::size_t g = group.empty() ? 0 : group[i];
    if (open.size() <= g) open.resize(g + 1, {0, 0});
    auto& [count, start] = open[g];
    if (count % static_cast<std::size_t>(lane_count) == 0) start = static_cast<Index>(i);
    first[i] = start;
    ++count;
  }
  return first;
}

template <int Dim, ReactionModel M>
class ReactionSystem {
 public:
  static constexpr std::size_t n_states = M::n_states;
  struct Settings {
    ReactionScheme scheme = ReactionScheme::rbr_qss;
    bool write_states = false;  ///< write the state variables other than the potential to output
    double quiescent_step = 0;   ///< longest step of a quiescent block [ms]; 0: every cell at every step
    double quiescent_rate = 0.1;   ///< |dV/dt| below which a block is quiescent [voltage unit / ms]
  };

  /// Registers the state fields and sets every particle to the model's resting state.
  ReactionSystem(ParticleSet<Dim>& particles, M model, Settings settings)
      : ReactionSystem(particles, std::vector<M>{std::move(model)}, {}, settings) {}

  /// Particle i takes models[group[i]] (group empty: models[0] everywhere) and starts from its
  /// resting state. Throws std::invalid_argument if a group has no model or the sizes differ.
  ReactionSystem(ParticleSet<Dim>& particles, std::vector<M> models, std::vector<std::uint16_t> group, Settings settings)
      : particles_(particles), models_(std::move(models)), group_(std::move(group)), settings_(settings) {
    // The cells of the owned particles (distribution.hpp): a ghost's potential comes from its owner.
    const std::size_t n = particles_.n_owned();
    if (models_.empty()) throw std::invalid_argument("reaction on '" + particles_.name() + "': no cell model");
    if (!group_.empty() && group_.size() == particles_.n_particles()) group_.resize(n);
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
    if (!(settings_.quiescent_step >= 0 && std::isfinite(settings_.quiescent_step)) ||
        !(settings_.quiescent_rate > 0 && std::isfinite(settings_.quiescent_rate)))
      throw std::invalid_argument("reaction on '" + particles_.name() + "': the quiescent step must be >= 0 and the quiescent rate > 0");
    if (models_.size() == 1) group_.clear();
    if (!group_.empty()) {
      // Every particle at its own model's resting state.
      std::vector<typename M::State> rests;
      for (const auto& m : models_) rests.push_back(m.initial_state());
      for (std::size_t k = 0; k < n_states; ++k) {
        auto column = particles_.field(fields_[k]);
        for (std::size_t i = 0; i < n; ++i) column[i] = static_cast<Real>(rests[group_[i]][k]);
      }
    }
    // The blocks run within each group, in the order of the particle indices (fixed, whatever the
    // thread count).
    members_.resize(models_.size());
    for (std::size_t i = 0; i < n; ++i) members_[group_.empty() ? 0 : group_[i]].push_back(i);
    for (std::size_t g = 0; g < members_.size(); ++g)
      for (std::size_t first = 0; first < members_[g].size(); first += lane_count)
        blocks_.push_back({g, first, std::min<std::size_t>(lane_count, members_[g].size() - first)});
    block_steps_.assign(blocks_.size(), 0);
    if (settings_.quiescent_step > 0) {
      if (particles_.partition()) require_whole_blocks();
      skipped_.assign(blocks_.size(), 0);
      quiescent_.assign(blocks_.size(), 0);
      last_potential_.assign(n, static_cast<Real>(rest[0]));
      const auto V = particles_.field(fields_[0]);
      std::copy(V.begin(), V.begin() + static_cast<std::ptrdiff_t>(n), last_potential_.begin());
    }
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
    parallel_for(blocks_.size(), [&](std::size_t b) {
      if (settings_.quiescent_step > 0) advance_or_skip(b, columns, stimulus, double(dt));
      else advance_block(b, columns, stimulus, double(dt), 1.0);
    });
    check(columns, time + dt);
    update_ghosts(particles_, columns[0]);
  }

  /// Blocks of at most lane_count cells (each cell group in blocks of its own).
  std::size_t n_blocks() const { return blocks_.size(); }
  /// Reaction steps taken, counted in blocks of lane_count cells (a skipped block takes none).
  std::size_t block_steps() const { return std::accumulate(block_steps_.begin(), block_steps_.end(), std::size_t(0)); }
  /// Saves or loads the skipped time, the quiescence and the last potentials of the blocks
  /// (checkpoints; nothing when every cell steps every time).
  void checkpoint(StateArchive& archive) {
    archive.io("reaction_skipped_time", skipped_);
    archive.io("reaction_quiescent", quiescent_);
    archive.io("reaction_last_potential", last_potential_);
    archive.io("reaction_block_steps", block_steps_);
  }

 private:
  /// A block skips or steps as a whole, so on several ranks each rank must hold whole blocks of a
  /// one-rank run (sph::reaction_blocks kept together by sph::distribute) for the same results.
  void require_whole_blocks() const {
    const Partition<Dim>& p = *particles_.partition();
    std::vector<std::uint16_t> local(p.n_owned, 0), whole;
    if (!group_.empty()) std::copy(group_.begin(), group_.end(), local.begin());
    const auto all = gather_all(particles_, std::span<const std::uint16_t>(local), whole);
    const auto first = reaction_blocks(all);
    std::vector<std::size_t> size(first.size(), 0);
    for (const Index f : first) ++size[f];
    for (const Block& block : blocks_) {
      const Index f = first[p.global_id[members_[block.group][block.first]]];
      bool whole_block = block.count == size[f];
      for (std::size_t l = 0; l < block.count; ++l) whole_block = whole_block && first[p.global_id[members_[block.group][block.first + l]]] == f;
      if (!whole_block)
        throw std::invalid_argument("reaction on '" + particles_.name() + "': quiescent cells (reaction_quiescent_step > 0) on "
                                    "several ranks need the cells' lane blocks whole on each rank (distribute the particles "
                                    "keeping sph::reaction_blocks together)");
    }
  }
  std::size_t particle(const std::size_t b, std::size_t l) const {
    return members_[blocks_[b].group][blocks_[b].first + std::min(l, blocks_[b].count - 1)];
  }
  /// A quiescent block skips the step (module comment); otherwise it steps over its skipped time
  /// and dt, and records whether it is quiescent now.
  void advance_or_skip(std::size_t b, const std::array<std::span<Real>, n_states>& columns, std::span<const Real> stimulus,
                       double dt) {
    const Block& block = blocks_[b];
    const double step = settings_.quiescent_step, rate = settings_.quiescent_rate;
    bool disturbed = false;
    for (std::size_t l = 0; l < block.count && !disturbed; ++l) {
      const std::size_t i = particle(b, l);
      disturbed = (!stimulus.empty() && stimulus[i] != 0) || std::abs(columns[0][i] - last_potential_[i]) > rate * step;
    }
    if (quiescent_[b] && !disturbed && skipped_[b] + dt <= step * (1 + 1e-9)) {
      skipped_[b] += dt;
      return;
    }
    const double h = skipped_[b] + dt;
    std::array<Real, lane_count> before;
    for (std::size_t l = 0; l < block.count; ++l) before[l] = columns[0][particle(b, l)];
    advance_block(b, columns, stimulus, h, dt / h);
    skipped_[b] = 0;
    double fastest = 0;
    for (std::size_t l = 0; l < block.count; ++l) {
      const std::size_t i = particle(b, l);
      fastest = std::max(fastest, std::abs(double(columns[0][i]) - double(before[l])) / h);
      last_potential_[i] = columns[0][i];
    }
    quiescent_[b] = fastest < rate;
  }
  /// One step of dt of block b: in SIMD lanes for rbr_qss of a model that has them (the lanes past
  /// the block's count repeat its last cell, whose results are dropped), cell by cell otherwise.
  /// The stimulus is scaled by stimulus_scale (the share of the step it was averaged over).
  void advance_block(std::size_t b, const std::array<std::span<Real>, n_states>& columns, std::span<const Real> stimulus,
                     double dt, double stimulus_scale) {
    ++block_steps_[b];
    const Block& block = blocks_[b];
    const M& model = models_[block.group];
    if constexpr (HasLanesRbrQssStep<M>) {
      if (settings_.scheme == ReactionScheme::rbr_qss) {
        std::array<Lanes, n_states> y;
        Lanes s = Lanes::Zero();
        for (int l = 0; l < lane_count; ++l) {
          const std::size_t i = particle(b, static_cast<std::size_t>(l));
          for (std::size_t k = 0; k < n_states; ++k) y[k][l] = columns[k][i];
          if (!stimulus.empty()) s[l] = stimulus_scale * stimulus[i];
        }
        rbr_qss_step_in_lanes(model, y, s, dt);
        for (std::size_t l = 0; l < block.count; ++l)
          for (std::size_t k = 0; k < n_states; ++k) columns[k][particle(b, l)] = static_cast<Real>(y[k][static_cast<int>(l)]);
        return;
      }
    }
    for (std::size_t l = 0; l < block.count; ++l) {
      const std::size_t i = particle(b, l);
      typename M::State y;
      for (std::size_t k = 0; k < n_states; ++k) y[k] = columns[k][i];
      advance_cell(model, y, stimulus.empty() ? 0.0 : stimulus_scale * double(stimulus[i]), dt, settings_.scheme);
      for (std::size_t k = 0; k < n_states; ++k) columns[k][i] = static_cast<Real>(y[k]);
    }
  }

  void check(const std::array<std::span<Real>, n_states>& columns, Real time) const {
    const std::size_t n = particles_.n_owned();
    const VoltageRange range = models_[0].valid_voltage();
    const std::size_t bad = first_index_where(n, [&](std::size_t i) {
      for (std::size_t k = 0; k < n_states; ++k)
        if (!std::isfinite(columns[k][i])) return true;
      return !(columns[0][i] >= range.lower && columns[0][i] <= range.upper);
    });
    // Collective in a distributed run: every rank names the lowest global id with a problem.
    const auto first = first_over_ranks(particles_, bad);
    if (!first.found) return;
    const std::string where = NumericalFailure::format_position(first.position);
    if (bad >= n || (particles_.partition() && particles_.partition()->global_id[bad] != first.id))
      throw NumericalFailure(particles_.name(), first.id, where, time, std::string(M::state_names[0]),
                             "or another state is not finite or outside the valid range of the cell model (on another rank)");
    std::ostringstream problem;
    for (std::size_t k = 0; k < n_states; ++k)
      if (!std::isfinite(columns[k][bad])) {
        problem << "is not finite";
        throw NumericalFailure(particles_.name(), first.id, where, time, std::string(M::state_names[k]), problem.str());
      }
    problem << "= " << columns[0][bad] << " lies outside the valid range [" << range.lower << ", " << range.upper
            << "] of the cell model (stimulus too strong or reaction step too large)";
    throw NumericalFailure(particles_.name(), first.id, where, time, std::string(M::state_names[0]), problem.str());
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
  // Quiescent blocks (settings_.quiescent_step > 0): per block the time skipped since its last
  // step [ms] and whether that step found it quiescent; per particle the potential after it.
  std::vector<double> skipped_;
  std::vector<std::uint8_t> quiescent_;
  std::vector<Real> last_potential_;
  std::vector<std::size_t> block_steps_;  ///< steps taken by each block
  std::array<FieldHandle<Real>, n_states> fields_;
};

}  // namespace sph
