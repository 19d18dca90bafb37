// The impact family's speed, as two tables (a standalone program, no Google Benchmark):
//  1. particle-steps per second of the updated-Lagrangian body on a basalt block (3D lattice, M4 at
//     h = 1.2 dx) stirred by a random velocity field: hydrodynamics alone, with strength (Tillotson,
//     Hooke in the Jaumann rate, von Mises), with strength and Grady-Kipp damage, and with variable h
//     (k-d tree) instead of the cell-linked list;
//  2. the Barnes-Hut gravity's cost and accuracy against the particle count: for n uniform random
//     particles in a unit ball (h = 1.2 mean spacing), the tree's build + force time (theta 0.5 with
//     quadrupole unless told), the direct summation's time and the tree's relative rms acceleration
//     error against direct summation, sampled on 1000 target particles. With --full-direct the whole
//     direct sum is timed up to n = 1e5; otherwise (and always beyond 1e5) the direct time is the
//     1000-target time scaled by n / 1000, i.e. extrapolated as n^2.
//   bench_impact [largest n of the gravity table, default 1000000] [--full-direct] [--leaf-size k]
//                [--theta t] [--steps-only | --gravity-only]

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <vector>

#ifdef CARDIOSPH_HAVE_NANOFLANN
#include <nanoflann.hpp>
#endif

#include "libsph/core/parallel.hpp"
#include "geometry/lattice.hpp"
#include "libsph/core/kd_tree.hpp"
#include "libsph/impact/gravity.hpp"
#include "libsph/impact/updated_lagrangian.hpp"

namespace {

using sph::Real;
using Vec3 = sph::Vec<3>;

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

// Particle-steps per second of one configuration of the body on a basalt block of about n particles.
double particle_steps_per_second(std::size_t n, bool strength, bool damage, bool variable_h, std::size_t& particles) {
  const auto& basalt = sph::tillotson_material("basalt").parameters;
  const Real dx = Real(0.001), side = dx * std::round(Real(std::cbrt(double(n))));
  auto block = geometry::lattice_box<3>("block", Vec3::Zero(), Vec3(side, side, side), dx);
  particles = block.n_particles();
  sph::UpdatedLagrangianBody<3>::Settings s;
  s.equation_of_state = basalt;
  s.smoothing_length = Real(1.2) * dx;
  if (variable_h) s.smoothing_length_factor = Real(1.2);
  if (strength) {
    s.shear_modulus = Real(22.7e9);
    s.yield_strength = Real(3.5e9);
  }
  if (damage) s.damage = sph::DamageSettings{{5e34, 8.5}, 1, Real(53e9)};
  sph::UpdatedLagrangianBody<3> body(block, s);
  auto rho = block.field(body.density_field());
  auto v = block.field(body.velocity_field());
  std::mt19937_64 engine(7);
  for (std::size_t i = 0; i < particles; ++i) {
    rho[i] = Real(basalt.reference_density);
    for (int d = 0; d < 3; ++d) v[i][d] = Real(20 * (double(engine() >> 11) * 0x1.0p-53 - 0.5));  // +-10 m/s
  }
  body.initialise();
  Real t = 0;
  auto step = [&] {
    const Real dt = body.stable_time_step();
    body.advance(t, dt);
    t += dt;
  };
  for (int k = 0; k < 2; ++k) step();  // warm the scratch storage
  const int steps = particles > 200000 ? 5 : 20;
  const auto start = std::chrono::steady_clock::now();
  for (int k = 0; k < steps; ++k) step();
  return double(particles) * steps / seconds_since(start);
}

#ifdef CARDIOSPH_HAVE_NANOFLANN
// The same radius search (every point's neighbours within 2.4 dx on a jittered 3D lattice, one
// thread, tree built anew) with Debian's nanoflann and with the library's k-d tree.
struct Cloud {
  const std::vector<Vec3>& points;
  std::size_t kdtree_get_point_count() const { return points.size(); }
  Real kdtree_get_pt(std::size_t i, std::size_t d) const { return points[i][int(d)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const { return false; }
};

void radius_search_against_nanoflann() {
  std::printf("radius search, 1 thread, all points within 2.4 dx (build + queries), seconds\n");
  std::printf("%9s %12s %12s %12s %8s\n", "points", "pairs", "nanoflann", "sph::KdTree", "ratio");
  for (const int side : {22, 46, 100}) {
    std::mt19937_64 engine(3);
    std::vector<Vec3> x;
    const Real dx = Real(1);
    for (int i = 0; i < side; ++i)
      for (int j = 0; j < side; ++j)
        for (int k = 0; k < side; ++k) {
          Vec3 p{Real(i), Real(j), Real(k)};
          for (int d = 0; d < 3; ++d) p[d] += Real(0.2) * (Real(double(engine() >> 11) * 0x1.0p-53) - Real(0.5));
          x.push_back(dx * p);
        }
    const Real radius = Real(2.4) * dx;
    sph::ThreadLimit one(1);
    std::size_t pairs_nano = 0, pairs_own = 0;
    auto start = std::chrono::steady_clock::now();
    {
      Cloud cloud{x};
      using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<Real, Cloud>, Cloud, 3>;
      Tree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(8));
      tree.buildIndex();
      std::vector<std::pair<unsigned, Real>> found;  // the adaptor's index type
      nanoflann::SearchParams params;
      params.sorted = false;
      for (const auto& p : x) pairs_nano += tree.radiusSearch(p.data(), radius * radius, found, params) - 1;
    }
    const double nano = seconds_since(start);
    start = std::chrono::steady_clock::now();
    {
      sph::KdTree<3> tree(x);
      std::vector<sph::Index> found;
      for (const auto& p : x) {
        tree.radius_query(p, radius, found);
        pairs_own += found.size() - 1;
      }
    }
    const double own = seconds_since(start);
    std::printf("%9zu %12zu %12.3f %12.3f %8.2f\n", x.size(), pairs_own, nano, own, own / nano);
    if (pairs_nano != pairs_own) std::printf("  (pair counts differ: nanoflann %zu)\n", pairs_nano);
    std::fflush(stdout);
  }
}
#endif

int main(int argc, char** argv) {
  std::size_t largest = 1000000;
  bool full_direct = false, steps_table = true, gravity_table = true;
  sph::GravitySettings settings;
  for (int k = 1; k < argc; ++k) {
    if (std::strcmp(argv[k], "--full-direct") == 0) full_direct = true;
    else if (std::strcmp(argv[k], "--leaf-size") == 0 && k + 1 < argc) settings.leaf_size = std::strtoull(argv[++k], nullptr, 10);
    else if (std::strcmp(argv[k], "--theta") == 0 && k + 1 < argc) settings.theta = static_cast<Real>(std::strtod(argv[++k], nullptr));
    else if (std::strcmp(argv[k], "--steps-only") == 0) gravity_table = false;
    else if (std::strcmp(argv[k], "--gravity-only") == 0) steps_table = false;
    else largest = std::strtoull(argv[k], nullptr, 10);
  }
  if (steps_table) {
    std::printf("updated-Lagrangian body, basalt block, threads %zu: million particle-steps per second\n", sph::active_thread_count());
    std::printf("%9s %12s %12s %16s %16s\n", "particles", "hydro", "strength", "strength+damage", "hydro, k-d tree");
    for (const std::size_t n : {10000ul, 100000ul}) {
      std::size_t particles = 0;
      const double hydro = particle_steps_per_second(n, false, false, false, particles);
      const double strength = particle_steps_per_second(n, true, false, false, particles);
      const double damage = particle_steps_per_second(n, true, true, false, particles);
      const double kd = particle_steps_per_second(n, false, false, true, particles);
      std::printf("%9zu %12.3f %12.3f %16.3f %16.3f\n", particles, 1e-6 * hydro, 1e-6 * strength, 1e-6 * damage, 1e-6 * kd);
      std::fflush(stdout);
    }
  }
#ifdef CARDIOSPH_HAVE_NANOFLANN
  if (steps_table) radius_search_against_nanoflann();
#endif
  if (!gravity_table) return 0;
  std::printf("threads %zu; theta %g, quadrupole, leaf size %zu\n", sph::active_thread_count(), double(settings.theta), settings.leaf_size);
  std::printf("%9s %10s %10s %12s %10s %12s %10s %10s %14s\n", "n", "build+BH s", "2nd call s", "us/particle", "us/p/log2n",
              "direct s", "(how)", "rms error", "multipoles,pairs");
  for (std::size_t n = 10000; n <= largest; n *= 10) {
    std::mt19937_64 engine(42);
    auto uniform = [&] { return static_cast<Real>(static_cast<double>(engine() >> 11) * 0x1.0p-53); };
    std::vector<Vec3> x;
    x.reserve(n);
    while (x.size() < n) {
      const Vec3 p(2 * uniform() - 1, 2 * uniform() - 1, 2 * uniform() - 1);
      if (p.squaredNorm() <= 1) x.push_back(p);
    }
    const std::vector<Real> m(n, Real(1.0 / n)), h(n, Real(1.2 * std::cbrt(4.0 / 3.0 * sph::pi / n)));
    std::vector<Vec3> a(n);
    sph::BarnesHutGravity gravity(settings);
    auto start = std::chrono::steady_clock::now();
    gravity.compute(x, m, h, a, {});
    const double first = seconds_since(start);
    start = std::chrono::steady_clock::now();
    gravity.compute(x, m, h, a, {});
    const double second = seconds_since(start);
    const auto s = gravity.statistics();

    std::vector<std::size_t> targets(1000);
    for (std::size_t t = 0; t < targets.size(); ++t) targets[t] = t * (n / targets.size());
    std::vector<Vec3> a_direct(targets.size());
    start = std::chrono::steady_clock::now();
    sph::direct_gravity(x, m, h, 1, targets, a_direct, {});
    double direct = seconds_since(start) * double(n) / double(targets.size());
    const char* how = "n^2 extrap";
    if (full_direct && n <= 100000) {
      std::vector<Vec3> all(n);
      start = std::chrono::steady_clock::now();
      sph::direct_gravity(x, m, h, 1, all, {});
      direct = seconds_since(start);
      how = "measured";
    }
    double num = 0, den = 0;
    for (std::size_t t = 0; t < targets.size(); ++t) {
      num += (a[targets[t]] - a_direct[t]).squaredNorm();
      den += a_direct[t].squaredNorm();
    }
    const double per_particle = 1e6 * second / double(n);
    std::printf("%9zu %10.3f %10.3f %12.3f %10.4f %12.2f %10s %10.3e %7.0f,%5.0f\n", n, first, second, per_particle,
                per_particle / std::log2(double(n)), direct, how, std::sqrt(num / den), s.multipoles_per_particle, s.pairs_per_particle);
    std::fflush(stdout);
  }
}
