#include "libsph/impact/gravity.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

#include "libsph/core/parallel.hpp"

namespace sph {

namespace {

std::string number(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.17g", value);
  return buffer;
}

// The checks every entry point shares: sizes, finite positions, m >= 0, h > 0.
void check_particles(const char* where, std::span<const Vec<3>> x, std::span<const Real> m, std::span<const Real> h) {
  const std::string prefix = std::string(where) + ": ";
  if (m.size() != x.size())
    throw std::invalid_argument(prefix + "m has " + std::to_string(m.size()) + " entries but x has " + std::to_string(x.size()));
  if (h.size() != x.size())
    throw std::invalid_argument(prefix + "h has " + std::to_string(h.size()) + " entries but x has " + std::to_string(x.size()));
  if (x.size() >= std::numeric_limits<std::uint32_t>::max())
    throw std::invalid_argument(prefix + std::to_string(x.size()) + " particles exceed the 32-bit particle index");
  const std::size_t n = x.size();
  if (const std::size_t i = first_index_where(n, [&](std::size_t k) { return !x[k].allFinite(); }); i < n)
    throw std::invalid_argument(prefix + "position x[" + std::to_string(i) + "] is not finite");
  if (const std::size_t i = first_index_where(n, [&](std::size_t k) { return !(m[k] >= 0 && std::isfinite(m[k])); }); i < n)
    throw std::invalid_argument(prefix + "mass m[" + std::to_string(i) + "] = " + number(m[i]) + " must be finite and >= 0");
  if (const std::size_t i = first_index_where(n, [&](std::size_t k) { return !(h[k] > 0 && std::isfinite(h[k])); }); i < n)
    throw std::invalid_argument(prefix + "smoothing length h[" + std::to_string(i) + "] = " + number(h[i]) +
                                " must be finite and > 0");
}

// One softened pair: adds m_j phi'_ij / r_ij (x_j - x_i) to acc and m_j phi_ij to pot (unit G).
// Beyond 2 max(h_i, h_j) both halves of the symmetric average are the Newtonian values.
inline void add_pair(const Vec<3>& d, Real m_j, Real h_i, Real h_j, Vec<3>& acc, Real& pot) {
  const Real r2 = d.squaredNorm();
  const Real h_max = std::max(h_i, h_j);
  if (r2 >= Real(4) * h_max * h_max) {
    const Real r_inv = Real(1) / std::sqrt(r2);
    acc += (m_j * r_inv * r_inv * r_inv) * d;
    pot -= m_j * r_inv;
    return;
  }
  const Real r = std::sqrt(r2);
  const Real g = Real(0.5) * (m4_softened_force_over_r(r, h_i) + m4_softened_force_over_r(r, h_j));
  acc += (m_j * g) * d;
  pot += m_j * Real(0.5) * (m4_softened_potential(r, h_i) + m4_softened_potential(r, h_j));
}

// Traceless quadrupole of mass `mass` at displacement d from the expansion centre, added to q.
inline void add_point_quadrupole(std::array<Real, 6>& q, Real mass, const Vec<3>& d) {
  const Real d2 = d.squaredNorm();
  q[0] += mass * (Real(3) * d[0] * d[0] - d2);
  q[1] += mass * (Real(3) * d[1] * d[1] - d2);
  q[2] += mass * (Real(3) * d[2] * d[2] - d2);
  q[3] += mass * Real(3) * d[0] * d[1];
  q[4] += mass * Real(3) * d[0] * d[2];
  q[5] += mass * Real(3) * d[1] * d[2];
}

}  // namespace

void GravitySettings::check() const {
  if (!std::isfinite(G) || !(G > 0))
    throw std::invalid_argument("gravity settings: G = " + number(G) + " must be finite and > 0");
  if (!std::isfinite(theta))
    throw std::invalid_argument("gravity settings: opening angle theta = " + number(theta) + " must be finite, in (0, 1]");
  if (!(theta > 0))
    throw std::invalid_argument("gravity settings: opening angle theta = " + number(theta) +
                                " must be > 0 (theta = 0 would be direct summation: use direct_gravity)");
  if (theta > 1)
    throw std::invalid_argument("gravity settings: opening angle theta = " + number(theta) +
                                " must be <= 1 (beyond, the multipole series of a node may not converge)");
  if (leaf_size < 1) throw std::invalid_argument("gravity settings: leaf_size = 0 must be >= 1");
}

BarnesHutGravity::BarnesHutGravity(GravitySettings settings) : settings_(settings) { settings_.check(); }

void BarnesHutGravity::leaf_moments(Node& node) const {
  Real mass = 0;
  Vec<3> weighted = Vec<3>::Zero();
  Real h_max = 0;
  for (std::uint32_t k = node.begin; k < node.end; ++k) {
    mass += mass_[k];
    weighted += mass_[k] * items_[k].x;
    h_max = std::max(h_max, h_[k]);
  }
  node.mass = mass;
  node.h_max = h_max;
  node.centre_of_mass = mass > 0 ? Vec<3>(weighted / mass) : Vec<3>(Real(0.5) * (node.lower + node.upper));
  node.quadrupole.fill(0);
  if (settings_.quadrupole)
    for (std::uint32_t k = node.begin; k < node.end; ++k)
      add_point_quadrupole(node.quadrupole, mass_[k], items_[k].x - node.centre_of_mass);
}

void BarnesHutGravity::combine_moments(Node& node, const Node& left, const Node& right) const {
  node.mass = left.mass + right.mass;
  node.h_max = std::max(left.h_max, right.h_max);
  node.centre_of_mass = node.mass > 0 ? Vec<3>((left.mass * left.centre_of_mass + right.mass * right.centre_of_mass) / node.mass)
                                      : Vec<3>(Real(0.5) * (node.lower + node.upper));
  node.quadrupole.fill(0);
  if (!settings_.quadrupole) return;
  // Parallel-axis theorem: each child's quadrupole plus that of its mass at its centre of mass.
  for (const Node* child : {&left, &right}) {
    for (int c = 0; c < 6; ++c) node.quadrupole[c] += child->quadrupole[c];
    add_point_quadrupole(node.quadrupole, child->mass, child->centre_of_mass - node.centre_of_mass);
  }
}

std::uint32_t BarnesHutGravity::build(std::uint32_t begin, std::uint32_t end, std::span<const Real> m, std::span<const Real> h) {
  const auto id = static_cast<std::uint32_t>(nodes_.size());
  nodes_.emplace_back();
  Node node;
  node.begin = begin;
  node.end = end;
  node.lower = node.upper = items_[begin].x;
  for (std::uint32_t k = begin + 1; k < end; ++k) {
    node.lower = node.lower.cwiseMin(items_[k].x);
    node.upper = node.upper.cwiseMax(items_[k].x);
  }
  const Vec<3> extent = node.upper - node.lower;
  int axis = 0;
  const Real longest = extent.maxCoeff(&axis);
  node.size_squared = longest * longest;
  if (end - begin <= settings_.leaf_size) {
    // The leaf's particles are in their final place: gather their masses and smoothing lengths.
    for (std::uint32_t k = begin; k < end; ++k) {
      mass_[k] = m[items_[k].index];
      h_[k] = h[items_[k].index];
    }
    node.leaf = true;
    leaf_moments(node);
    node.next = id + 1;
    nodes_[id] = node;
    return id;
  }
  // Median cut along the longest side; ties in the coordinate are ordered by input index, so the
  // tree depends on the input alone.
  const std::uint32_t middle = begin + (end - begin) / 2;
  std::nth_element(items_.begin() + begin, items_.begin() + middle, items_.begin() + end, [axis](const Item& a, const Item& b) {
    return a.x[axis] < b.x[axis] || (a.x[axis] == b.x[axis] && a.index < b.index);
  });
  const std::uint32_t left = build(begin, middle, m, h);
  const std::uint32_t right = build(middle, end, m, h);
  node.next = static_cast<std::uint32_t>(nodes_.size());
  combine_moments(node, nodes_[left], nodes_[right]);
  nodes_[id] = node;
  return id;
}

void BarnesHutGravity::compute(std::span<const Vec<3>> x, std::span<const Real> m, std::span<const Real> h,
                               std::span<Vec<3>> acceleration, std::span<Real> potential) {
  check_particles("Barnes-Hut gravity", x, m, h);
  const std::size_t n = x.size();
  if (acceleration.size() != n)
    throw std::invalid_argument("Barnes-Hut gravity: acceleration has " + std::to_string(acceleration.size()) +
                                " entries but x has " + std::to_string(n));
  if (!potential.empty() && potential.size() != n)
    throw std::invalid_argument("Barnes-Hut gravity: potential has " + std::to_string(potential.size()) +
                                " entries but x has " + std::to_string(n) + " (pass an empty span to skip it)");
  statistics_ = {};
  nodes_.clear();
  if (n == 0) return;

  // Build (sequential; the storage keeps its capacity between calls).
  items_.resize(n);
  mass_.resize(n);
  h_.resize(n);
  multipole_count_.resize(n);
  pair_count_.resize(n);
  for (std::size_t i = 0; i < n; ++i) items_[i] = {x[i], static_cast<std::uint32_t>(i)};
  build(0, static_cast<std::uint32_t>(n), m, h);

  // Walk: particle k (tree order) visits the nodes depth-first; an accepted node or a summed leaf
  // skips to the node after its subtree, an opened node steps to its first child.
  const Real theta2 = settings_.theta * settings_.theta;
  const Real G = settings_.G;
  const bool quadrupole = settings_.quadrupole;
  const bool want_potential = !potential.empty();
  const Node* nodes = nodes_.data();
  const auto n_nodes = static_cast<std::uint32_t>(nodes_.size());
  const Item* items = items_.data();
  const Real* mass = mass_.data();
  const Real* smoothing = h_.data();
  parallel_for(n, [&](std::size_t k) {
    const Vec<3> p = items[k].x;
    const Real h_i = smoothing[k];
    Vec<3> acc = Vec<3>::Zero();
    Real pot = 0;
    std::uint32_t multipoles = 0, pairs = 0;
    std::uint32_t id = 0;
    while (id < n_nodes) {
      const Node& node = nodes[id];
      const Vec<3> d = node.centre_of_mass - p;
      const Real r2 = d.squaredNorm();
      bool accept = node.size_squared < theta2 * r2;
      if (accept) {
        const Vec<3> outside = (node.lower - p).cwiseMax(p - node.upper).cwiseMax(Real(0));
        const Real reach = Real(2) * std::max(node.h_max, h_i);
        accept = outside.squaredNorm() > reach * reach;
      }
      if (accept) {
        const Real r_inv = Real(1) / std::sqrt(r2);
        const Real r_inv2 = r_inv * r_inv, r_inv3 = r_inv * r_inv2;
        acc += (node.mass * r_inv3) * d;
        pot -= node.mass * r_inv;
        if (quadrupole) {
          const auto& q = node.quadrupole;
          const Vec<3> qd(q[0] * d[0] + q[3] * d[1] + q[4] * d[2], q[3] * d[0] + q[1] * d[1] + q[5] * d[2],
                          q[4] * d[0] + q[5] * d[1] + q[2] * d[2]);
          const Real dqd = d.dot(qd);
          const Real r_inv5 = r_inv3 * r_inv2;
          acc += (Real(2.5) * dqd * r_inv5 * r_inv2) * d - r_inv5 * qd;
          pot -= Real(0.5) * dqd * r_inv5;
        }
        ++multipoles;
        id = node.next;
      } else if (node.leaf) {
        for (std::uint32_t j = node.begin; j < node.end; ++j)
          if (j != k) add_pair(items[j].x - p, mass[j], h_i, smoothing[j], acc, pot);
        pairs += node.end - node.begin - (k >= node.begin && k < node.end ? 1 : 0);
        id = node.next;
      } else {
        ++id;
      }
    }
    const std::uint32_t i = items[k].index;
    acceleration[i] = G * acc;
    if (want_potential) potential[i] = G * pot;
    multipole_count_[k] = multipoles;
    pair_count_[k] = pairs;
  });

  statistics_.nodes = nodes_.size();
  statistics_.leaves = static_cast<std::size_t>(std::count_if(nodes_.begin(), nodes_.end(), [](const Node& node) { return node.leaf; }));
  statistics_.multipoles_per_particle = parallel_sum(n, 0.0, [&](std::size_t k) { return double(multipole_count_[k]); }) / double(n);
  statistics_.pairs_per_particle = parallel_sum(n, 0.0, [&](std::size_t k) { return double(pair_count_[k]); }) / double(n);
}

void direct_gravity(std::span<const Vec<3>> x, std::span<const Real> m, std::span<const Real> h, Real G,
                    std::span<const std::size_t> targets, std::span<Vec<3>> acceleration, std::span<Real> potential) {
  check_particles("direct gravity", x, m, h);
  if (!std::isfinite(G) || !(G > 0)) throw std::invalid_argument("direct gravity: G = " + number(G) + " must be finite and > 0");
  const std::size_t n = x.size(), n_targets = targets.size();
  if (acceleration.size() != n_targets)
    throw std::invalid_argument("direct gravity: acceleration has " + std::to_string(acceleration.size()) + " entries but there are " +
                                std::to_string(n_targets) + " targets");
  if (!potential.empty() && potential.size() != n_targets)
    throw std::invalid_argument("direct gravity: potential has " + std::to_string(potential.size()) + " entries but there are " +
                                std::to_string(n_targets) + " targets (pass an empty span to skip it)");
  if (const std::size_t k = first_index_where(n_targets, [&](std::size_t t) { return targets[t] >= n; }); k < n_targets)
    throw std::invalid_argument("direct gravity: targets[" + std::to_string(k) + "] = " + std::to_string(targets[k]) +
                                " is not a particle (there are " + std::to_string(n) + ")");
  parallel_for(n_targets, [&](std::size_t t) {
    const std::size_t i = targets[t];
    const Vec<3> p = x[i];
    Vec<3> acc = Vec<3>::Zero();
    Real pot = 0;
    for (std::size_t j = 0; j < n; ++j)
      if (j != i) add_pair(x[j] - p, m[j], h[i], h[j], acc, pot);
    acceleration[t] = G * acc;
    if (!potential.empty()) potential[t] = G * pot;
  });
}

void direct_gravity(std::span<const Vec<3>> x, std::span<const Real> m, std::span<const Real> h, Real G,
                    std::span<Vec<3>> acceleration, std::span<Real> potential) {
  std::vector<std::size_t> all(x.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
  direct_gravity(x, m, h, G, all, acceleration, potential);
}

double gravitational_energy(std::span<const Real> m, std::span<const Real> potential) {
  if (potential.size() != m.size())
    throw std::invalid_argument("gravitational energy: potential has " + std::to_string(potential.size()) + " entries but m has " +
                                std::to_string(m.size()));
  return parallel_sum(m.size(), 0.0, [&](std::size_t i) { return 0.5 * double(m[i]) * double(potential[i]); });
}

}  // namespace sph
