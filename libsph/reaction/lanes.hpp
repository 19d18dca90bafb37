#pragma once
// Several cells in one evaluation: a cell model may write its equations once for a number type T
// and evaluate them with T = double (one cell) and with T = Lanes (lane_count cells, one per SIMD
// lane, with Eigen's vectorised exp, log and sqrt, and exp_minus_one below). The arithmetic per
// lane is the scalar one; only the elementary functions round differently (Eigen's polynomial
// approximations against the C library's), so a lane's result differs from the scalar one by
// rounding, not by method.
//
// Lane-wise branching: `pick(condition, when_true, when_false)` evaluates only the chosen branch for
// double; for Lanes, only the branches that some lane takes, each lane keeping its own (a branch
// evaluated for the other lanes may produce inf or NaN in a lane; it is discarded).

#include <Eigen/Core>
#include <cmath>
#include <concepts>

namespace sph {

inline constexpr int lane_count = 8;  ///< one AVX-512 register of doubles, two AVX2 ones
using Lanes = Eigen::Array<double, lane_count, 1>;

/// x as a value of T.
template <class T>
T constant(double x) {
  if constexpr (std::same_as<T, double>) return x;
  else return T::Constant(x);
}

/// `condition ? when_true() : when_false()` for one cell.
template <class A, class B>
double pick(bool condition, A&& when_true, B&& when_false) {
  return condition ? when_true() : when_false();
}

/// The same for lanes: each lane takes the branch its condition selects; a branch that no lane
/// takes is not evaluated.
template <class Condition, class A, class B>
  requires(!std::same_as<Condition, bool>)
Lanes pick(const Condition& condition, A&& when_true, B&& when_false) {
  const Eigen::Array<bool, lane_count, 1> c = condition;
  if (c.all()) return when_true();
  if (!c.any()) return when_false();
  return c.select(Lanes(when_true()), Lanes(when_false()));
}

/// exp(x) - 1 without cancellation for small x. For lanes (Eigen has no vectorised expm1 for double,
/// and its select() is not vectorised): for |x| <= 1/2 the Taylor series to x^14 / 14!, whose
/// remainder is below 5e-17 |x|; elsewhere exp(x) - 1, which loses no more than about one digit there.
inline double exp_minus_one(double x) { return std::expm1(x); }
inline Lanes exp_minus_one(const Lanes& x) {
  const auto series = [&]() -> Lanes {
    // Horner: x (1 + x/2 (1 + x/3 (1 + ... (1 + x/14)))).
    Lanes sum = Lanes::Ones();
    for (int k = 14; k >= 2; --k) sum = 1 + sum * x * (1.0 / k);
    return x * sum;
  };
  return pick((x.abs() <= 0.5).eval(), series, [&]() -> Lanes { return x.exp() - 1; });
}

}  // namespace sph
