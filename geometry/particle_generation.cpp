#include "geometry/particle_generation.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <variant>

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Spatial_sort_traits_adapter_3.h>
#include <CGAL/hilbert_sort.h>
#include <CGAL/property_map.h>
#include <Eigen/Eigenvalues>

#include "libsph/core/cell_linked_list.hpp"
#include "libsph/core/kernels.hpp"
#include "libsph/core/parallel.hpp"

namespace geometry {
namespace {

using Clock = std::chrono::steady_clock;

// The order of lattice nodes along a Hilbert curve (CGAL's, cut at the middle of each box: on a
// lattice it depends on the node indices only). Particles near on the curve are near in space, so
// a run of consecutive particles (a block of cells that are reacted together, a cache line of a
// neighbour loop, the particles a rank owns) is compact.
std::vector<std::size_t> hilbert_order(const std::vector<std::array<long, 3>>& nodes) {
  using Kernel = CGAL::Simple_cartesian<double>;
  std::vector<Kernel::Point_3> points;
  points.reserve(nodes.size());
  for (const auto& [i, j, k] : nodes) points.emplace_back(double(i), double(j), double(k));
  std::vector<std::size_t> order(nodes.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  using Traits = CGAL::Spatial_sort_traits_adapter_3<Kernel, CGAL::Pointer_property_map<Kernel::Point_3>::type>;
  CGAL::hilbert_sort(order.begin(), order.end(), Traits(CGAL::make_property_map(points)), CGAL::Hilbert_sort_middle_policy());
  return order;
}

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// Signed distance on the nodes x_ijk = origin + spacing (i, j, k), with trilinear interpolation.
class LevelSet {
 public:
  static constexpr long coarsening = 4;

  LevelSet(const Shape& shape, const Vec3& origin, double spacing, const std::array<long, 3>& nodes)
      : origin_(origin), spacing_(spacing) {
    // Round the node counts up so that the coarse grid (every 4th node) covers the fine one.
    for (int d = 0; d < 3; ++d) n_[d] = ((std::max(nodes[d], 2L) - 1 + coarsening - 1) / coarsening) * coarsening + 1;
    values_.assign(static_cast<std::size_t>(n_[0] * n_[1] * n_[2]), 0.0);
    // Exact values on the coarse nodes.
    std::array<long, 3> nc{};
    for (int d = 0; d < 3; ++d) nc[d] = (n_[d] - 1) / coarsening + 1;
    std::vector<double> coarse(static_cast<std::size_t>(nc[0] * nc[1] * nc[2]));
    sph::parallel_for(coarse.size(), [&](std::size_t c) {
      const long i = static_cast<long>(c) % nc[0], j = (static_cast<long>(c) / nc[0]) % nc[1],
                 k = static_cast<long>(c) / (nc[0] * nc[1]);
      coarse[c] = shape.signed_distance(node_position(i * coarsening, j * coarsening, k * coarsening));
    });
    auto coarse_at = [&](long i, long j, long k) { return coarse[static_cast<std::size_t>(i + nc[0] * (j + nc[1] * k))]; };
    // A coarse cell whose corners all lie farther from the surface than its diagonal is wholly on
    // one side (the distance is 1-Lipschitz); its fine nodes take the trilinear coarse value, which
    // keeps the sign and stays farther from the surface than the kernel reaches. Elsewhere exact.
    const double far = std::sqrt(3.0) * coarsening * spacing;
    sph::parallel_for(values_.size(), [&](std::size_t n) {
      const long i = static_cast<long>(n) % n_[0], j = (static_cast<long>(n) / n_[0]) % n_[1],
                 k = static_cast<long>(n) / (n_[0] * n_[1]);
      const long ci = std::min(i / coarsening, nc[0] - 2), cj = std::min(j / coarsening, nc[1] - 2),
                 ck = std::min(k / coarsening, nc[2] - 2);
      double smallest = std::numeric_limits<double>::infinity();
      double corner[2][2][2];
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
          for (int c = 0; c < 2; ++c) {
            corner[a][b][c] = coarse_at(ci + a, cj + b, ck + c);
            smallest = std::min(smallest, std::abs(corner[a][b][c]));
          }
      if (smallest > far) {
        const double fx = double(i - ci * coarsening) / coarsening, fy = double(j - cj * coarsening) / coarsening,
                     fz = double(k - ck * coarsening) / coarsening;
        values_[n] = trilinear(corner, fx, fy, fz);
      } else {
        values_[n] = shape.signed_distance(node_position(i, j, k));
      }
    });
  }

  Vec3 node_position(long i, long j, long k) const { return origin_ + spacing_ * Vec3(double(i), double(j), double(k)); }
  double node(long i, long j, long k) const {
    i = std::clamp(i, 0L, n_[0] - 1);
    j = std::clamp(j, 0L, n_[1] - 1);
    k = std::clamp(k, 0L, n_[2] - 1);
    return values_[static_cast<std::size_t>(i + n_[0] * (j + n_[1] * k))];
  }
  const std::array<long, 3>& nodes() const { return n_; }
  const Vec3& origin() const { return origin_; }
  double spacing() const { return spacing_; }

  double distance(const Vec3& p) const {
    long i, j, k;
    double fx, fy, fz;
    locate(p, i, j, k, fx, fy, fz);
    double corner[2][2][2];
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        for (int c = 0; c < 2; ++c) corner[a][b][c] = node(i + a, j + b, k + c);
    return trilinear(corner, fx, fy, fz);
  }

  /// Trilinear interpolation of the nodal central-difference gradients, normalised.
  Vec3 normal(const Vec3& p) const {
    long i, j, k;
    double fx, fy, fz;
    locate(p, i, j, k, fx, fy, fz);
    Vec3 g = Vec3::Zero();
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        for (int c = 0; c < 2; ++c) {
          const long x = i + a, y = j + b, z = k + c;
          const Vec3 gradient(node(x + 1, y, z) - node(x - 1, y, z), node(x, y + 1, z) - node(x, y - 1, z),
                              node(x, y, z + 1) - node(x, y, z - 1));
          g += (a ? fx : 1 - fx) * (b ? fy : 1 - fy) * (c ? fz : 1 - fz) * gradient;
        }
    const double norm = g.norm();
    return norm > 0 ? Vec3(g / norm) : Vec3::UnitZ();
  }

 private:
  static double trilinear(const double (&v)[2][2][2], double fx, double fy, double fz) {
    const double x00 = v[0][0][0] + fx * (v[1][0][0] - v[0][0][0]), x10 = v[0][1][0] + fx * (v[1][1][0] - v[0][1][0]);
    const double x01 = v[0][0][1] + fx * (v[1][0][1] - v[0][0][1]), x11 = v[0][1][1] + fx * (v[1][1][1] - v[0][1][1]);
    const double y0 = x00 + fy * (x10 - x00), y1 = x01 + fy * (x11 - x01);
    return y0 + fz * (y1 - y0);
  }
  void locate(const Vec3& p, long& i, long& j, long& k, double& fx, double& fy, double& fz) const {
    const Vec3 s = (p - origin_) / spacing_;
    auto cell = [](double x, long n, long& c, double& f) {
      x = std::clamp(x, 0.0, double(n - 1));
      c = std::min(static_cast<long>(std::floor(x)), n - 2);
      f = x - double(c);
    };
    cell(s.x(), n_[0], i, fx);
    cell(s.y(), n_[1], j, fy);
    cell(s.z(), n_[2], k, fz);
  }

  Vec3 origin_;
  double spacing_;
  std::array<long, 3> n_{};
  std::vector<double> values_;
};

// The level-set nodes that can lie in the kernel support of a particle outside the shape: those
// whose cell is partly outside, H = clamp(1/2 + phi / dp, 0, 1) > 0 (H = 1 for a face parallel to
// the lattice at phi = dp/2, smooth across curved surfaces, edges and corners). Each stands for a
// cell of volume dp^3, of which the fraction H is outside. Only nodes closer to the surface than
// `reach` are kept: a particle, inside, cannot see the others.
struct OutsideNodes {
  std::vector<Vec3> position;
  std::vector<double> weight;                 ///< H dp^3
  std::vector<std::uint32_t> index_of_node;   ///< node -> index here, or `none`
  static constexpr std::uint32_t none = ~std::uint32_t(0);

  OutsideNodes(const LevelSet& level_set, double reach) {
    const double dp = level_set.spacing();
    const auto& n = level_set.nodes();
    const std::size_t total = static_cast<std::size_t>(n[0] * n[1] * n[2]);
    if (total >= std::size_t(none))
      throw std::invalid_argument("particle generation: " + std::to_string(total) + " level-set nodes are too many");
    index_of_node.assign(total, none);
    for (long k = 0; k < n[2]; ++k)
      for (long j = 0; j < n[1]; ++j)
        for (long i = 0; i < n[0]; ++i) {
          const double phi = level_set.node(i, j, k);
          const double outside = std::clamp(0.5 + phi / dp, 0.0, 1.0);
          if (outside == 0 || phi > reach) continue;
          index_of_node[static_cast<std::size_t>(i + n[0] * (j + n[1] * k))] = static_cast<std::uint32_t>(position.size());
          position.push_back(level_set.node_position(i, j, k));
          weight.push_back(outside * (dp * dp * dp));
        }
  }
};

// Verlet lists: for each particle, the particles and the outside nodes within support + skin of its
// position at the last build, in increasing index. While no particle has moved more than skin / 2
// since, they hold every particle and node within the support (two particles approach by at most
// skin), so the sums below, which test the exact distance, have the same terms in the same order as
// with lists built anew: the result does not depend on the skin or on when the lists were rebuilt.
// Verlet 1967, Phys. Rev. 159:98; Allen & Tildesley, Computer Simulation of Liquids, sec. 5.3.
struct SkinLists {
  double skin = 0;
  std::vector<Vec3> built_at;                   ///< positions at the last build
  std::vector<std::size_t> pair_offsets, node_offsets;
  std::vector<sph::Index> pairs;                ///< particle neighbours j of row i
  std::vector<std::uint32_t> nodes;             ///< OutsideNodes indices of row i
  sph::CellLinkedList<3> cells;
  long builds = 0;

  void build(const std::vector<sph::Vec<3>>& x, const std::vector<Vec3>& positions, const LevelSet& level_set,
             const OutsideNodes& outside, double support) {
    const std::size_t n = x.size();
    const double dp = level_set.spacing();
    const auto radius = sph::Real(support + skin);
    // Kept: squared distance below radius^2, widened by 64 epsilon so that rounding never drops a
    // pair that the residual would count.
    const auto radius2 = radius * radius * (1 + 64 * std::numeric_limits<sph::Real>::epsilon());
    const double node_radius2 = (support + skin) * (support + skin) * (1 + 64 * std::numeric_limits<double>::epsilon());
    built_at = positions;
    ++builds;
    cells.rebuild(x, radius);
    auto visit_pairs = [&](std::size_t i, auto&& keep) {
      cells.for_each_candidate(x[i], [&](sph::Index j) {
        if (j != i && (x[i] - x[j]).squaredNorm() < radius2) keep(j);
      });
    };
    const auto& n_nodes = level_set.nodes();
    // A node within support + skin of x lies within (support + skin) / dp + 1/2 nodes of x's
    // rounded node along each axis.
    const long reach = static_cast<long>(std::floor((support + skin) / dp + 0.5));
    auto visit_nodes = [&](std::size_t i, auto&& keep) {
      const Vec3 s = (positions[i] - level_set.origin()) / dp;
      const long ci = std::lround(s.x()), cj = std::lround(s.y()), ck = std::lround(s.z());
      for (long k = std::max(ck - reach, 0L); k <= std::min(ck + reach, n_nodes[2] - 1); ++k)
        for (long j = std::max(cj - reach, 0L); j <= std::min(cj + reach, n_nodes[1] - 1); ++j)
          for (long l = std::max(ci - reach, 0L); l <= std::min(ci + reach, n_nodes[0] - 1); ++l) {
            const auto node = static_cast<std::size_t>(l + n_nodes[0] * (j + n_nodes[1] * k));
            const std::uint32_t o = outside.index_of_node[node];
            if (o != OutsideNodes::none && (positions[i] - outside.position[o]).squaredNorm() < node_radius2) keep(o);
          }
    };
    // Compressed rows, collected in fixed blocks of particles (each row sorted when asked) and joined
    // in block order: the same lists for any thread count, with one search instead of the count and
    // fill passes of sph::NeighbourList. Node rows come out in increasing node index, which is
    // increasing OutsideNodes index.
    auto fill = [&](auto&& visit, std::vector<std::size_t>& offsets, auto& entries, bool sort) {
      constexpr std::size_t block = 256;
      const std::size_t n_blocks = (n + block - 1) / block;
      std::vector<std::vector<std::uint32_t>> parts(n_blocks);
      offsets.resize(n + 1);
      sph::parallel_for(n_blocks, [&](std::size_t b) {
        auto& part = parts[b];
        for (std::size_t i = b * block; i < std::min(n, (b + 1) * block); ++i) {
          const std::size_t start = part.size();
          visit(i, [&](std::uint32_t e) { part.push_back(e); });
          if (sort) std::sort(part.begin() + std::ptrdiff_t(start), part.end());
          offsets[i + 1] = part.size() - start;
        }
      });
      offsets[0] = 0;
      for (std::size_t i = 0; i < n; ++i) offsets[i + 1] += offsets[i];
      entries.resize(offsets[n]);
      sph::parallel_for(n_blocks, [&](std::size_t b) {
        std::copy(parts[b].begin(), parts[b].end(), entries.begin() + std::ptrdiff_t(offsets[b * block]));
      });
    };
    fill(visit_pairs, pair_offsets, pairs, true);
    fill(visit_nodes, node_offsets, nodes, false);
  }
  /// The largest displacement since the last build; the lists are stale once twice it exceeds the skin.
  double largest_displacement(const std::vector<Vec3>& positions) const {
    return sph::parallel_max(positions.size(), 0.0, [&](std::size_t i) { return (positions[i] - built_at[i]).norm(); });
  }
};

template <class Kernel>
void relax_and_measure(const Kernel&, const LevelSet& level_set, const ParticleGenerationSettings& settings,
                       BodyParticles& body) {
  const double dp = settings.spacing;
  const double h = settings.smoothing_ratio * dp;
  const auto hr = sph::Real(h);
  const double support = Kernel::support_radius(hr);
  const double v0 = dp * dp * dp;
  const std::size_t n = body.size();
  std::vector<sph::Vec<3>> x(n);
  std::vector<Vec3> residual(n);
  SkinLists lists;
  lists.skin = settings.neighbour_skin * dp;
  // Outside nodes a particle can reach: within support + skin of the surface, with 2 dp for the
  // level set's interpolation (a particle may sit a little outside it).
  const OutsideNodes outside(level_set, support + lists.skin + 2 * dp);

  auto refresh = [&] {
    sph::parallel_for(n, [&](std::size_t i) {
      x[i] = body.positions[i].cast<sph::Real>();
      body.depth[i] = -level_set.distance(body.positions[i]);
    });
    if (lists.builds == 0 || 2 * lists.largest_displacement(body.positions) > lists.skin)
      lists.build(x, body.positions, level_set, outside, support);
  };
  // r_i and, alongside, the kernel sum sum_j W_ij (for the volumes). The outside part integrates
  // the kernel over the outside nodes in the support (only for particles near the surface). With
  // W = a(h) w(q) and dW/dr = a(h) / h w'(q), q = r / h: one division per pair.
  const double value_factor = double(Kernel::normalisation(hr));
  const double gradient_factor = value_factor / h;
  const double inverse_h = 1 / h;
  const double support2 = support * support;
  auto compute_residual = [&](std::vector<double>* kernel_sum) {
    const std::size_t* pair_offsets = lists.pair_offsets.data();
    const sph::Index* pairs = lists.pairs.data();
    const std::size_t* node_offsets = lists.node_offsets.data();
    const std::uint32_t* nodes = lists.nodes.data();
    const sph::Vec<3>* xs = x.data();
    const Vec3* node_position = outside.position.data();
    const double* node_weight = outside.weight.data();
    auto row = [&](std::size_t i, auto with_sum) {
      Vec3 r = Vec3::Zero();
      double w = 0;
      const sph::Vec<3> xi = xs[i];
      for (std::size_t k = pair_offsets[i]; k < pair_offsets[i + 1]; ++k) {
        const Vec3 xij = (xi - xs[pairs[k]]).template cast<double>();
        const double distance2 = xij.squaredNorm();
        if (distance2 >= support2 || distance2 <= 0) continue;
        const double distance = std::sqrt(distance2);
        const auto q = sph::Real(distance * inverse_h);
        r += (v0 * gradient_factor * double(Kernel::shape_derivative(q)) / distance) * xij;
        if constexpr (with_sum) w += value_factor * double(Kernel::shape(q));
      }
      if (body.depth[i] < support + 0.5 * dp) {
        const Vec3 p = body.positions[i];
        double mass = 0;
        for (std::size_t k = node_offsets[i]; k < node_offsets[i + 1]; ++k) {
          const std::uint32_t o = nodes[k];
          const Vec3 xy = p - node_position[o];
          const double distance2 = xy.squaredNorm();
          if (distance2 >= support2 || distance2 <= 0) continue;
          const double distance = std::sqrt(distance2);
          const auto q = sph::Real(distance * inverse_h);
          r += (node_weight[o] * gradient_factor * double(Kernel::shape_derivative(q)) / distance) * xy;
          if constexpr (with_sum) mass += node_weight[o] * value_factor * double(Kernel::shape(q));
        }
        w += mass / v0;
      }
      residual[i] = r;
      if constexpr (with_sum) (*kernel_sum)[i] = w;
      return r.squaredNorm() * h * h;
    };
    return std::sqrt(sph::parallel_sum(n, 0.0, [&](std::size_t i) {
      return kernel_sum ? row(i, std::true_type{}) : row(i, std::false_type{});
    }) / double(n));
  };

  const auto relax_start = Clock::now();
  refresh();
  body.residual_initial = compute_residual(nullptr);
  body.residual_final = body.residual_initial;
  const double max_step = 0.1 * dp;
  const double min_depth = 0.1 * dp;
  for (long step = 0; step < settings.relaxation_steps; ++step) {
    const double largest = sph::parallel_max(n, 0.0, [&](std::size_t i) {
      Vec3 move = -settings.relaxation_gain * h * h * residual[i];
      if (move.norm() > max_step) move *= max_step / move.norm();
      Vec3 p = body.positions[i] + move;
      // Keep the particle inside; the outside support already holds it near depth dp/2.
      const double depth = -level_set.distance(p);
      if (depth < min_depth) p -= (min_depth - depth) * level_set.normal(p);
      const double moved = (p - body.positions[i]).norm();
      body.positions[i] = p;
      return moved;
    });
    refresh();
    body.residual_final = compute_residual(nullptr);
    body.relaxation_steps_done = step + 1;
    if (settings.on_step) settings.on_step(step + 1, body.residual_final);
    if (largest < settings.converged_displacement * dp) break;
  }
  body.neighbour_builds = lists.builds;
  body.relaxation_seconds = seconds_since(relax_start);

  // Volumes from the number density, with the kernel mass missing beyond the surface added back.
  const auto volume_start = Clock::now();
  std::vector<double> kernel_sum(n);
  body.residual_final = compute_residual(&kernel_sum);
  // The kernel sum of a perfect lattice differs from 1 / dp^3 by the discrete normalisation error
  // of the kernel (about 1 % for Wendland C2 at h = 1.3 dp); measure it so that the lattice volume
  // is exactly dp^3.
  const double w0 = double(Kernel::value(0, hr));
  double lattice_sum = w0;
  const long reach = static_cast<long>(std::ceil(support / dp));
  for (long k = -reach; k <= reach; ++k)
    for (long j = -reach; j <= reach; ++j)
      for (long i = -reach; i <= reach; ++i) {
        const double r = dp * std::sqrt(double(i * i + j * j + k * k));
        if (r > 0 && r < support) lattice_sum += double(Kernel::value(sph::Real(r), hr));
      }
  sph::parallel_for(n, [&](std::size_t i) {
    body.normals[i] = level_set.normal(body.positions[i]);
    body.volumes[i] = v0 * lattice_sum / (kernel_sum[i] + w0);
    body.surface[i] = body.depth[i] < dp ? 1 : 0;
  });
  body.volume_seconds = seconds_since(volume_start);
}

// Nearest-neighbour distances over dp (min, mean, max, std / mean) by a cell list of cell 2 dp; a
// particle without a neighbour within 2 dp counts 2.
void measure_spacing(BodyParticles& body, double dp) {
  const std::size_t n = body.size();
  std::vector<sph::Vec<3>> x(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = body.positions[i].cast<sph::Real>();
  const sph::CellLinkedList<3> cells(x, sph::Real(2 * dp));
  std::vector<double> nearest(n);
  sph::parallel_for(n, [&](std::size_t i) {
    double d = 2 * dp;
    cells.for_each_candidate(x[i], [&](sph::Index j) {
      if (j != i) d = std::min(d, (body.positions[i] - body.positions[j]).norm());
    });
    nearest[i] = d / dp;
  });
  double sum = 0, sum2 = 0;
  body.spacing_min_ratio = std::numeric_limits<double>::infinity();
  body.spacing_max_ratio = 0;
  for (double d : nearest) {
    sum += d;
    sum2 += d * d;
    body.spacing_min_ratio = std::min(body.spacing_min_ratio, d);
    body.spacing_max_ratio = std::max(body.spacing_max_ratio, d);
  }
  body.spacing_mean_ratio = sum / double(n);
  body.spacing_spread = std::sqrt(std::max(0.0, sum2 / double(n) - body.spacing_mean_ratio * body.spacing_mean_ratio)) /
                        body.spacing_mean_ratio;
}

// Neighbour counts within the support R = 2 h, the conditioning of each neighbourhood's second
// moment sum_j w_j r_ij r_ij^T with w = (1 - r/R)^4 (1 + 4 r/R), and the thin-feature flags.
void measure_neighbourhoods(BodyParticles& body, double dp, const ParticleGenerationSettings& settings) {
  const std::size_t n = body.size();
  const double support = 2 * settings.smoothing_ratio * dp;
  std::vector<sph::Vec<3>> x(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = body.positions[i].cast<sph::Real>();
  const sph::CellLinkedList<3> cells(x, sph::Real(support));
  std::vector<std::size_t> count(n);
  std::vector<double> conditioning(n), nearest(n);
  sph::parallel_for(n, [&](std::size_t i) {
    Eigen::Matrix3d moment = Eigen::Matrix3d::Zero();
    std::size_t k = 0;
    double d_min = support;
    cells.for_each_candidate(x[i], [&](sph::Index j) {
      if (j == i) return;
      const Vec3 r = body.positions[j] - body.positions[i];
      const double d = r.norm();
      if (d >= support) return;
      ++k;
      d_min = std::min(d_min, d);
      const double q = d / support;
      moment += std::pow(1 - q, 4) * (1 + 4 * q) * r * r.transpose();
    });
    count[i] = k;
    nearest[i] = d_min;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(moment, Eigen::EigenvaluesOnly);
    const double largest = eigen.eigenvalues()(2);
    conditioning[i] = largest > 0 ? std::max(0.0, eigen.eigenvalues()(0)) / largest : 0;
  });
  std::vector<std::size_t> sorted = count;
  std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(n / 2), sorted.end());
  body.neighbours_median = sorted[n / 2];
  body.neighbours_min = *std::min_element(count.begin(), count.end());
  body.conditioning_min = *std::min_element(conditioning.begin(), conditioning.end());
  body.thin.clear();
  body.thin_description.clear();
  std::size_t worst = n;
  double worst_score = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    const double neighbours = double(count[i]) / std::max<double>(1, double(body.neighbours_median));
    const bool thin = neighbours < settings.min_neighbour_fraction || conditioning[i] < settings.min_conditioning ||
                      nearest[i] < settings.min_distance_ratio * dp;
    if (!thin) continue;
    body.thin.push_back(i);
    // The worst: the smallest of the three measures, each over its threshold.
    const double score = std::min({neighbours / settings.min_neighbour_fraction, conditioning[i] / settings.min_conditioning,
                                   nearest[i] / (settings.min_distance_ratio * dp)});
    if (score < worst_score) {
      worst_score = score;
      worst = i;
    }
  }
  if (worst == n) return;
  // Local thickness: twice the largest depth of the thin particles within the support of the worst.
  double depth = body.depth[worst];
  for (std::size_t i : body.thin)
    if ((body.positions[i] - body.positions[worst]).norm() < support) depth = std::max(depth, body.depth[i]);
  const Vec3& p = body.positions[worst];
  char text[400];
  std::snprintf(text, sizeof text,
                "at (%.3g, %.3g, %.3g): %zu neighbours (median %zu), nearest %.2f dp, conditioning %.3f; the feature is "
                "about %.3g thick there, so a spacing of %.3g or less resolves it",
                p.x(), p.y(), p.z(), count[worst], body.neighbours_median, nearest[worst] / dp, conditioning[worst],
                2 * depth, 2 * depth / 3);
  body.thin_description = text;
}

}  // namespace

void require_no_thin_features(const BodyParticles& body, double spacing, const std::string& what) {
  if (body.thin.empty()) return;
  throw std::invalid_argument(what + ": " + std::to_string(body.thin.size()) + " particle" +
                              (body.thin.size() == 1 ? "" : "s") + " at spacing " + std::to_string(spacing) +
                              " lie in features thinner than the spacing (too few neighbours, a flat neighbourhood or "
                              "a neighbour closer than half the spacing); the worst " +
                              body.thin_description);
}

BodyParticles generate_particles(const Shape& shape, const ParticleGenerationSettings& settings) {
  const double dp = settings.spacing;
  if (!(dp > 0)) throw std::invalid_argument("particle generation: spacing must be positive");
  if (!(settings.smoothing_ratio > 0)) throw std::invalid_argument("particle generation: smoothing ratio must be positive");
  const Aabb box = shape.bounding_box();
  if (!box.extent().allFinite() || box.extent().minCoeff() <= 0)
    throw std::invalid_argument("particle generation: " + shape.describe() + " is unbounded or empty");
  const double cells = (box.extent() / dp).prod();
  if (cells > 4e9)
    throw std::invalid_argument("particle generation: spacing " + std::to_string(dp) + " gives about " +
                                std::to_string(cells) + " lattice points for " + shape.describe() +
                                "; check the spacing and the mesh units (scale)");

  BodyParticles body;
  // Level set on lattice nodes: cell centres of a grid aligned with the box, padded by 3 cells.
  const auto ls_start = Clock::now();
  const Vec3 origin = box.lower - Vec3::Constant(2.5 * dp);
  std::array<long, 3> nodes{};
  for (int d = 0; d < 3; ++d) nodes[d] = static_cast<long>(std::ceil(box.extent()[d] / dp)) + 6;
  const LevelSet level_set(shape, origin, dp, nodes);
  body.level_set_seconds = seconds_since(ls_start);

  // Lattice: the nodes inside, in the order of a Hilbert curve through the lattice.
  const auto lattice_start = Clock::now();
  const auto& n = level_set.nodes();
  std::vector<std::array<long, 3>> inside;
  for (long k = 0; k < n[2]; ++k)
    for (long j = 0; j < n[1]; ++j)
      for (long i = 0; i < n[0]; ++i)
        if (level_set.node(i, j, k) < 0) inside.push_back({i, j, k});
  if (inside.empty())
    throw std::invalid_argument("particle generation: no particle of spacing " + std::to_string(dp) + " fits inside " +
                                shape.describe());
  for (std::size_t p : hilbert_order(inside)) {
    const auto [i, j, k] = inside[p];
    body.positions.push_back(level_set.node_position(i, j, k));
  }
  const std::size_t count = body.positions.size();
  body.volumes.assign(count, dp * dp * dp);
  body.depth.assign(count, 0.0);
  body.normals.assign(count, Vec3::UnitZ());
  body.surface.assign(count, 0);
  body.lattice_seconds = seconds_since(lattice_start);

  std::visit([&](const auto& kernel) { relax_and_measure(kernel, level_set, settings, body); },
             sph::make_kernel<3>(settings.kernel));

  body.shape_volume = shape_volume(shape, 0.25 * dp);
  double sum = 0, sum2 = 0;
  body.volume_min_ratio = std::numeric_limits<double>::infinity();
  body.volume_max_ratio = 0;
  for (double v : body.volumes) {
    sum += v;
    sum2 += v * v;
    body.volume_min_ratio = std::min(body.volume_min_ratio, v / (dp * dp * dp));
    body.volume_max_ratio = std::max(body.volume_max_ratio, v / (dp * dp * dp));
  }
  const double mean = sum / double(count);
  body.volume_relative_error = (sum - body.shape_volume) / body.shape_volume;
  body.density_spread = std::sqrt(std::max(0.0, sum2 / double(count) - mean * mean)) / mean;
  measure_spacing(body, dp);
  measure_neighbourhoods(body, dp, settings);
  return body;
}

}  // namespace geometry
