#pragma once
// Self-gravity of a 3D particle set: a Barnes-Hut tree code with monopole and quadrupole moments
// (Barnes & Hut 1986, Nature 324:446; quadrupole as in Hernquist 1987, ApJS 64:715), the pairs
// closer than the kernel support softened to match the cubic M4 kernel (Price & Monaghan 2007,
// MNRAS 374:1347, appendix A), and the O(n^2) direct sum with the same softening as reference.
//
// Potential and acceleration of particle i (G the gravitational constant):
//
//   Phi_i = G sum_{j != i} m_j phi_ij,      a_i = -G sum_{j != i} m_j phi'_ij (x_i - x_j) / r_ij,
//   phi_ij  = [phi (r_ij, h_i) + phi (r_ij, h_j)] / 2,
//   phi'_ij = [phi'(r_ij, h_i) + phi'(r_ij, h_j)] / 2,
//
// symmetric in i and j, so a pair's forces are equal and opposite. With q = r / h, the kernel
// softening of the M4 spline W(r, h) = 1 / (pi h^3) w(q), support 2h (Price & Monaghan 2007, A1 and
// A2; phi' is the Newtonian field of the mass distribution W, 4 pi / r^2 int_0^r W(s) s^2 ds):
//
//   phi'(r, h) = 1/h^2 (4/3 q - 6/5 q^3 + 1/2 q^4)                          0 <= q < 1
//              = 1/h^2 (8/3 q - 3 q^2 + 6/5 q^3 - 1/6 q^4 - 1/(15 q^2))      1 <= q < 2
//              = 1/r^2                                                       q >= 2
//   phi (r, h) = 1/h (2/3 q^2 - 3/10 q^4 + 1/10 q^5 - 7/5)                    0 <= q < 1
//              = 1/h (4/3 q^2 - q^3 + 3/10 q^4 - 1/30 q^5 - 8/5 + 1/(15 q))   1 <= q < 2
//              = -1/r                                                        q >= 2
//
// The potential leaves out the self term G m_i phi(0, h_i) = -7/5 G m_i / h_i (constant for a
// fixed h; add it where a variable-h energy needs it).
//
// The tree (BarnesHutGravity) is a binary k-d tree: each node is cut at the median of its particles
// along the longest side of their bounding box until at most leaf_size particles remain. A node
// stores its mass M, centre of mass c, traceless quadrupole about c,
//   Q = sum_k m_k (3 d_k d_k^T - |d_k|^2 I),  d_k = x_k - c,
// the longest side l of its particles' bounding box and the largest h inside. Seen from a particle
// at x, with d = c - x and r = |d|, a node is accepted as one multipole when
//
//   l / r < theta   and   the bounding box is farther than 2 max(h_node, h_i) from x,
//
// the second condition ensuring that no pair inside an accepted node is softened and that x is not
// inside the node. An accepted node contributes (the quadrupole terms as in Hernquist 1987)
//
//   a   += G [ M d / r^3 - Q d / r^5 + 5/2 (d^T Q d) d / r^7 ],
//   Phi += -G [ M / r + 1/2 (d^T Q d) / r^5 ];
//
// a node that is not accepted is opened, and the pairs of a leaf that is not accepted are summed
// directly with the softened interaction. Each particle walks the tree in the same depth-first
// order, so its sums do not depend on the number of threads (bitwise). Build O(n log n); the walk
// costs O(log n) node interactions per particle for a fixed theta.

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "libsph/core/types.hpp"

namespace sph {

/// phi'(r, h): the M4-matched softened radial force per unit mass and unit G (1 / r^2 beyond 2h).
inline Real m4_softened_force(Real r, Real h) {
  const Real q = r / h;
  if (q >= Real(2)) return Real(1) / (r * r);
  const Real q2 = q * q;
  if (q < Real(1)) return q * (Real(4) / Real(3) - Real(6) / Real(5) * q2 + Real(0.5) * q2 * q) / (h * h);
  return (q * (Real(8) / Real(3) - Real(3) * q + Real(6) / Real(5) * q2 - q2 * q / Real(6)) - Real(1) / (Real(15) * q2)) / (h * h);
}

/// phi(r, h): the M4-matched softened potential per unit mass and unit G (-1 / r beyond 2h).
inline Real m4_softened_potential(Real r, Real h) {
  const Real q = r / h;
  if (q >= Real(2)) return -Real(1) / r;
  const Real q2 = q * q;
  if (q < Real(1)) return (q2 * (Real(2) / Real(3) - Real(0.3) * q2 + Real(0.1) * q2 * q) - Real(1.4)) / h;
  return (q2 * (Real(4) / Real(3) - q + Real(0.3) * q2 - q2 * q / Real(30)) - Real(1.6) + Real(1) / (Real(15) * q)) / h;
}

/// phi'(r, h) / r, finite at r = 0 (4 / (3 h^3)): the factor of the separation vector in a pair force.
inline Real m4_softened_force_over_r(Real r, Real h) {
  const Real q = r / h;
  if (q >= Real(2)) return Real(1) / (r * r * r);
  const Real q2 = q * q, h3 = h * h * h;
  if (q < Real(1)) return (Real(4) / Real(3) - Real(6) / Real(5) * q2 + Real(0.5) * q2 * q) / h3;
  return (Real(8) / Real(3) - Real(3) * q + Real(6) / Real(5) * q2 - q2 * q / Real(6) - Real(1) / (Real(15) * q2 * q)) / h3;
}

struct GravitySettings {
  Real G = 1;                   ///< gravitational constant, in the units of x, m and time
  Real theta = Real(0.5);       ///< opening angle, in (0, 1]
  bool quadrupole = true;       ///< false: monopole (point mass at the centre of mass) only
  std::size_t leaf_size = 8;    ///< most particles in a leaf, >= 1
  /// Throws std::invalid_argument naming the first impossible value.
  void check() const;
};

/// Barnes-Hut self-gravity over a k-d tree, rebuilt by every compute(); the storage is kept between
/// calls, so that a call with no more particles than before allocates nothing.
class BarnesHutGravity {
 public:
  explicit BarnesHutGravity(GravitySettings settings = {});

  /// Accelerations (and, unless `potential` is empty, potentials Phi_i) of the n particles at x with
  /// masses m >= 0 and smoothing lengths h > 0. x, m, h and acceleration have n entries; potential
  /// has n or none. Throws std::invalid_argument for mismatched sizes or non-finite / impossible input.
  void compute(std::span<const Vec<3>> x, std::span<const Real> m, std::span<const Real> h, std::span<Vec<3>> acceleration,
               std::span<Real> potential);

  const GravitySettings& settings() const { return settings_; }

  /// Counts of the last compute(): tree nodes and leaves, and per particle the mean number of
  /// accepted multipoles and of directly summed pairs.
  struct Statistics {
    std::size_t nodes = 0, leaves = 0;
    double multipoles_per_particle = 0, pairs_per_particle = 0;
  };
  Statistics statistics() const { return statistics_; }

 private:
  struct Node {
    Vec<3> centre_of_mass = Vec<3>::Zero();
    Vec<3> lower = Vec<3>::Zero(), upper = Vec<3>::Zero();  // bounding box of the node's particles
    Real mass = 0;
    Real size_squared = 0;                                   // l^2, l the box's longest side
    Real h_max = 0;
    std::array<Real, 6> quadrupole{};                        // Q_xx, Q_yy, Q_zz, Q_xy, Q_xz, Q_yz
    std::uint32_t begin = 0, end = 0;                        // particles [begin, end) in tree order
    std::uint32_t next = 0;                                  // the node after this one's subtree
    bool leaf = false;
  };
  struct Item {
    Vec<3> x;
    std::uint32_t index;
  };

  std::uint32_t build(std::uint32_t begin, std::uint32_t end, std::span<const Real> m, std::span<const Real> h);
  void leaf_moments(Node& node) const;
  void combine_moments(Node& node, const Node& left, const Node& right) const;

  GravitySettings settings_;
  std::vector<Node> nodes_;
  std::vector<Item> items_;          // positions in tree order, with their input index
  std::vector<Real> mass_, h_;       // masses and smoothing lengths in tree order
  std::vector<std::uint32_t> multipole_count_, pair_count_;
  Statistics statistics_;
};

/// The O(n^2) direct sum with the same softening: acceleration[k] and potential[k] (potential may be
/// empty) of particle targets[k], summed over all n particles j != targets[k] in index order.
void direct_gravity(std::span<const Vec<3>> x, std::span<const Real> m, std::span<const Real> h, Real G,
                    std::span<const std::size_t> targets, std::span<Vec<3>> acceleration, std::span<Real> potential);

/// direct_gravity with every particle a target (acceleration and potential have n entries).
void direct_gravity(std::span<const Vec<3>> x, std::span<const Real> m, std::span<const Real> h, Real G,
                    std::span<Vec<3>> acceleration, std::span<Real> potential);

/// Gravitational energy 1/2 sum_i m_i Phi_i (reproducible for any thread count).
double gravitational_energy(std::span<const Real> m, std::span<const Real> potential);

}  // namespace sph
