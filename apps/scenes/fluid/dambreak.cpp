// The dam break of SPHinXsys's test_2d_dambreak (Zhang, Hu & Adams 2017, sec. 4.3): a water column
// of width a = 2 and height H = 1 at the left of a 5.366 x 5.366 tank, rho = 1, g = 1,
// c0 = 20 = 10 x 2 sqrt(g H), released at t = 0 from hydrostatic rest.
//
// Surge front. The toe x(t) (the rightmost particle plus dp / 2) against the experiments, as
// Z = x / a over T = t sqrt(g / a) (the scaling checked in docs/fluid.md: it is the one under which
// the Martin & Moyce points and the dimensional Koshizuka & Oka points, a = 1 m, g = 9.81, agree;
// T = t sqrt(2 g / a) puts them 41 % apart in time). Only the points with Z below the tank's far
// wall count. RMS of Z_sim(T) - Z_ref over those points: errors.surge_front_rms (Martin & Moyce)
// and errors.surge_front_rms_koshizuka, in column widths.
// Pressure probe: Shepard average of the fluid pressure at (tank_width, probe_height) (observers.csv)
// and the first time it exceeds 0.1 rho g H (results.pressure_first_rise_time).
// Files besides the particle output: surge_front.csv (x(t), Z(T)), surge_front_reference.csv (the
// published points with the simulated Z at their T), snapshots.csv (every particle's position and
// pressure at the first step after t = 1, 2, ..., 6), observers.csv (wall pressure, front).

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <limits>
#include <memory>
#include <tuple>
#include <vector>

#include "apps/scenes/fluid/fluid_scenes.hpp"
#include "geometry/lattice.hpp"
#include "libsph/core/distribution.hpp"
#include "libsph/core/point_probes.hpp"
#include "libsph/io/atomic_file.hpp"

namespace cardiosph {
namespace {

using sph::Real;

struct FrontPoint {
  double T, Z;
};

// Martin & Moyce 1952 (Phil. Trans. A 244:312), pairs (T, Z) as listed in REFERENCES.md.
constexpr std::array<FrontPoint, 10> martin_moyce{{{0.430, 1.108}, {0.614, 1.218}, {0.796, 1.437}, {0.970, 1.671},
                                                   {1.137, 1.893}, {1.292, 2.109}, {1.442, 2.334}, {1.621, 2.564},
                                                   {1.757, 2.787}, {1.929, 3.001}}};
// Koshizuka & Oka 1996, column 1 m wide: (t [s], x_tip [m]); T = t sqrt(9.81 / 1), Z = x_tip / 1.
constexpr std::array<FrontPoint, 15> koshizuka_oka{{{0.092, 1.128}, {0.191, 1.244}, {0.266, 1.464}, {0.322, 1.695},
                                                    {0.368, 1.903}, {0.414, 2.123}, {0.447, 2.365}, {0.496, 2.584},
                                                    {0.522, 2.804}, {0.565, 3.034}, {0.594, 3.219}, {0.637, 3.462},
                                                    {0.669, 3.704}, {0.702, 3.900}, {0.751, 4.132}}};

template <int Dim>
class DamBreakScene final : public Scene {
 public:
  explicit DamBreakScene(DamBreakParameters p) : p_(std::move(p)) {}

  void declare(sph::Parameters& p) override {
    p.add("resolution", p_.resolution, "-", "particles across the water height (dp = water_height / resolution)",
          sph::Range::closed(4, 2000));
    p.add("end_time", p_.end_time, "-", "simulated time (units of sqrt(H / g) with H = 1, g = 1)", sph::Range::positive());
    p.add("water_width", p_.water_width, "-", "width a of the water column", sph::Range::positive());
    p.add("water_height", p_.water_height, "-", "height H of the water column", sph::Range::positive());
    p.add("tank_width", p_.tank_width, "-", "inner width of the tank", sph::Range::positive());
    p.add("tank_height", p_.tank_height, "-", "inner height of the tank", sph::Range::positive());
    if constexpr (Dim == 3) p.add("depth", p_.depth, "-", "extent of tank and water along z", sph::Range::positive());
    p.add("density", p_.density, "-", "reference density rho0", sph::Range::positive());
    p.add("gravity", p_.gravity, "-", "gravitational acceleration g (downwards)", sph::Range::positive());
    p.add("sound_speed", p_.sound_speed, "-", "artificial sound speed c0", sph::Range::positive());
    p.add("viscosity", p_.viscosity, "-", "dynamic viscosity", sph::Range::non_negative());
    p.add("probe_height", p_.probe_height, "-", "height of the pressure probe on the far wall", sph::Range::non_negative());
    declare_fluid_numerics(p, p_.numerics, "-");
  }

  double dp() const { return p_.water_height / static_cast<double>(p_.resolution); }
  double reference_speed() const { return 2 * std::sqrt(p_.gravity * p_.water_height); }

  void check() const override {
    check_mach_number(reference_speed(), p_.sound_speed);
    const double spacing = dp();
    if (spacing > std::min({p_.tank_width, p_.tank_height, Dim == 3 ? p_.depth : p_.tank_width}) / 4)
      throw sph::ParameterError("parameter 'resolution' = " + std::to_string(p_.resolution) +
                                ": the particle spacing " + std::to_string(spacing) + " is not small against the tank");
    const double columns = p_.water_width / spacing;
    if (std::abs(columns - std::round(columns)) > 1e-6 * columns)
      throw sph::ParameterError("parameter 'water_width' = " + std::to_string(p_.water_width) +
                                " must be a whole number of particle spacings (" + std::to_string(spacing) + ")");
    if (p_.water_width > p_.tank_width || p_.water_height > p_.tank_height)
      throw sph::ParameterError("the water column (" + std::to_string(p_.water_width) + " x " +
                                std::to_string(p_.water_height) + ") does not fit in the tank (" +
                                std::to_string(p_.tank_width) + " x " + std::to_string(p_.tank_height) + ")");
  }

  bool checkpoints() const override { return true; }
  bool distributes() const override { return true; }
  void run(RunContext& ctx) override {
    using VecD = sph::Vec<Dim>;
    const Real dp = static_cast<Real>(this->dp());
    VecD water_upper, tank_upper;
    water_upper[0] = static_cast<Real>(p_.water_width);
    water_upper[1] = static_cast<Real>(p_.water_height);
    tank_upper[0] = static_cast<Real>(p_.tank_width);
    tank_upper[1] = static_cast<Real>(p_.tank_height);
    if constexpr (Dim == 3) {
      water_upper[2] = static_cast<Real>(p_.depth);
      tank_upper[2] = static_cast<Real>(p_.depth);
    }
    auto water = geometry::lattice_box<Dim>("water", VecD::Zero(), water_upper, dp);
    auto wall_set = box_walls<Dim>("tank", VecD::Zero(), tank_upper, dp, wall_layers(p_.numerics.discretisation));
    sph::FluidWall<Dim> tank(wall_set.particles, wall_set.normals, sph::WallSlip::free_slip);

    VecD g = VecD::Zero();
    g[1] = -static_cast<Real>(p_.gravity);
    auto settings = fluid_settings<Dim>(p_.numerics, dp, p_.density, p_.sound_speed, p_.viscosity, g, reference_speed());
    settings.domain_lower = VecD::Zero();
    settings.domain_upper = tank_upper;
    sph::WeaklyCompressibleFluid<Dim> fluid(water, settings);
    fluid.add_wall(tank);
    set_hydrostatic_state<Dim>(fluid, p_.water_height, p_.gravity);
    fluid.distribute();  // (on several MPI ranks)
    const std::string warning = check_mach_number(reference_speed(), p_.sound_speed);
    if (!warning.empty()) ctx.report.results["mach_warning"] = warning;

    // Surge front, every advection step until it reaches the far wall.
    const double a = p_.water_width, time_scale = std::sqrt(p_.gravity / a);
    struct Front {  // the toe's position at every advection step, and when it reached the far wall
      std::vector<double> t, x;
      bool done = false;
      double arrival_time = std::numeric_limits<double>::quiet_NaN();
      void checkpoint(sph::StateArchive& archive) {
        archive.io("front_done", done);
        archive.io("front_t", t);
        archive.io("front_x", x);
        archive.io("arrival_time", arrival_time);
      }
    } front{{0}, {p_.water_width}};
    auto& front_t = front.t;
    auto& front_x = front.x;
    bool& front_done = front.done;
    double& arrival_time = front.arrival_time;
    auto toe = [&] {
      Real x = 0;
      for (std::size_t i = 0; i < water.n_owned(); ++i) x = std::max(x, water.position[i][0]);
      return double(sph::global_max(water, x)) + 0.5 * double(dp);
    };
    // The whole water body's positions, volumes and pressures (gathered in global-id order from
    // several ranks; the local arrays on one).
    std::vector<VecD> whole_x;
    std::vector<Real> whole_volume, whole_pressure;
    auto gathered = [&] {
      const auto x = sph::gather_all<Dim, VecD>(water, water.position, whole_x);
      const auto volume = sph::gather_all<Dim, Real>(water, water.volume, whole_volume);
      const auto pressure = sph::gather_all<Dim, Real>(water, water.field(fluid.pressure_field()), whole_pressure);
      return std::make_tuple(x, volume, pressure);
    };

    // Pressure probe on the far wall.
    VecD probe_point = VecD::Zero();
    probe_point[0] = static_cast<Real>(p_.tank_width);
    probe_point[1] = static_cast<Real>(p_.probe_height);
    if constexpr (Dim == 3) probe_point[2] = static_cast<Real>(p_.depth / 2);
    const auto kernel = sph::make_kernel<Dim>(p_.numerics.discretisation.kernel);
    const auto [x0, volume0, pressure0] = gathered();
    sph::PointProbes<Dim> probe({probe_point}, x0, volume0, kernel, settings.smoothing_length, sph::ProbeFit::shepard);
    const double rise_threshold = 0.1 * p_.density * p_.gravity * p_.water_height;
    sph::RunRecord wall_probe;  // the first rise above rise_threshold and the peak
    double& first_rise = wall_probe.value("first_rise", std::numeric_limits<double>::quiet_NaN());
    double& peak_pressure = wall_probe.value("peak_pressure");

    FluidRunPlan plan(Dim == 2 ? "dambreak" : "dambreak-3d", p_.end_time, p_.numerics.discretisation.output_interval);
    plan.sample_interval = std::min(0.01, p_.end_time / 100);
    plan.observer_columns = {"wall_pressure", "surge_front"};
    plan.observers = [&](const sph::StepInfo& s) {
      // (the probe's sums run in the order of the particles' positions: the same on any rank count)
      const auto [x, volume, p] = gathered();
      probe.update(x, volume);
      const double pressure = probe.sample(0, p);
      peak_pressure = std::max(peak_pressure, pressure);
      if (std::isnan(first_rise) && pressure > rise_threshold) first_rise = s.time;
      return std::vector<double>{pressure, toe()};
    };
    // Snapshots of the particles (position and pressure) at a few times, for pictures without ParaView.
    const std::vector<double> snapshot_times{1, 2, 3, 4, 5, 6};
    struct Snapshots {  // the next snapshot time and the rows taken
      std::size_t next = 0;
      std::string text = "time,x,y,z,pressure\n";
      void checkpoint(sph::StateArchive& a) {
        a.io("next_snapshot", next);
        a.io("snapshots", text);
      }
    } snapshot_record;
    std::size_t& next_snapshot = snapshot_record.next;
    std::string& snapshots = snapshot_record.text;
    auto take_snapshot = [&](double time) {
      const auto [position, volume, p] = gathered();
      for (std::size_t i = 0; i < position.size(); ++i) {
        const auto& x = position[i];
        snapshots += std::to_string(time) + "," + std::to_string(x[0]) + "," + std::to_string(x[1]) + "," +
                     std::to_string(Dim == 3 ? double(x[Dim - 1]) : 0.0) + "," + std::to_string(p[i]) + "\n";
      }
    };
    plan.every_step = [&](const sph::StepInfo& s) {
      while (next_snapshot < snapshot_times.size() && s.time >= snapshot_times[next_snapshot]) {
        take_snapshot(s.time);
        ++next_snapshot;
      }
      if (front_done) return;
      const double x = toe();
      front_t.push_back(s.time);
      front_x.push_back(x);
      if (x >= p_.tank_width - 0.5 * double(dp)) {
        front_done = true;
        arrival_time = s.time;
      }
    };
    plan.keep("wall_probe", wall_probe);
    plan.keep("snapshots", snapshot_record);
    plan.keep("surge_front", front);
    run_fluid<Dim>(fluid, {&tank}, plan, ctx);

    // Front against the experiments.
    auto simulated_Z = [&](double T) {
      const double t = T / time_scale;
      const auto it = std::lower_bound(front_t.begin(), front_t.end(), t);
      if (it == front_t.end()) return std::numeric_limits<double>::quiet_NaN();
      const std::size_t k = static_cast<std::size_t>(it - front_t.begin());
      if (k == 0) return front_x[0] / a;
      const double w = (t - front_t[k - 1]) / (front_t[k] - front_t[k - 1]);
      return ((1 - w) * front_x[k - 1] + w * front_x[k]) / a;
    };
    const double wall_Z = p_.tank_width / a;
    std::string table = "source,T,Z_reference,Z_simulated\n";
    auto rms = [&](const auto& points, double T_factor, const char* name, bool write) {
      double sum = 0;
      std::size_t count = 0;
      for (const auto& pt : points) {
        if (pt.Z >= wall_Z) continue;
        const double T = pt.T * T_factor;
        const double Z = simulated_Z(T);
        if (std::isnan(Z)) continue;
        sum += (Z - pt.Z) * (Z - pt.Z);
        ++count;
        if (write) table += std::string(name) + "," + std::to_string(T) + "," + std::to_string(pt.Z) + "," + std::to_string(Z) + "\n";
      }
      return std::make_pair(count ? std::sqrt(sum / double(count)) : std::numeric_limits<double>::quiet_NaN(), count);
    };
    const auto mm = rms(martin_moyce, 1.0, "martin_moyce", true);
    const auto ko = rms(koshizuka_oka, std::sqrt(9.81 / 1.0), "koshizuka_oka", true);
    // The other reading of the scaling, T = t sqrt(2 g / a), for the record.
    const auto mm_alt = rms(martin_moyce, 1.0 / std::sqrt(2.0), "", false);
    const bool writes = sph::Communicator::world().is_root();
    if (writes) sph::write_file_atomically(ctx.output_dir / "surge_front_reference.csv", table);
    std::string front_csv = "time,x,T,Z\n";
    for (std::size_t k = 0; k < front_t.size(); ++k)
      front_csv += std::to_string(front_t[k]) + "," + std::to_string(front_x[k]) + "," + std::to_string(front_t[k] * time_scale) +
                   "," + std::to_string(front_x[k] / a) + "\n";
    if (writes) {
      sph::write_file_atomically(ctx.output_dir / "surge_front.csv", front_csv);
      sph::write_file_atomically(ctx.output_dir / "snapshots.csv", snapshots);
    }

    auto& report = ctx.report;
    report.reference = "surge front: Martin & Moyce 1952 and Koshizuka & Oka 1996 (Z = x / a against T = t sqrt(g / a), "
                       "points before the far wall); wall pressure probe: first rise above 0.1 rho g H";
    report.errors["surge_front_rms"] = mm.first;
    report.errors["surge_front_rms_koshizuka"] = ko.first;
    report.results["surge_front_points_martin_moyce"] = mm.second;
    report.results["surge_front_points_koshizuka"] = ko.second;
    report.results["surge_front_rms_if_T_is_t_sqrt_2g_over_a"] = mm_alt.first;
    report.results["front_arrival_time"] = arrival_time;
    report.results["pressure_first_rise_time"] = first_rise;
    report.results["peak_wall_pressure"] = peak_pressure;
    report.results["wall_particles"] = wall_set.particles.n_particles();
  }

 private:
  DamBreakParameters p_;
};

}  // namespace

std::unique_ptr<Scene> make_dambreak_scene(DamBreakParameters parameters) {
  return std::make_unique<DamBreakScene<2>>(std::move(parameters));
}
std::unique_ptr<Scene> make_dambreak_3d_scene(DamBreakParameters parameters) {
  return std::make_unique<DamBreakScene<3>>(std::move(parameters));
}

}  // namespace cardiosph
