#pragma once
// Interactions: what one system does to another.
//
// A system owns its particles, its fields and its material (sph::ElasticSolid,
// sph::ScalarDiffusionSystem, cardio::Monodomain, cardio::ActiveTension, ...). An interaction is one
// free function per pair of system types,
//
//   void interact(On& on, const By& by, const Relation& relation, Real time, Real dt);
//
// that adds the effect of `by` on `on` over the step [time, time + dt] and writes only entries of
// `on` (a gather over the relation's rows, so the result is the same for any thread count). The
// relation is a sph::ContactRelation from the particles of `on` to those of `by`, or
// sph::same_particles when both systems live on one particle set (the coupled physics of a
// myocardium: the potential drives the tension, the tension the stress, the deformation the
// conduction). The physics sits in a named worker beside the overload, which tests call directly.
//
// A scene declares the pairs it couples as phases of its stages (libsph/core/time_stepper.hpp):
//
//   stage.then("heat from the right block", sph::coupling(left, right, left_to_right));
//
// `coupling` resolves the overload (by argument-dependent lookup) where the pair is declared, so a
// pair of system types without an interaction is a compile error, never a silent no-op. Adding a
// coupling means adding one `interact` overload; docs/architecture.md has a worked example.
//
// Distribution: an interaction reads `by` only through the relation's source indices, so when a
// system becomes one partition with ghost particles, the ghosts are more sources and nothing here
// changes (docs/architecture.md).

#include <concepts>

#include "libsph/core/time_stepper.hpp"
#include "libsph/core/types.hpp"

namespace sph {

/// The relation of two systems that share one particle set: particle i of one is particle i of the other.
struct SameParticles {};
inline constexpr SameParticles same_particles{};

/// True if `interact(on, by, relation, time, dt)` exists for these types.
template <class On, class By, class Relation>
concept Interacts = requires(On& on, const By& by, const Relation& relation, Real t) {
  interact(on, by, relation, t, t);
};

/// The interaction of `by` on `on` across `relation` as a stage phase. All three must outlive the stage.
template <class On, class By, class Relation>
  requires Interacts<On, By, Relation>
StepAction coupling(On& on, const By& by, const Relation& relation) {
  return [&on, &by, &relation](Real time, Real dt) { interact(on, by, relation, time, dt); };
}

}  // namespace sph
