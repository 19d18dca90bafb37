// `cardiosph particles MESH --dp X`: the heart-geometry stage alone. Writes the particles with
// volumes, surface normals, labels, fibres, sheets and the Laplace coordinates (particles.pvd) and
// reports the particle count, volume error, volume spread, nearest-neighbour spacing and, on the shipped LV ellipsoid, the
// fibre angle's deviation from the prescribed law.

#include <iostream>

#include "apps/scenes/geometry/geometry_scenes.hpp"
#include "apps/scenes/geometry/heart_geometry_parameters.hpp"
#include "libsph/io/particle_output.hpp"

namespace cardiosph {
namespace {

class ParticlesScene final : public Scene {
 public:
  void declare(sph::Parameters& p) override {
    geometry_.settings.mesh = shipped_mesh("lv_ellipsoid.stl");
    geometry_.declare(p);
    p.add_choice("fibre_check", fibre_check_, {"auto", "lv-ellipsoid", "none"},
                 "measure the fibre angle against the analytic LV ellipsoid (auto: when the mesh is the shipped one)");
    p.add_alias("fiber_check", "fibre_check");
    p.add("rim", rim_, "mm", "fibre check: leave out particles this close to the base plane", sph::Range::non_negative());
  }
  void check() const override { (void)geometry_.resolved(); }

  void run(RunContext& ctx) override {
    const auto settings = geometry_.resolved();
    auto log = [&](const std::string& line) {
      if (!ctx.quiet) std::cout << line << '\n' << std::flush;
    };
    const auto g = cardio::prepare_heart_geometry(settings, geometry_.cache_folder(), log);
    const std::size_t n = g.body.size();

    auto particles = make_particle_set(g, "myocardium");
    auto vector_field = [&](const std::string& name, const std::vector<geometry::Vec3>& values) {
      if (values.size() != n) return;
      auto f = particles.field(particles.register_field<sph::Vec<3>>(name, sph::Vec<3>::Zero()));
      for (std::size_t i = 0; i < n; ++i) f[i] = values[i].cast<sph::Real>();
    };
    auto scalar_field = [&](const std::string& name, const std::vector<double>& values) {
      if (values.size() != n) return;
      auto f = particles.field(particles.register_field<sph::Real>(name));
      for (std::size_t i = 0; i < n; ++i) f[i] = sph::Real(values[i]);
    };
    auto label = particles.field(particles.register_field<int>("label"));
    for (std::size_t i = 0; i < n; ++i) label[i] = g.labels[i];
    vector_field("normal", g.body.normals);
    vector_field("fibre", g.fibres.fibre);
    vector_field("sheet", g.fibres.sheet);
    scalar_field("transmural", g.fibres.transmural);
    scalar_field("apicobasal", g.fibres.apicobasal);
    scalar_field("lv", g.fibres.lv);
    scalar_field("rv", g.fibres.rv);
    sph::ParticleOutput<3>(ctx.output_dir, "particles").write(particles, 0.0);

    auto& r = ctx.report;
    r.particles["myocardium"] = n;
    r.memory_bytes["myocardium"] = n * particles.bytes_per_particle();
    r.results["particles"] = n;
    r.results["volume_relative_error"] = g.body.volume_relative_error;
    r.results["density_spread"] = g.body.density_spread;
    r.results["volume_ratio_min"] = g.body.volume_min_ratio;
    r.results["volume_ratio_max"] = g.body.volume_max_ratio;
    r.results["spacing_ratio"] = {{"min", g.body.spacing_min_ratio},
                                  {"mean", g.body.spacing_mean_ratio},
                                  {"max", g.body.spacing_max_ratio},
                                  {"spread", g.body.spacing_spread}};
    r.results["shape_volume_mm3"] = g.body.shape_volume;
    r.results["relaxation_residual"] = {g.body.residual_initial, g.body.residual_final};
    r.results["relaxation_steps"] = g.body.relaxation_steps_done;
    r.results["neighbour_builds"] = g.body.neighbour_builds;
    r.results["neighbours"] = {{"median", g.body.neighbours_median}, {"min", g.body.neighbours_min}};
    r.results["conditioning_min"] = g.body.conditioning_min;
    r.results["thin_particles"] = g.body.thin.size();
    r.results["label_method"] = g.label_method;
    r.results["fibre_method"] = g.fibre_method;
    r.results["tetrahedra"] = g.tets;
    if (g.fibre_method.rfind("mesh", 0) == 0) r.results["fibre_particles_outside_mesh"] = g.fibre_particles_outside;
    for (auto l : {cardio::label_epi, cardio::label_lv_endo, cardio::label_rv_endo, cardio::label_base})
      r.results["labelled"][std::string(cardio::surface_label_name(l))] = std::count(g.labels.begin(), g.labels.end(), l);
    r.results["geometry_hash"] = g.hash;
    r.results["from_cache"] = g.from_cache;
    r.results["geometry_seconds"] = g.seconds;
    if (!g.from_cache) {
      r.results["seconds"] = {{"level_set", g.body.level_set_seconds},
                              {"lattice", g.body.lattice_seconds},
                              {"relaxation", g.body.relaxation_seconds},
                              {"volumes", g.body.volume_seconds},
                              {"fibres", g.fibres.total_seconds},
                              {"fibre_solves", g.fibres.solver_seconds}};
      r.results["fibre_solver_iterations"] = g.fibres.solver_iterations;
    }
    std::error_code ec;
    const bool shipped_lv = std::filesystem::equivalent(settings.mesh, shipped_mesh("lv_ellipsoid.stl"), ec);
    if (!g.fibres.transmural.empty() && (fibre_check_ == "lv-ellipsoid" || (fibre_check_ == "auto" && shipped_lv))) {
      const auto check = cardio::check_lv_ellipsoid_fibres(g.body.positions, g.fibres, geometry::LvEllipsoid{}, settings.ldrb,
                                                           rim_, 2 * settings.spacing);
      r.results["fibre_angle_mad_deg"] = check.mad_deg;
      r.results["fibre_angle_max_deg"] = check.max_deg;
      r.results["fibre_check_particles"] = check.particles;
      r.reference = "fibre angle against alpha_endo (1 - e) + alpha_epi e on the Land et al. 2015 LV, analytic directions";
    }
  }

 private:
  HeartGeometryParameters geometry_;
  std::string fibre_check_ = "auto";
  double rim_ = 1.0;
};

}  // namespace

std::unique_ptr<Scene> make_particles_scene() { return std::make_unique<ParticlesScene>(); }

}  // namespace cardiosph
