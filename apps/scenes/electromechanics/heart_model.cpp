#include "apps/scenes/electromechanics/heart_model.hpp"

#include <algorithm>

#include "apps/scenes/electromechanics/em_setup.hpp"
#include "geometry/tet_mesh.hpp"
#include "libsph/core/distribution.hpp"
#include "libsph/core/numerical_failure.hpp"
#include "libsph/core/parallel.hpp"
#include "libsph/reaction/reaction_system.hpp"
#include "libsph/io/parameters.hpp"

namespace cardiosph {
namespace {

/// Holzapfel-Ogden (passive_law; kPa) with active stress.
sph::ElasticSolid<3>::Settings solid_settings(const HeartParameters& p) {
  sph::ElasticSolid<3>::Settings s;
  auto law = p.passive_law == PassiveLaw::zhang_2021 ? sph::holzapfel_ogden_zhang_2021_kpa<3>(Real(p.bulk_modulus))
                                                     : sph::holzapfel_ogden_2009_kpa<3>(Real(p.bulk_modulus));
  if (p.passive_law == PassiveLaw::holzapfel_ogden_2009_transverse) law.a_s = law.a_fs = 0;
  s.material = law;
  s.density = Real(p.density);
  s.damping_rate = Real(p.damping_rate);
  s.active_stress = true;
  s.active_stiffness = p.tension_model == cardio::TensionModel::land_2017 && p.land_velocity_dependence;
  s.active_tension_non_negative = !p.tension_allow_negative;
  s.numerics = p.numerics.solid;
  return s;
}
/// Aliev-Panfilov with the Nash-Panfilov parameters in its own units (V = u, t = tau), as the
/// SPHinXsys heart case runs it (../shared/PARITY.md).
sph::AlievPanfilov nash_panfilov_dimensionless() {
  auto parameters = sph::AlievPanfilov::nash_panfilov_2004().parameters();
  parameters.scaling = {1, 0, 1};
  return sph::AlievPanfilov(parameters);
}
/// The cell types and scalings of a ten Tusscher-Panfilov heart, on the whole set.
cardio::CellGroups heart_cell_groups(const HeartModel& m, const HeartParameters& p, const cardio::HeartGeometry& g) {
  const auto& f = g.fibres;
  const auto cells = cell_heterogeneity(p.cells);
  std::vector<std::uint8_t> in_rv;
  if (cells.needs_coordinates() && f.lv.size() == m.n())
    in_rv = cardio::rv_ventricle(f.lv, f.rv, sph::build_inner_relation<3>(std::span<const Vec3>(m.whole_X), m.kernel, m.h));
  return cardio::ten_tusscher_groups(cells, m.n(), f.transmural, f.apicobasal, in_rv);
}
/// Aliev-Panfilov (Nash-Panfilov parameters) or ten Tusscher-Panfilov 2006, conduction D_l along
/// the solid's fibres and D_t across, and the paced stimulus within the radius of the centre.
//
/// On a distributed body the per-particle settings are this rank's local particles (owned and
/// ghosts) and the stimuli its owned ones, taken from the whole set's values by global id.
cardio::Monodomain<3>::Settings monodomain_settings(HeartModel& m, const HeartParameters& p, const cardio::HeartGeometry& g) {
  const std::size_t N = m.n();  // the whole set
  const auto& labels = m.labels;
  const auto& body = *m.body;
  const std::size_t n = body.n_particles();  // this rank's particles
  auto id = [&](std::size_t i) { return sph::global_index(body, i); };
  const auto x = std::span<const Vec3>(m.whole_X);
  const Vec3& stimulus_centre = m.stimulus_centre;
  cardio::Monodomain<3>::Settings ep;
  if (m.ttp) {
    if (m.cell_groups.models.size() == 1) ep.cell_model = m.cell_groups.models[0];
    else {
      ep.cell_variants = m.cell_groups.models;
      ep.cell_variant.resize(n);
      for (std::size_t i = 0; i < n; ++i) ep.cell_variant[i] = m.cell_groups.group[id(i)];
    }
  }
  else if (m.dimensionless) ep.cell_model = nash_panfilov_dimensionless();
  else ep.cell_model = sph::AlievPanfilov::nash_panfilov_2004();
  ep.numerics = p.monodomain;
  ep.repolarisation_percent = Real(p.apd_percent);
  ep.longitudinal_diffusivity = Real(m.D_fibre);
  ep.transverse_diffusivity = Real(m.D_cross);
  const auto f = body.field(m.solid->fibre_field());
  // A fast endocardial layer: D times endocardial_conduction on the endocardial particles.
  if (p.endocardial_conduction != 1) {
    ep.conduction_scale.assign(n, Real(1));
    for (std::size_t i = 0; i < n; ++i)
      if (labels[id(i)] == cardio::label_lv_endo || labels[id(i)] == cardio::label_rv_endo)
        ep.conduction_scale[i] = Real(p.endocardial_conduction);
  }
  ep.diffusion_tensor.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Real k = ep.conduction_scale.empty() ? Real(1) : ep.conduction_scale[i];
    ep.diffusion_tensor[i] = sph::transversely_isotropic_tensor<3>(k * Real(m.D_fibre), k * Real(m.D_cross), f[i]);
  }
  cardio::Monodomain<3>::StimulusRegion stimulus;
  const Vec3 lo = p.stimulus_box_min.cast<Real>(), hi = p.stimulus_box_max.cast<Real>();
  switch (p.stimulus_site) {
    case StimulusSite::box:
      stimulus.name = "box";
      for (std::size_t i = 0; i < N; ++i)
        if ((x[i].array() >= lo.array()).all() && (x[i].array() <= hi.array()).all()) stimulus.particles.push_back(i);
      if (stimulus.particles.empty())
        throw sph::ParameterError("no particle lies in the stimulus box " + sph::NumericalFailure::format_position(lo) +
                                  " to " + sph::NumericalFailure::format_position(hi) +
                                  " ('stimulus_box_min', 'stimulus_box_max', mesh coordinates)");
      break;
    case StimulusSite::point:
    case StimulusSite::lv_apex:
      stimulus.name = p.stimulus_site == StimulusSite::point ? "point" : "lv-apex";
      for (std::size_t i = 0; i < N; ++i)
        if ((x[i] - stimulus_centre).norm() <= p.stimulus_radius) stimulus.particles.push_back(i);
      if (stimulus.particles.empty())
        throw sph::ParameterError("no particle lies within 'stimulus_radius' of the stimulus centre " +
                                  sph::NumericalFailure::format_position(stimulus_centre));
      break;
    case StimulusSite::surface: {
      const auto label = cardio::label_of_surface_name(p.stimulus_surface);
      stimulus.name = p.stimulus_surface;
      for (std::size_t i = 0; i < N; ++i)
        if (labels[i] == label) stimulus.particles.push_back(i);
      if (stimulus.particles.empty())
        throw sph::ParameterError("parameter 'stimulus_surface' = " + p.stimulus_surface + ": no particle carries that label (labels by " +
                                  g.label_method + ")");
      break;
    }
    case StimulusSite::nodes: {
      // Mesh nodes of the tetrahedral mesh (an openCARP .vtx list): the particles within
      // stimulus_radius of any of them.
      const auto gs = p.geometry.resolved(preset_spacing(p.preset));
      const auto mesh = geometry::read_tet_mesh(gs.mesh, gs.scale);
      const auto nodes = geometry::read_vertex_list(p.stimulus_nodes, mesh.vertices.size());
      stimulus.name = "nodes";
      for (std::size_t i = 0; i < N; ++i)
        for (std::size_t k : nodes)
          if ((x[i] - mesh.vertices[k].cast<Real>()).norm() <= p.stimulus_radius) {
            stimulus.particles.push_back(i);
            break;
          }
      if (stimulus.particles.empty())
        throw sph::ParameterError("no particle lies within 'stimulus_radius' of the " + std::to_string(nodes.size()) +
                                  " nodes of '" + p.stimulus_nodes.string() + "'");
      break;
    }
    case StimulusSite::endocardium: {
      m.early = cardio::early_activation_sites(p.early_sites, p.early_site_list, g, x, stimulus_centre);
      ep.stimuli = cardio::endocardial_stimuli(m.early, p.purkinje_velocity, double(p.monodomain.time_step),
                                               {beat_origin(p), p.stimulus_duration, p.stimulus_strength, p.cycle_length, int(p.beats)},
                                               labels, x);
      for (const auto& region : ep.stimuli) m.stimulated += region.particles.size();
      break;
    }
  }
  if (p.stimulus_site != StimulusSite::endocardium) {
    m.stimulated = stimulus.particles.size();
    stimulus.protocol = {beat_origin(p), p.stimulus_duration, p.stimulus_strength, p.cycle_length, int(p.beats)};
    ep.stimuli.push_back(stimulus);
  }
  // The stimuli found on the whole set, in global ids: this rank stimulates its owned particles.
  if (body.partition())
    for (auto& region : ep.stimuli) {
      const std::vector<sph::Index> ids(region.particles.begin(), region.particles.end());
      const auto local = sph::local_indices(body, std::span<const sph::Index>(ids), true);
      region.particles.assign(local.begin(), local.end());
    }
  // Activation: the upstroke through -40 mV (ten Tusscher-Panfilov), -30 mV (u = 0.5), or u = 0.5.
  ep.activation_threshold = m.ttp ? Real(-40) : m.dimensionless ? Real(0.5) : Real(-30);
  return ep;
}
/// The centre of the stimulus: the point, the LV apex, or the centre of the box.
Vec3 stimulus_centre_of(const HeartParameters& p, const cardio::HeartGeometry& g, std::span<const Vec3> x) {
  switch (p.stimulus_site) {
    case StimulusSite::point: return p.stimulus_point.cast<Real>();
    case StimulusSite::box: return (Real(0.5) * (p.stimulus_box_min + p.stimulus_box_max)).cast<Real>();
    case StimulusSite::lv_apex:
    case StimulusSite::surface:
    case StimulusSite::nodes:
    case StimulusSite::endocardium: break;
  }
  return cardio::lv_apex(g, x);
}
cardio::ActiveTensionSettings tension_settings(const HeartParameters& p, Real rest) {
  cardio::ActiveTensionSettings ts = p.tension_rates;
  ts.model = p.tension_model;
  ts.land.T_ref = p.land_reference_tension;
  ts.velocity_dependence = p.land_velocity_dependence;
  ts.k_a = p.k_a;
  ts.rest_potential = rest;
  ts.threshold = rest + p.tension_threshold;
  ts.allow_negative = p.tension_allow_negative;
  return ts;
}

}  // namespace

HeartModel::HeartModel(const HeartParameters& p, const cardio::HeartGeometry& g, const cardio::HeartGeometrySettings& gs)
    : kernel(sph::make_kernel<3>(p.numerics.discretisation.kernel)), labels(g.labels) {
  // 1. Particles and relation; on several ranks this rank's part of them with its ghosts.
  dp = Real(gs.spacing);
  h = Real(p.numerics.discretisation.smoothing_length_ratio) * dp;
  body = std::make_unique<sph::ParticleSet<3>>(make_particle_set(g, "heart"));
  auto label = body->field(body->register_field<int>("label"));
  for (std::size_t i = 0; i < body->n_particles(); ++i) label[i] = g.labels[i];
  whole_X.assign(body->position.begin(), body->position.end());
  whole_volume.assign(body->volume.begin(), body->volume.end());
  ttp = p.cell_model == CellModel::ten_tusscher_panfilov;
  dimensionless = p.cell_model == CellModel::aliev_panfilov_dimensionless;
  if (ttp) cell_groups = heart_cell_groups(*this, p, g);
  // (with quiescent cells their lane blocks kept whole on a rank, so that they skip as on one rank)
  if (sph::Communicator::world().size() > 1)
    sph::distribute(*body, std::visit([this]<class K>(const K&) { return K::support_radius(h); }, kernel),
                    sph::Communicator::world(),
                    p.monodomain.quiescent_step > 0 ? sph::reaction_blocks(cell_groups.group, n()) : std::vector<sph::Index>{});
  relation = std::make_unique<const sph::InnerRelation<3>>(sph::build_inner_relation<3>(*body, kernel, h));
  // 2. Solid.
  solid = std::make_unique<sph::ElasticSolid<3>>(*body, *relation, solid_settings(p));
  base = attach_heart_geometry(*solid, g, "heart", Real(p.clamp_depth), p.base_condition == BaseCondition::clamp);
  X = body->field(solid->reference_position_field());
  // 3. Monodomain.
  D_fibre = p.diffusivity_fibre > 0 ? p.diffusivity_fibre : 1.0;
  D_cross = p.diffusivity_cross > 0 ? p.diffusivity_cross : D_fibre / 4;
  stimulus_centre = stimulus_centre_of(p, g, whole_X);
  monodomain = std::make_unique<cardio::Monodomain<3>>(*body, *relation, monodomain_settings(*this, p, g));
  // 4. Active tension.
  tension = std::make_unique<cardio::ActiveTension<3>>(
      *body, p.tension_model == cardio::TensionModel::land_2017 ? monodomain->calcium_field() : monodomain->potential_field(),
      tension_settings(p, body->field(monodomain->potential_field())[0]));
  // 5. Cavities and springs: the labelled surfaces of the mesh, carried by the particles.
  // (found on the whole set; on several ranks every rank holds whole surfaces, cardio/cavities.hpp)
  const auto mesh = read_geometry_mesh(gs);
  const auto face_labels = cavity_face_labels(mesh, g);
  cavities = std::make_unique<cardio::Cavities>(
      *solid, cardio::cavity_surfaces(mesh, face_labels, whole_X, whole_volume, g.labels, dp, kernel, h), p.cavity_pressure);
  if (p.base_condition == BaseCondition::springs) {
    static constexpr cardio::SurfaceLabel wanted[] = {cardio::label_epi, cardio::label_base};
    springs = std::make_unique<cardio::BoundarySprings>(
        *solid, cardio::cavity_surfaces(mesh, face_labels, whole_X, whole_volume, g.labels, dp, kernel, h, wanted),
        Real(p.pericardium_stiffness), Real(p.base_stiffness));
  }
}

double HeartModel::max_displacement() const {
  return sph::global_max(*body, sph::parallel_max(body->n_owned(), Real(0), [&](std::size_t i) { return (body->position[i] - X[i]).norm(); }));
}

double HeartModel::mean_potential() const {
  const auto V = body->field(monodomain->potential_field());
  return sph::global_sum(*body, [&](std::size_t i) { return double(V[i]); }) / double(n());
}

double HeartModel::max_tension() const {
  const auto& T = tension->tension();
  return sph::global_max(*body, *std::max_element(T.begin(), T.begin() + std::ptrdiff_t(body->n_owned())));
}

}  // namespace cardiosph
