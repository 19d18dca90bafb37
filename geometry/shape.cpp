#include "geometry/shape.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>

#include "libsph/core/parallel.hpp"

namespace geometry {
namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();

std::string text(const Vec3& v) {
  std::ostringstream s;
  s << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return s.str();
}

void require(bool condition, const std::string& message) {
  if (!condition) throw std::invalid_argument(message);
}

// Exact signed distance of a box of half-extents `half` centred at the origin.
double box_distance(const Vec3& p, const Vec3& half) {
  const Vec3 q = p.cwiseAbs() - half;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

class Box final : public Shape {
 public:
  Box(const Vec3& lower, const Vec3& upper) : lower_(lower), upper_(upper) {
    require((upper - lower).minCoeff() > 0, "box: upper " + text(upper) + " must exceed lower " + text(lower));
  }
  double signed_distance(const Vec3& p) const override {
    return box_distance(p - 0.5 * (lower_ + upper_), 0.5 * (upper_ - lower_));
  }
  // Exact gradient of the distance: outside, towards p from its nearest point of the box; inside,
  // the outward normal of the nearest face.
  Vec3 normal(const Vec3& p) const override {
    const Vec3 nearest = p.cwiseMax(lower_).cwiseMin(upper_);
    const Vec3 out = p - nearest;
    if (out.norm() > 0) return out.normalized();
    int face = 0;
    double closest = infinity, sign = 1;
    for (int k = 0; k < 3; ++k) {
      if (p[k] - lower_[k] < closest) closest = p[k] - lower_[k], face = k, sign = -1;
      if (upper_[k] - p[k] < closest) closest = upper_[k] - p[k], face = k, sign = 1;
    }
    return sign * Vec3::Unit(face);
  }
  Aabb bounding_box() const override { return {lower_, upper_}; }
  std::optional<double> volume() const override { return (upper_ - lower_).prod(); }
  std::string describe() const override { return "box " + text(lower_) + " to " + text(upper_); }

 private:
  Vec3 lower_, upper_;
};

class Cylinder final : public Shape {
 public:
  Cylinder(const Vec3& base, const Vec3& top, double radius) : base_(base), top_(top), radius_(radius) {
    require(radius > 0, "cylinder: radius must be positive");
    require((top - base).norm() > 0, "cylinder: base and top coincide");
    axis_ = (top - base).normalized();
    half_length_ = 0.5 * (top - base).norm();
  }
  double signed_distance(const Vec3& p) const override {
    const Vec3 d = p - 0.5 * (base_ + top_);
    const double axial = d.dot(axis_);
    const double radial = (d - axial * axis_).norm();
    const Eigen::Vector2d q(radial - radius_, std::abs(axial) - half_length_);
    return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
  }
  Aabb bounding_box() const override {
    // Extent of a disc of radius R with normal a along axis k: R sqrt(1 - a_k^2).
    const Vec3 disc = radius_ * (Vec3::Ones() - axis_.cwiseAbs2()).cwiseMax(0.0).cwiseSqrt();
    return {base_.cwiseMin(top_) - disc, base_.cwiseMax(top_) + disc};
  }
  std::optional<double> volume() const override { return std::acos(-1.0) * radius_ * radius_ * 2 * half_length_; }
  std::string describe() const override {
    return "cylinder " + text(base_) + " to " + text(top_) + ", radius " + std::to_string(radius_);
  }

 private:
  Vec3 base_, top_, axis_;
  double radius_, half_length_;
};

// Distance from y (all components >= 0) to the ellipse or ellipsoid x^T diag(e)^-2 x = 1, for semi-axes
// sorted e[0] >= e[1] >= ... (Eberly, "Distance from a point to an ellipse, an ellipsoid, or a
// hyperellipsoid", Geometric Tools 2013). The closest point satisfies x_i = e_i^2 y_i / (t + e_i^2)
// for the largest root t of F(t) = sum_i (e_i y_i / (t + e_i^2))^2 - 1; F decreases on
// (-e_min^2, inf), the root is bracketed by t0 = -e_min^2 + e_min y_min (F >= 0) and
// t1 = -e_min^2 + |e o y| (F <= 0), and found by bisection. Components with y_i = 0 are the
// special cases where the root may sit at the pole (x_i != 0 with y_i = 0).
template <int N>
double ellipsoid_root_distance(const std::array<double, N>& e, const std::array<double, N>& y) {
  const double e_min = e[N - 1];
  double norm = 0;
  for (int i = 0; i < N; ++i) norm += (e[i] * y[i]) * (e[i] * y[i]);
  double lo = -e_min * e_min + e_min * y[N - 1];
  double hi = -e_min * e_min + std::sqrt(norm);
  auto f = [&](double t) {
    double s = -1;
    for (int i = 0; i < N; ++i) {
      const double r = e[i] * y[i] / (t + e[i] * e[i]);
      s += r * r;
    }
    return s;
  };
  for (int iteration = 0; iteration < 200; ++iteration) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (f(mid) > 0 ? lo : hi) = mid;
  }
  const double t = 0.5 * (lo + hi);
  double d2 = 0;
  for (int i = 0; i < N; ++i) {
    const double x = e[i] * e[i] * y[i] / (t + e[i] * e[i]);
    d2 += (x - y[i]) * (x - y[i]);
  }
  return std::sqrt(d2);
}

double ellipse_distance(double e0, double e1, double y0, double y1) {
  if (y1 > 0) {
    if (y0 > 0) return ellipsoid_root_distance<2>({e0, e1}, {y0, y1});
    return std::abs(y1 - e1);
  }
  const double denominator = e0 * e0 - e1 * e1;
  if (e0 * y0 < denominator) {
    const double x0 = e0 * e0 * y0 / denominator;
    const double x1 = e1 * std::sqrt(std::max(0.0, 1 - (x0 / e0) * (x0 / e0)));
    return std::hypot(x0 - y0, x1);
  }
  return std::abs(y0 - e0);
}

// Same for three semi-axes e0 >= e1 >= e2 and y >= 0.
double ellipsoid_distance(const std::array<double, 3>& e, const std::array<double, 3>& y) {
  if (y[2] > 0) {
    if (y[1] > 0) {
      if (y[0] > 0) return ellipsoid_root_distance<3>(e, y);
      return ellipse_distance(e[1], e[2], y[1], y[2]);
    }
    if (y[0] > 0) return ellipse_distance(e[0], e[2], y[0], y[2]);
    return std::abs(y[2] - e[2]);
  }
  const double d0 = e[0] * e[0] - e[2] * e[2], d1 = e[1] * e[1] - e[2] * e[2];
  if (e[0] * y[0] < d0 && e[1] * y[1] < d1) {
    const double x0 = e[0] * y[0] / d0, x1 = e[1] * y[1] / d1;  // x_i / e_i
    const double rest = 1 - x0 * x0 - x1 * x1;
    if (rest > 0) return std::sqrt((e[0] * x0 - y[0]) * (e[0] * x0 - y[0]) + (e[1] * x1 - y[1]) * (e[1] * x1 - y[1]) +
                                    e[2] * e[2] * rest);
  }
  return ellipse_distance(e[0], e[1], y[0], y[1]);
}

class Ellipsoid final : public Shape {
 public:
  Ellipsoid(const Vec3& centre, const Vec3& radii) : centre_(centre), radii_(radii) {
    require(radii.minCoeff() > 0, "ellipsoid: radii " + text(radii) + " must be positive");
    std::iota(order_.begin(), order_.end(), 0);
    std::sort(order_.begin(), order_.end(), [&](int a, int b) { return radii[a] > radii[b]; });
  }
  double signed_distance(const Vec3& p) const override {
    const Vec3 local = p - centre_;
    std::array<double, 3> e{}, y{};
    for (int k = 0; k < 3; ++k) {
      e[k] = radii_[order_[k]];
      y[k] = std::abs(local[order_[k]]);
    }
    const double d = ellipsoid_distance(e, y);
    return local.cwiseQuotient(radii_).squaredNorm() < 1 ? -d : d;
  }
  Aabb bounding_box() const override { return {centre_ - radii_, centre_ + radii_}; }
  std::optional<double> volume() const override { return 4.0 / 3.0 * std::acos(-1.0) * radii_.prod(); }
  std::string describe() const override { return "ellipsoid centre " + text(centre_) + ", radii " + text(radii_); }

 private:
  Vec3 centre_, radii_;
  std::array<int, 3> order_{};
};

class HalfSpace final : public Shape {
 public:
  HalfSpace(const Vec3& point, const Vec3& normal) : point_(point) {
    require(normal.norm() > 0, "half-space: normal must be non-zero");
    normal_ = normal.normalized();
  }
  double signed_distance(const Vec3& p) const override { return (p - point_).dot(normal_); }
  Vec3 normal(const Vec3&) const override { return normal_; }
  Aabb bounding_box() const override {
    // Unbounded except along an axis-aligned normal.
    Aabb box{Vec3::Constant(-infinity), Vec3::Constant(infinity)};
    for (int k = 0; k < 3; ++k) {
      if (normal_[k] == 1) box.upper[k] = point_[k];
      if (normal_[k] == -1) box.lower[k] = point_[k];
    }
    return box;
  }
  std::string describe() const override { return "half-space through " + text(point_) + ", outward " + text(normal_); }

 private:
  Vec3 point_, normal_;
};

enum class Operation { unite, intersect, subtract };

class Boolean final : public Shape {
 public:
  Boolean(Operation op, ShapePtr a, ShapePtr b) : op_(op), a_(std::move(a)), b_(std::move(b)) {
    require(a_ && b_, "boolean shape: missing operand");
  }
  double signed_distance(const Vec3& p) const override {
    const double da = a_->signed_distance(p), db = b_->signed_distance(p);
    switch (op_) {
      case Operation::unite: return std::min(da, db);
      case Operation::intersect: return std::max(da, db);
      case Operation::subtract: return std::max(da, -db);
    }
    return da;
  }
  Vec3 normal(const Vec3& p) const override {
    // The normal of the operand whose surface decides the distance.
    const double da = a_->signed_distance(p), db = b_->signed_distance(p);
    switch (op_) {
      case Operation::unite: return da <= db ? a_->normal(p) : b_->normal(p);
      case Operation::intersect: return da >= db ? a_->normal(p) : b_->normal(p);
      case Operation::subtract: return da >= -db ? a_->normal(p) : Vec3(-b_->normal(p));
    }
    return a_->normal(p);
  }
  Aabb bounding_box() const override {
    const Aabb a = a_->bounding_box(), b = b_->bounding_box();
    switch (op_) {
      case Operation::unite: return {a.lower.cwiseMin(b.lower), a.upper.cwiseMax(b.upper)};
      case Operation::intersect: return {a.lower.cwiseMax(b.lower), a.upper.cwiseMin(b.upper)};
      case Operation::subtract: return a;
    }
    return a;
  }
  std::string describe() const override {
    const char* name = op_ == Operation::unite ? "union" : op_ == Operation::intersect ? "intersection" : "difference";
    return std::string(name) + " of [" + a_->describe() + "] and [" + b_->describe() + "]";
  }

 private:
  Operation op_;
  ShapePtr a_, b_;
};

// Volume inside `shape` of the box centred at c with half-extents half (see shape_volume).
double cell_volume(const Shape& shape, const Vec3& c, const Vec3& half, double cell_size) {
  const double d = shape.signed_distance(c);
  const double radius = half.norm();
  const double full = 8 * half.prod();
  if (d <= -radius) return full;
  if (d >= radius) return 0;
  if (2 * half.maxCoeff() <= cell_size) {
    // A plane at distance d from the centre of a cube of edge 2a leaves 1/2 - d/(2a) of it inside
    // when it is parallel to a face; second-order accurate for a smooth surface.
    return full * std::clamp(0.5 - d / (2 * half.maxCoeff()), 0.0, 1.0);
  }
  double sum = 0;
  const Vec3 quarter = 0.5 * half;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 sign((corner & 1) ? 1.0 : -1.0, (corner & 2) ? 1.0 : -1.0, (corner & 4) ? 1.0 : -1.0);
    sum += cell_volume(shape, c + sign.cwiseProduct(quarter), quarter, cell_size);
  }
  return sum;
}

}  // namespace

Vec3 Shape::normal(const Vec3& p) const {
  const Aabb box = bounding_box();
  const double scale = std::isfinite(box.extent().norm()) ? box.extent().norm() : std::max(1.0, p.norm());
  const double eps = 1e-7 * scale;
  Vec3 g;
  for (int k = 0; k < 3; ++k) {
    Vec3 step = Vec3::Zero();
    step[k] = eps;
    g[k] = signed_distance(p + step) - signed_distance(p - step);
  }
  const double n = g.norm();
  return n > 0 ? Vec3(g / n) : Vec3::UnitZ();
}

ShapePtr make_box(const Vec3& lower, const Vec3& upper) { return std::make_shared<Box>(lower, upper); }
ShapePtr make_cylinder(const Vec3& base, const Vec3& top, double radius) {
  return std::make_shared<Cylinder>(base, top, radius);
}
ShapePtr make_ellipsoid(const Vec3& centre, const Vec3& radii) { return std::make_shared<Ellipsoid>(centre, radii); }
ShapePtr make_half_space(const Vec3& point, const Vec3& outward_normal) {
  return std::make_shared<HalfSpace>(point, outward_normal);
}
ShapePtr make_union(ShapePtr a, ShapePtr b) { return std::make_shared<Boolean>(Operation::unite, std::move(a), std::move(b)); }
ShapePtr make_intersection(ShapePtr a, ShapePtr b) {
  return std::make_shared<Boolean>(Operation::intersect, std::move(a), std::move(b));
}
ShapePtr make_difference(ShapePtr a, ShapePtr b) {
  return std::make_shared<Boolean>(Operation::subtract, std::move(a), std::move(b));
}

double shape_volume(const Shape& shape, double cell_size) {
  if (const auto v = shape.volume()) return *v;
  require(cell_size > 0, "shape volume: cell size must be positive");
  const Aabb box = shape.bounding_box();
  require(box.extent().allFinite() && box.extent().minCoeff() > 0,
          "shape volume: " + shape.describe() + " is unbounded");
  // Top-level cubes of edge a power of two times cell_size, integrated in parallel.
  double edge = cell_size;
  while (edge < box.extent().maxCoeff() / 16) edge *= 2;
  std::array<long, 3> n{};
  for (int k = 0; k < 3; ++k) n[k] = static_cast<long>(std::ceil(box.extent()[k] / edge));
  const std::size_t total = static_cast<std::size_t>(n[0] * n[1] * n[2]);
  const Vec3 half = Vec3::Constant(0.5 * edge);
  return sph::parallel_sum(total, 0.0, [&](std::size_t c) {
    const long i = static_cast<long>(c) % n[0], j = (static_cast<long>(c) / n[0]) % n[1], k = static_cast<long>(c) / (n[0] * n[1]);
    const Vec3 centre = box.lower + edge * Vec3(i + 0.5, j + 0.5, k + 0.5);
    return cell_volume(shape, centre, half, cell_size);
  });
}

}  // namespace geometry
