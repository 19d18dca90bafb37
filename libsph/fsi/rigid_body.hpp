#pragma once
// A rigid body driven by the fluid: its particles are a wall of the fluid (libsph/fluid/fluid_wall.hpp)
// that records the fluid's force on each of them (WallForces::record), and the body moves under
//   M dV/dt = sum_j f_j + M g,        d(I w)/dt = sum_j (x_j - c) x f_j  (+ (c - pivot) x M g, hinged),
// with f_j the pressure force of the fluid's acoustic step and its viscous force of the advection
// step, c the centre of mass, I the inertia about c (free) or about the pivot (hinged); each particle
// contributes rho V (|r|^2 + s^2 / 6) to I in 2D (its own square of side s = V^(1/2) about its
// centre), rho V ((|r|^2 + s^2 / 6) 1 - r r^T) in 3D. Motions: fixed (forces and torque only, e.g.
// drag and lift), hinged (rotation about a pivot) or free (translation and rotation).
//
// Time integration, once per fluid acoustic step dt with the forces of that step (mid-point in the
// fluid's position-based Verlet scheme):
//   V' = V + dt A,  c' = c + dt (V + V') / 2,  w' = w + dt alpha,  R' = exp(dt (w + w') / 2) R,
// and the particles follow x_j = c + R r_j. The fluid sees the motion averaged over the step, as
// for an elastic solid: v_j = (x_j' - x_j) / dt, a_j = (u_j' - u_j) / dt with u = V + w x r.
//
// The step is the interaction of the fluid on the body (libsph/core/interaction.hpp), across the
// body's wall (whose pair forces the fluid records), in the fluid's acoustic slot:
//
//   step.fill(fluid.acoustic_slot(), "rigid body 'disc'", sph::coupling(body, fluid, body.wall()));

#include <string>
#include <vector>

#include "libsph/core/interaction.hpp"
#include "libsph/fluid/fluid_wall.hpp"
#include "libsph/fluid/weakly_compressible_fluid.hpp"

namespace sph {

enum class RigidMotion { fixed, hinged, free };

template <int Dim>
class RigidBody {
 public:
  /// Angular quantities: a scalar about z in 2D, a vector in 3D (stored as Vec<3> in both).
  struct Settings {
    Real density = 1;                        ///< rho of the body [mass / length^Dim]
    RigidMotion motion = RigidMotion::free;
    Vec<Dim> pivot = Vec<Dim>::Zero();       ///< hinge point (hinged)
    Vec<Dim> gravity = Vec<Dim>::Zero();     ///< g acting on the body
  };

  /// `normals`: unit normals of the body's surface pointing into the fluid, one per particle.
  RigidBody(WeaklyCompressibleFluid<Dim>& fluid, ParticleSet<Dim>& particles, const std::vector<Vec<Dim>>& normals,
            Settings settings);

  /// Advances the body over one fluid acoustic step dt with the fluid's forces of that step.
  void advance(Real dt);

  Real mass() const { return mass_; }
  /// The reference point: the centre of mass (free, fixed) or the pivot (hinged).
  const Vec<Dim>& centre() const { return centre_; }
  const Vec<Dim>& velocity() const { return velocity_; }
  /// The angular velocity (z component in 2D).
  const Vec<3>& angular_velocity() const { return omega_; }
  /// The rotation angle about z (2D), or the angle of the rotation (3D).
  Real angle() const;
  /// Force and torque (about the centre of mass) of the fluid on the body at the last step.
  const Vec<Dim>& fluid_force() const { return force_; }
  const Vec<3>& fluid_torque() const { return torque_; }
  const FluidWall<Dim>& wall() const { return wall_; }

 private:
  void forces();

  WeaklyCompressibleFluid<Dim>& fluid_;
  ParticleSet<Dim>& particles_;
  Settings settings_;
  FluidWall<Dim> wall_;
  std::size_t wall_index_ = 0;
  Real mass_ = 0;
  Mat<3> inertia_body_ = Mat<3>::Zero();  // about the reference point, in the body frame
  Mat<3> rotation_ = Mat<3>::Identity();
  Vec<Dim> centre_ = Vec<Dim>::Zero(), velocity_ = Vec<Dim>::Zero(), force_ = Vec<Dim>::Zero();
  Vec<3> omega_ = Vec<3>::Zero(), torque_ = Vec<3>::Zero();
  std::vector<Vec<Dim>> offset_;           // x_j - reference point in the body frame
  std::vector<Vec<Dim>> reference_normal_; // in the body frame
  std::vector<Vec<Dim>> pressure_, viscous_;
};

/// The body over the fluid's acoustic step [time, time + dt] under the forces of that step
/// (RigidBody::advance); `by` is the fluid the body was built in and `wall` the body's wall().
template <int Dim>
void interact(RigidBody<Dim>& on, const WeaklyCompressibleFluid<Dim>& by, const FluidWall<Dim>& wall, Real time, Real dt);

extern template class RigidBody<2>;
extern template class RigidBody<3>;

}  // namespace sph
