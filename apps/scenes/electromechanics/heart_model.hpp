#pragma once
// The systems of one heart on one particle set (apps/scenes/electromechanics/heart.cpp): the
// particles and their relation, the solid, the monodomain, the active tension, the cavities and
// the boundary springs, built from the heart's parameters and its geometry.

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "apps/scenes/electromechanics/heart_parameters.hpp"
#include "cardio/boundary_springs.hpp"
#include "cardio/cavities.hpp"
#include "cardio/cell_heterogeneity.hpp"
#include "cardio/early_activation.hpp"
#include "cardio/heart_geometry.hpp"

namespace cardiosph {

using Vec3 = sph::Vec<3>;

/// The constructor builds the parts in this order, each from those before it:
///   1. the particles (with their surface labels) and their inner relation in the reference configuration;
///   2. the solid (Holzapfel-Ogden with active stress; fibres and sheets of the geometry, the base clamped or held);
///   3. the monodomain (cells, conduction along the solid's fibres, the stimuli);
///   4. the active tension on the monodomain's calcium (Land) or potential (Nash-Panfilov), at its rest;
///   5. the cavities (the labelled endocardia) with their pressure, and the pericardial and base
///      springs (base_condition = springs).
//
/// On several MPI ranks (mpirun) the body is distributed right after it is built
/// (libsph/core/distribution.hpp): the systems hold this rank's particles, while what is found on
/// the whole heart (the stimuli, the base, the cavity surfaces, the observers) is found on whole_X
/// by every rank alike.
class HeartModel {
 public:
  HeartModel(const HeartParameters& p, const cardio::HeartGeometry& g, const cardio::HeartGeometrySettings& gs);
  HeartModel(const HeartModel&) = delete;

  /// Particles of the whole heart (on several ranks, every rank's owned ones together).
  std::size_t n() const { return whole_X.size(); }
  double max_displacement() const;
  double mean_potential() const;
  double max_tension() const;

  Real dp = 0, h = 0;
  sph::AnyKernel<3> kernel;
  std::span<const std::int8_t> labels;  ///< cardio::SurfaceLabel per particle of the whole heart, by global id
  std::unique_ptr<sph::ParticleSet<3>> body;
  std::unique_ptr<const sph::InnerRelation<3>> relation;
  std::unique_ptr<sph::ElasticSolid<3>> solid;
  std::vector<sph::Index> base;  ///< the base particles (global ids)
  std::span<const Vec3> X;  ///< reference positions (this rank's particles)
  std::vector<Vec3> whole_X;         ///< reference positions of the whole heart, by global id
  std::vector<Real> whole_volume;    ///< volumes of the whole heart, by global id
  bool ttp = false, dimensionless = false;
  double D_fibre = 0, D_cross = 0;
  Vec3 stimulus_centre = Vec3::Zero();
  std::size_t stimulated = 0;
  cardio::CellGroups cell_groups;        ///< the cell types and scalings of the ten Tusscher-Panfilov tissue
  std::vector<cardio::EarlySite> early;  ///< the early-activation sites of the endocardial surrogate
  std::unique_ptr<cardio::Monodomain<3>> monodomain;
  std::unique_ptr<cardio::ActiveTension<3>> tension;
  std::unique_ptr<cardio::Cavities> cavities;
  std::unique_ptr<cardio::BoundarySprings> springs;  ///< base_condition = springs
};

}  // namespace cardiosph
