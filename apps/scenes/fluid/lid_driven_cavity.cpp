// The lid-driven cavity: the unit square with no-slip walls, the top one sliding at U = 1
// (rho = 1, nu = 1 / Re), run to a steady state. The velocities on the centre lines, u along
// x = 1/2 and v along y = 1/2, sampled by linear moving-least-squares probes at the points of
// Ghia, Ghia & Shin 1982 (J. Comput. Phys. 48:387, tables I and II; the wall points excluded),
// give errors.centreline_rms, the RMS difference over both lines in lid velocities.

#include <array>
#include <cmath>
#include <memory>
#include <vector>

#include "apps/scenes/fluid/fluid_scenes.hpp"
#include "geometry/lattice.hpp"
#include "libsph/core/point_probes.hpp"
#include "libsph/io/atomic_file.hpp"

namespace cardiosph {
namespace {

using sph::Real;
using Vec2 = sph::Vec<2>;

struct GhiaTable {
  double reynolds;
  std::array<double, 15> y, u;  // u on x = 1/2
  std::array<double, 15> x, v;  // v on y = 1/2
};

constexpr std::array<double, 15> ghia_y{0.9766, 0.9688, 0.9609, 0.9531, 0.8516, 0.7344, 0.6172, 0.5000,
                                        0.4531, 0.2813, 0.1719, 0.1016, 0.0703, 0.0625, 0.0547};
constexpr std::array<double, 15> ghia_x{0.9688, 0.9609, 0.9531, 0.9453, 0.9063, 0.8594, 0.8047, 0.5000,
                                        0.2344, 0.2266, 0.1563, 0.0938, 0.0781, 0.0703, 0.0625};
const GhiaTable ghia_re100{100, ghia_y,
                           {0.84123, 0.78871, 0.73722, 0.68717, 0.23151, 0.00332, -0.13641, -0.20581, -0.21090,
                            -0.15662, -0.10150, -0.06434, -0.04775, -0.04192, -0.03717},
                           ghia_x,
                           {-0.05906, -0.07391, -0.08864, -0.10313, -0.16914, -0.22445, -0.24533, 0.05454, 0.17527,
                            0.17507, 0.16077, 0.12317, 0.10890, 0.10091, 0.09233}};
const GhiaTable ghia_re1000{1000, ghia_y,
                            {0.65928, 0.57492, 0.51117, 0.46604, 0.33304, 0.18719, 0.05702, -0.06080, -0.10648,
                             -0.27805, -0.38289, -0.29730, -0.22220, -0.20196, -0.18109},
                            ghia_x,
                            {-0.21388, -0.27669, -0.33714, -0.39188, -0.51550, -0.42665, -0.31966, 0.02526, 0.32235,
                             0.33075, 0.37095, 0.32627, 0.30353, 0.29012, 0.27485}};

class LidDrivenCavityScene final : public Scene {
 public:
  explicit LidDrivenCavityScene(LidDrivenCavityParameters p) : p_(std::move(p)) {}

  void declare(sph::Parameters& p) override {
    p.add("resolution", p_.resolution, "-", "particles across the unit cavity", sph::Range::closed(8, 4000));
    p.add("end_time", p_.end_time, "-", "simulated time (units of L / U)", sph::Range::positive());
    p.add_choice("preset", p_.preset, {"re100", "re1000"}, "Reynolds number of the run and its Ghia et al. table");
    p.add("sound_speed", p_.sound_speed, "-", "artificial sound speed c0", sph::Range::positive());
    declare_fluid_numerics(p, p_.numerics, "-");
  }

  void check() const override { check_mach_number(1.0, p_.sound_speed); }

  bool checkpoints() const override { return true; }  // nothing kept outside the bodies
  void run(RunContext& ctx) override {
    const GhiaTable& table = p_.preset == "re1000" ? ghia_re1000 : ghia_re100;
    const Real dp = Real(1) / static_cast<Real>(p_.resolution);
    auto water = geometry::lattice_box<2>("fluid", Vec2::Zero(), Vec2(1, 1), dp);
    auto wall_set = box_walls<2>("walls", Vec2::Zero(), Vec2(1, 1), dp, wall_layers(p_.numerics.discretisation));
    sph::FluidWall<2> walls(wall_set.particles, wall_set.normals, sph::WallSlip::no_slip);
    auto vw = wall_set.particles.field(walls.velocity_field());
    for (std::size_t i = 0; i < vw.size(); ++i)
      if (wall_set.particles.position[i][1] > 1) vw[i] = Vec2(1, 0);  // the lid, corners included
    auto settings = fluid_settings<2>(p_.numerics, dp, 1.0, p_.sound_speed, 1.0 / table.reynolds, Vec2::Zero(), 1.0);
    settings.domain_lower = Vec2::Zero();
    settings.domain_upper = Vec2(1, 1);
    sph::WeaklyCompressibleFluid<2> fluid(water, settings);
    fluid.add_wall(walls);

    FluidRunPlan plan("lid-driven-cavity", p_.end_time, p_.numerics.discretisation.output_interval);
    run_fluid<2>(fluid, {&walls}, plan, ctx);

    std::vector<Vec2> points;
    for (double y : table.y) points.emplace_back(Real(0.5), Real(y));
    for (double x : table.x) points.emplace_back(Real(x), Real(0.5));
    const auto kernel = sph::make_kernel<2>(p_.numerics.discretisation.kernel);
    sph::PointProbes<2> probes(points, water.position, water.volume, kernel, settings.smoothing_length);
    const auto v = water.field(fluid.velocity_field());
    double sum = 0;
    std::string csv = "line,coordinate,ghia,simulated\n";
    for (std::size_t k = 0; k < points.size(); ++k) {
      const Vec2 sample = probes.sample_value<Vec2>(k, v);
      const bool vertical = k < table.y.size();
      const double simulated = vertical ? sample[0] : sample[1];
      const double reference = vertical ? table.u[k] : table.v[k - table.y.size()];
      sum += (simulated - reference) * (simulated - reference);
      csv += std::string(vertical ? "u_at_x_half," : "v_at_y_half,") + std::to_string(vertical ? points[k][1] : points[k][0]) +
             "," + std::to_string(reference) + "," + std::to_string(simulated) + "\n";
    }
    sph::write_file_atomically(ctx.output_dir / "centrelines.csv", csv);
    auto& report = ctx.report;
    report.reference = "Ghia, Ghia & Shin 1982, centre-line velocities at Re " + std::to_string(int(table.reynolds));
    report.errors["centreline_rms"] = std::sqrt(sum / double(points.size()));
    report.results["reynolds"] = table.reynolds;
  }

 private:
  LidDrivenCavityParameters p_;
};

}  // namespace

std::unique_ptr<Scene> make_lid_driven_cavity_scene(LidDrivenCavityParameters parameters) {
  return std::make_unique<LidDrivenCavityScene>(std::move(parameters));
}

}  // namespace cardiosph
