#pragma once
// Shapes for particle generation: a closed region of space known through its signed distance
// (negative inside). Analytic primitives (box, cylinder, ellipsoid, half-space), boolean
// combinations of shapes, and closed triangle meshes (geometry/mesh.hpp) share this interface.
//
// Geometry works in double precision whatever sph::Real is: particle positions are rounded to Real
// only when a particle set is made.

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>

namespace geometry {

using Vec3 = Eigen::Vector3d;

struct Aabb {
  Vec3 lower = Vec3::Zero();
  Vec3 upper = Vec3::Zero();
  Vec3 extent() const { return upper - lower; }
};

class Shape {
 public:
  virtual ~Shape() = default;
  /// Signed distance from p to the surface, negative inside. Primitives and meshes give the exact
  /// distance; booleans give the exact sign and a lower bound on the magnitude (min/max of their
  /// operands), which is all that the volume integration and the relaxation rely on.
  virtual double signed_distance(const Vec3& p) const = 0;
  /// Outward unit normal at the surface point nearest to p (the gradient of the signed distance).
  /// The default differentiates signed_distance by central differences.
  virtual Vec3 normal(const Vec3& p) const;
  /// A box holding the shape.
  virtual Aabb bounding_box() const = 0;
  /// The enclosed volume when it is known exactly (primitives, meshes); std::nullopt otherwise.
  virtual std::optional<double> volume() const { return std::nullopt; }
  /// One line for reports and errors.
  virtual std::string describe() const = 0;

  bool contains(const Vec3& p) const { return signed_distance(p) < 0; }
};

using ShapePtr = std::shared_ptr<const Shape>;

/// Axis-aligned box [lower, upper].
ShapePtr make_box(const Vec3& lower, const Vec3& upper);
/// Solid cylinder of `radius` around the segment from `base` to `top` (flat ends).
ShapePtr make_cylinder(const Vec3& base, const Vec3& top, double radius);
/// Axis-aligned ellipsoid with semi-axes `radii` around `centre`.
ShapePtr make_ellipsoid(const Vec3& centre, const Vec3& radii);
/// Half-space {x : (x - point) . outward_normal <= 0}; unbounded, so only inside an intersection
/// or difference with a bounded shape.
ShapePtr make_half_space(const Vec3& point, const Vec3& outward_normal);

ShapePtr make_union(ShapePtr a, ShapePtr b);
ShapePtr make_intersection(ShapePtr a, ShapePtr b);
/// a without b.
ShapePtr make_difference(ShapePtr a, ShapePtr b);

/// Volume of `shape` by adaptive octree integration of its indicator: a cell whose centre lies
/// farther from the surface than its half-diagonal is wholly inside or outside; cells cut by the
/// surface are split until their size falls below `cell_size`, where the centre decides.
/// Uses shape.volume() instead when it is known.
double shape_volume(const Shape& shape, double cell_size);

}  // namespace geometry
