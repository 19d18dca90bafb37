#include "libsph/fsi/solid_fluid_coupling.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "libsph/core/neighbour_relation.hpp"
#include "libsph/core/numerical_failure.hpp"
#include "libsph/core/parallel.hpp"

namespace sph {

namespace {

/// The thinnest extent of a body along its normals: for each surface particle i (none of the body
/// lies beyond it along n_i), the depth max_j (X_i - X_j).n_i over the particles j within a band of
/// half-width 0.9 dp around the line through X_i along n_i (a lattice line at any angle passes that
/// close to its points), plus one spacing dp for the particle's own width. Pairs are searched up to
/// `reach`, so the result is capped near reach + dp.
template <int Dim>
Real body_thickness(std::span<const Vec<Dim>> x, std::span<const Vec<Dim>> normal, Real dp, Real reach,
                    std::size_t& thinnest) {
  // Pairs within `reach`: the Wendland C2 support is 2h.
  const auto relation = build_inner_relation<Dim>(x, WendlandC2<Dim>{}, Real(0.5) * reach);
  const Real band = Real(0.9) * dp;
  Real thickness = std::numeric_limits<Real>::infinity();
  thinnest = x.size();
  for (std::size_t i = 0; i < x.size(); ++i) {
    const Vec<Dim>& n = normal[i];
    Real depth = 0;
    bool surface = true;
    for (std::size_t k = relation.offsets[i]; k < relation.offsets[i + 1]; ++k) {
      const Vec<Dim> d = x[relation.neighbour[k]] - x[i];
      const Real along = d.dot(n);
      if ((d - along * n).norm() > band) continue;
      if (along > Real(0.5) * dp) surface = false;
      depth = std::max(depth, -along);
    }
    if (surface && depth + dp < thickness) {
      thickness = depth + dp;
      thinnest = i;
    }
  }
  return thickness;
}

}  // namespace

template <int Dim>
SolidFluidCoupling<Dim>::SolidFluidCoupling(WeaklyCompressibleFluid<Dim>& fluid, ElasticSolid<Dim>& solid,
                                            const std::vector<Vec<Dim>>& reference_normals, Settings settings)
    : fluid_(fluid),
      solid_(solid),
      settings_(settings),
      wall_(solid.particles(), reference_normals, WallSlip::no_slip,
            {"wall_normal", "fluid_velocity", "fluid_acceleration"}),
      reference_normal_(reference_normals) {
  auto& particles = solid_.particles();
  const std::string body = "solid '" + particles.name() + "' in fluid '" + fluid_.particles().name() + "'";
  if (!(settings_.solid_spacing > 0)) throw std::invalid_argument(body + ": the solid spacing must be positive");
  if (!(settings_.acceleration_relaxation > 0 && settings_.acceleration_relaxation <= 1))
    throw std::invalid_argument(body + ": the acceleration relaxation " + std::to_string(settings_.acceleration_relaxation) +
                                " must be in (0, 1]");
  const Real fluid_dp = fluid_.settings().particle_spacing;
  std::size_t thinnest = 0;
  thickness_ = body_thickness<Dim>(particles.position, reference_normal_, settings_.solid_spacing,
                                   fluid_dp + settings_.solid_spacing, thinnest);
  if (thickness_ < fluid_dp * Real(1 - 1e-6))
    throw std::invalid_argument(body + ": the solid is " + std::to_string(thickness_) + " thick at particle " +
                                std::to_string(thinnest) + " " + NumericalFailure::format_position(particles.position[thinnest]) +
                                ", thinner than one fluid particle spacing " + std::to_string(fluid_dp) +
                                " (the fluid would see through it): refine the fluid or thicken the solid");
  pressure_force_ = particles.template register_field<Vec<Dim>>("fluid_pressure_force", Vec<Dim>::Zero());
  viscous_force_ = particles.template register_field<Vec<Dim>>("fluid_viscous_force", Vec<Dim>::Zero());
  wall_index_ = fluid_.add_wall(wall_, WallForces::record);
  solid_.external_force_field();
  start_position_.resize(particles.n_particles());
  start_velocity_.resize(particles.n_particles());
}

template <int Dim>
void SolidFluidCoupling<Dim>::update_surface() {
  auto& particles = solid_.particles();
  solid_.update_deformation_gradient();
  const auto F = particles.field(solid_.deformation_gradient_field());
  auto n = particles.field(wall_.normal_field());
  parallel_for(particles.n_particles(), [&](std::size_t i) {
    const Vec<Dim> current = F[i].inverse().transpose() * reference_normal_[i];
    n[i] = current / current.norm();
  });
}

template <int Dim>
void SolidFluidCoupling<Dim>::begin_acoustic_step() {
  auto& particles = solid_.particles();
  fluid_.wall_forces(wall_index_, particles.field(pressure_force_), particles.field(viscous_force_));
  const auto v = particles.field(solid_.velocity_field());
  std::copy(particles.position.begin(), particles.position.end(), start_position_.begin());
  std::copy(v.begin(), v.end(), start_velocity_.begin());
}

template <int Dim>
void interact(ElasticSolid<Dim>& on, const WeaklyCompressibleFluid<Dim>&, const SolidFluidCoupling<Dim>& coupling, Real,
              Real) {
  auto& p = on.particles();
  const auto fp = p.field(coupling.pressure_force_field());
  const auto fv = p.field(coupling.viscous_force_field());
  auto force = p.field(on.external_force_field());
  parallel_for(force.size(), [&](std::size_t i) { force[i] += fp[i] + fv[i]; });
}

template <int Dim>
void interact(FluidWall<Dim>& on, const ElasticSolid<Dim>& by, const SolidFluidCoupling<Dim>& coupling, Real, Real dt) {
  auto& particles = on.particles();
  const auto& x = by.particles().position;
  const auto v = by.particles().field(by.velocity_field());
  auto v_avg = particles.field(on.velocity_field());
  auto a_avg = particles.field(on.acceleration_field());
  const auto& x0 = coupling.start_position();
  const auto& v0 = coupling.start_velocity();
  const Real inverse = Real(1) / dt;
  const Real theta = coupling.settings().acceleration_relaxation;
  parallel_for(particles.n_particles(), [&](std::size_t i) {
    v_avg[i] = (x[i] - x0[i]) * inverse;
    a_avg[i] += theta * ((v[i] - v0[i]) * inverse - a_avg[i]);
  });
}

template <int Dim>
void SolidFluidCoupling<Dim>::fill(Stage& fluid_step, SectionTimers& timers) {
  const std::string name = solid_.particles().name();
  fluid_step.fill(fluid_.forces_slot(), "surface of '" + name + "'",
                  timers.timed("fsi_forces", [this](Real, Real) { update_surface(); }));
  Stage solid_steps = solid_.stage("solid '" + name + "'");
  if (!settings_.sub_cycling) solid_steps.stable_time_step = {};  // one step per acoustic step
  solid_steps.fill(solid_.loads_slot(), "fluid forces", sph::coupling(solid_, fluid_, *this));
  solid_steps.then("count", [this](Real, Real) { ++solid_steps_; });
  Stage within{"fsi '" + name + "'", {}, {}};
  within.then("forces and start of '" + name + "'", timers.timed("fsi_forces", [this](Real, Real) { begin_acoustic_step(); }))
      .sub_cycle(timers.timed("solid_step", std::move(solid_steps)))
      .then("motion of '" + name + "'", sph::coupling(wall_, solid_, *this));
  fluid_step.fill(fluid_.acoustic_slot(), std::move(within));
  if (!settings_.sub_cycling) fluid_.add_acoustic_step_limit([this] { return solid_.stable_time_step(); });
}

template <int Dim>
Vec<Dim> SolidFluidCoupling<Dim>::total_force() const {
  const auto& particles = solid_.particles();
  const auto fp = particles.field(pressure_force_);
  const auto fv = particles.field(viscous_force_);
  Vec<Dim> total = Vec<Dim>::Zero();
  for (std::size_t i = 0; i < particles.n_particles(); ++i) total += fp[i] + fv[i];
  return total;
}

template class SolidFluidCoupling<2>;
template class SolidFluidCoupling<3>;
template void interact<2>(ElasticSolid<2>&, const WeaklyCompressibleFluid<2>&, const SolidFluidCoupling<2>&, Real, Real);
template void interact<3>(ElasticSolid<3>&, const WeaklyCompressibleFluid<3>&, const SolidFluidCoupling<3>&, Real, Real);
template void interact<2>(FluidWall<2>&, const ElasticSolid<2>&, const SolidFluidCoupling<2>&, Real, Real);
template void interact<3>(FluidWall<3>&, const ElasticSolid<3>&, const SolidFluidCoupling<3>&, Real, Real);

}  // namespace sph
