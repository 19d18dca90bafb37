// `spiral-wave`: a re-entrant Aliev-Panfilov spiral (physical units: mm, ms, mV) started by an S1-S2
// cross-field stimulus: S1 excites a strip along the left edge; S2 excites the lower half once the
// S1 wave back has passed the middle, so that the S2 front ends at the recovered/refractory border
// and curls into a spiral. Square or disc, isotropic or anisotropic (fibres along x). The rotation
// period is measured from the upstrokes at four observers; a spiral that breaks up or drifts out
// shows as irregular or missing upstrokes.
#include <cmath>

#include "apps/scenes/electrophysiology/ep_scenes.hpp"
#include "geometry/lattice.hpp"

namespace cardiosph {
namespace {

using sph::Real;
using Vec2 = sph::Vec<2>;

class SpiralWaveScene final : public Scene {
 public:
  explicit SpiralWaveScene(SpiralWaveParameters p) : p_(std::move(p)) {}
  void declare(sph::Parameters& p) override {
    p.add("resolution", p_.resolution, "-", "particles across the domain", sph::Range::positive());
    p.add("end_time", p_.end_time, "ms", "simulated time", sph::Range::positive());
    p.add_choice("domain", p_.domain, {"square", "disc"}, "shape of the tissue");
    p.add("size", p_.size, "mm", "side of the square or diameter of the disc", sph::Range::positive());
    p.add("diffusivity_longitudinal", p_.diffusivity_longitudinal, "mm^2/ms", "D along the fibres (x)",
          sph::Range::positive());
    p.add("diffusivity_transverse", p_.diffusivity_transverse, "mm^2/ms", "D across the fibres", sph::Range::positive());
    p.add("stimulus_strength", p_.stimulus_strength, "mV/ms", "applied dV/dt of the S1 and S2 pulses",
          sph::Range::positive());
    p.add("stimulus_duration", p_.stimulus_duration, "ms", "length of the S1 and S2 pulses", sph::Range::positive());
    p.add("s2_time", p_.s2_time, "ms",
          "onset of S2 (0: automatic, when the potential at the centre has fallen back through -70 mV after S1)",
          sph::Range::non_negative());
    declare_ep_numerics(p, p_.numerics, "ms");
  }
  bool checkpoints() const override { return true; }
  void run(RunContext& ctx) override {
    const double L = p_.size;
    const Real dp = static_cast<Real>(L / static_cast<double>(p_.resolution));
    auto body = [&] {
      auto box = geometry::lattice_box<2>("tissue", Vec2(0, 0), Vec2(L, L), dp);
      if (p_.domain == "square") return box;
      std::vector<Vec2> x;
      std::vector<Real> v;
      const Vec2 centre(L / 2, L / 2);
      for (std::size_t i = 0; i < box.n_particles(); ++i)
        if ((box.position[i] - centre).norm() <= L / 2) {
          x.push_back(box.position[i]);
          v.push_back(box.volume[i]);
        }
      return sph::ParticleSet<2>("tissue", std::move(x), std::move(v));
    }();
    const auto kernel = sph::make_kernel<2>(p_.numerics.discretisation.kernel);
    const Real h = static_cast<Real>(p_.numerics.discretisation.smoothing_length_ratio) * dp;
    const auto relation = sph::build_inner_relation<2>(body.position, kernel, h);

    cardio::Monodomain<2>::Settings settings;
    settings.cell_model = sph::AlievPanfilov{};
    settings.diffusion_tensor = {sph::transversely_isotropic_tensor<2>(static_cast<Real>(p_.diffusivity_longitudinal),
                                                                       static_cast<Real>(p_.diffusivity_transverse),
                                                                       Vec2(1, 0))};
    settings.activation_threshold = -40;
    // S1: a strip 5 % of the size wide along the left border (of the disc: within 0.45 L of the
    // horizontal diameter); S2: the lower half.
    std::vector<std::size_t> left_strip, lower_half;
    for (std::size_t i = 0; i < body.n_particles(); ++i) {
      const Vec2& x = body.position[i];
      const double dy = x[1] - L / 2;
      const double left_border = p_.domain == "square" ? 0.0 : L / 2 - std::sqrt(std::max(0.0, L * L / 4 - dy * dy));
      if (x[0] < left_border + 0.05 * L && (p_.domain == "square" || std::abs(dy) < 0.45 * L)) left_strip.push_back(i);
      if (x[1] < L / 2) lower_half.push_back(i);
    }
    const sph::StimulusProtocol s1{0, p_.stimulus_duration, p_.stimulus_strength, 0, 1};
    sph::StimulusProtocol s2{p_.s2_time, p_.stimulus_duration, p_.stimulus_strength, 0, p_.s2_time > 0 ? 1 : 0};
    settings.stimuli = {{"S1", left_strip, s1}, {"S2", lower_half, s2}};
    settings.numerics = p_.numerics.monodomain;
    settings.repolarisation_percent = static_cast<Real>(p_.numerics.apd_percent);
    cardio::Monodomain<2> monodomain(body, relation, settings);

    const std::vector<Vec2> observers{Vec2(L / 4, L / 4), Vec2(3 * L / 4, L / 4), Vec2(L / 4, 3 * L / 4),
                                      Vec2(3 * L / 4, 3 * L / 4), Vec2(L / 2, L / 2)};
    const sph::PointProbes<2> probes(observers, body.position, body.volume, kernel, h);
    // The S2 stimulus: at s2_time, or (s2_time <= 0) automatically, once the centre has been excited
    // by S1 and has fallen back through -70 mV. A resumed run places an automatic S2 again.
    struct SecondStimulus {
      const SpiralWaveParameters& p;
      cardio::Monodomain<2>& monodomain;
      double onset;
      bool excited = false;  // the centre has been excited by S1
      void place(double time) {
        onset = time;
        monodomain.stimuli()[1].protocol = {time, p.stimulus_duration, p.stimulus_strength, 0, 1};
      }
      void checkpoint(sph::StateArchive& a) {
        a.io("s2_onset", onset);
        a.io("excited", excited);
        if (a.loading() && p.s2_time <= 0 && onset > 0) place(onset);
      }
    } second{p_, monodomain, p_.s2_time};
    double& s2_onset = second.onset;
    EpRunPlan plan("spiral-wave", p_.end_time, p_.numerics.discretisation.output_interval, 0.5,
                   {"lower_left", "lower_right", "upper_left", "upper_right", "centre"});
    if (p_.s2_time <= 0) {
      const auto V = body.field(monodomain.potential_field());
      plan.every_step = [&, V](const sph::StepInfo& s) {
        if (second.onset > 0) return;
        const double centre = probes.sample(4, V);
        second.excited = second.excited || centre > 0;
        if (second.excited && centre < -70) second.place(s.time);
      };
    }
    plan.keep("s2", second);
    const auto traces = run_monodomain<2>(monodomain, body, relation, probes, plan, ctx);

    // Rotation period: intervals between successive upstrokes at each corner observer after S2,
    // skipping the first two (the S2 wave and the spiral forming).
    std::vector<double> intervals;
    std::size_t fewest_rotations = static_cast<std::size_t>(-1);
    double worst_deviation = 0;
    for (std::size_t p = 0; p < 4; ++p) {
      auto up = upward_crossings(traces.time, traces.potential[p], -40);
      std::erase_if(up, [&](double t) { return s2_onset <= 0 || t < s2_onset; });
      const std::size_t rotations = up.size() > 2 ? up.size() - 2 : 0;
      fewest_rotations = std::min(fewest_rotations, rotations);
      for (std::size_t k = 3; k < up.size(); ++k) intervals.push_back(up[k] - up[k - 1]);
    }
    double mean = 0, variance = 0;
    for (double d : intervals) mean += d / static_cast<double>(intervals.size());
    for (double d : intervals) {
      variance += (d - mean) * (d - mean) / static_cast<double>(intervals.size());
      worst_deviation = std::max(worst_deviation, std::abs(d - mean) / mean);
    }
    auto& r = ctx.report;
    r.results["particle_spacing"] = dp;
    r.results["s2_time_ms"] = s2_onset;
    r.results["rotations"] = fewest_rotations == static_cast<std::size_t>(-1) ? 0 : fewest_rotations;
    r.results["rotation_period_ms"] = intervals.empty() ? -1.0 : mean;
    r.results["rotation_period_sd_ms"] = intervals.empty() ? -1.0 : std::sqrt(variance);
    r.results["rotation_period_max_deviation"] = intervals.empty() ? -1.0 : worst_deviation;
  }

 private:
  SpiralWaveParameters p_;
};

}  // namespace

std::unique_ptr<Scene> make_spiral_wave_scene(SpiralWaveParameters p) {
  return std::make_unique<SpiralWaveScene>(std::move(p));
}

}  // namespace cardiosph
