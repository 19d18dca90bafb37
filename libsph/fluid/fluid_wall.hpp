#pragma once
// A wall for a fluid: particles in a few layers behind the boundary (Adami, Hu & Adams 2012,
// J. Comput. Phys. 231:7057), each with the unit normal of the boundary pointing into the fluid, a
// velocity and an acceleration (zero for a wall at rest; a lid's tangential speed; a moving
// body's motion). The fluid sees it through the one-sided Riemann problem of its own operators
// (weakly_compressible_fluid.hpp): the wall is a boundary condition of the fluid, not a system
// with dynamics of its own. A moving body (an elastic solid, a rigid body) is a wall whose
// velocity and acceleration fields are the body's motion averaged over the fluid's step, under field
// names of its own so that they do not clash with the body's instantaneous state.

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "libsph/core/particles.hpp"

namespace sph {

enum class WallSlip { no_slip, free_slip };

inline const std::vector<std::pair<std::string, WallSlip>>& wall_slip_names() {
  static const std::vector<std::pair<std::string, WallSlip>> names{{"no_slip", WallSlip::no_slip},
                                                                   {"free_slip", WallSlip::free_slip}};
  return names;
}

template <int Dim>
class FluidWall {
 public:
  /// The names of the wall's fields on its particle set.
  struct FieldNames {
    std::string normal = "wall_normal", velocity = "velocity", acceleration = "acceleration";
  };

  /// `normals`: one unit normal per particle, pointing from the wall into the fluid.
  FluidWall(ParticleSet<Dim>& particles, const std::vector<Vec<Dim>>& normals, WallSlip slip = WallSlip::no_slip,
            const FieldNames& names = {})
      : particles_(particles), slip_(slip) {
    if (normals.size() != particles.n_particles())
      throw std::invalid_argument("wall '" + particles.name() + "': one normal per particle is needed");
    normal_ = particles.template register_field<Vec<Dim>>(names.normal, Vec<Dim>::Zero());
    velocity_ = particles.template register_field<Vec<Dim>>(names.velocity, Vec<Dim>::Zero());
    acceleration_ = particles.template register_field<Vec<Dim>>(names.acceleration, Vec<Dim>::Zero(), false);
    auto n = particles.field(normal_);
    for (std::size_t i = 0; i < normals.size(); ++i) {
      if (!(std::abs(normals[i].norm() - 1) < Real(1e-6)))
        throw std::invalid_argument("wall '" + particles.name() + "': normal of particle " + std::to_string(i) +
                                    " is not a unit vector");
      n[i] = normals[i];
    }
  }

  ParticleSet<Dim>& particles() { return particles_; }
  const ParticleSet<Dim>& particles() const { return particles_; }
  WallSlip slip() const { return slip_; }
  FieldHandle<Vec<Dim>> normal_field() const { return normal_; }
  FieldHandle<Vec<Dim>> velocity_field() const { return velocity_; }
  FieldHandle<Vec<Dim>> acceleration_field() const { return acceleration_; }
  /// Sets the velocity of every wall particle (a lid sliding in its own plane).
  void set_velocity(const Vec<Dim>& v) {
    for (auto& vi : particles_.field(velocity_)) vi = v;
  }

 private:
  ParticleSet<Dim>& particles_;
  WallSlip slip_;
  FieldHandle<Vec<Dim>> normal_, velocity_, acceleration_;
};

}  // namespace sph
