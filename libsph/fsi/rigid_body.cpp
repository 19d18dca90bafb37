#include "libsph/fsi/rigid_body.hpp"

#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>

#include "libsph/core/parallel.hpp"

namespace sph {

namespace {

template <int Dim>
Vec<3> to3(const Vec<Dim>& v) {
  Vec<3> r = Vec<3>::Zero();
  for (int d = 0; d < Dim; ++d) r[d] = v[d];
  return r;
}

template <int Dim>
Vec<Dim> from3(const Vec<3>& v) {
  Vec<Dim> r;
  for (int d = 0; d < Dim; ++d) r[d] = v[d];
  return r;
}

}  // namespace

template <int Dim>
RigidBody<Dim>::RigidBody(WeaklyCompressibleFluid<Dim>& fluid, ParticleSet<Dim>& particles,
                          const std::vector<Vec<Dim>>& normals, Settings settings)
    : fluid_(fluid),
      particles_(particles),
      settings_(settings),
      wall_(particles, normals, WallSlip::no_slip, {"wall_normal", "fluid_velocity", "fluid_acceleration"}) {
  const std::string body = "rigid body '" + particles.name() + "'";
  if (!(settings_.density > 0)) throw std::invalid_argument(body + ": density must be positive");
  if (particles.n_particles() == 0) throw std::invalid_argument(body + ": no particles");
  const std::size_t n = particles.n_particles();
  double volume = 0;
  Vec<Dim> moment = Vec<Dim>::Zero();
  for (std::size_t j = 0; j < n; ++j) {
    volume += particles.volume[j];
    moment += particles.volume[j] * particles.position[j];
  }
  mass_ = static_cast<Real>(settings_.density * volume);
  const Vec<Dim> centre_of_mass = moment / static_cast<Real>(volume);
  centre_ = settings_.motion == RigidMotion::hinged ? settings_.pivot : centre_of_mass;  // the reference point
  offset_.resize(n);
  for (std::size_t j = 0; j < n; ++j) {
    offset_[j] = particles.position[j] - centre_;
    const Vec<3> r = to3<Dim>(offset_[j]);
    const Real V = particles.volume[j];
    const Real side2 = std::pow(V, Real(2) / Real(Dim));  // s^2 of the particle's own cell
    inertia_body_ += settings_.density * V *
                     ((r.squaredNorm() + side2 / 6) * Mat<3>::Identity() - (Dim == 3 ? (r * r.transpose()).eval() : Mat<3>::Zero()));
  }
  if constexpr (Dim == 2) {
    // Only I_zz matters in 2D (rotation about z): sum rho V (x^2 + y^2 + s^2 / 6).
    const Real izz = inertia_body_(2, 2);
    inertia_body_ = Mat<3>::Identity() * izz;
  }
  reference_normal_ = normals;
  pressure_.resize(n);
  viscous_.resize(n);
  wall_index_ = fluid_.add_wall(wall_, WallForces::record);
}

template <int Dim>
Real RigidBody<Dim>::angle() const {
  return static_cast<Real>(Eigen::AngleAxis<Real>(rotation_).angle() *
                           (Dim == 2 && Eigen::AngleAxis<Real>(rotation_).axis()[2] < 0 ? -1 : 1));
}

template <int Dim>
void RigidBody<Dim>::forces() {
  fluid_.wall_forces(wall_index_, pressure_, viscous_);
  Vec<Dim> force = Vec<Dim>::Zero();
  Vec<3> torque = Vec<3>::Zero();
  for (std::size_t j = 0; j < particles_.n_particles(); ++j) {
    const Vec<Dim> f = pressure_[j] + viscous_[j];
    force += f;
    torque += to3<Dim>(particles_.position[j] - centre_).cross(to3<Dim>(f));
  }
  force_ = force;
  torque_ = torque;
}

template <int Dim>
void RigidBody<Dim>::advance(Real dt) {
  forces();
  if (settings_.motion == RigidMotion::fixed) return;
  const std::size_t n = particles_.n_particles();
  auto v_wall = particles_.field(wall_.velocity_field());
  auto a_wall = particles_.field(wall_.acceleration_field());
  auto normal = particles_.field(wall_.normal_field());
  // Rigid velocity of each particle at the start of the step.
  std::vector<Vec<Dim>> start_position(particles_.position), start_velocity(n);
  for (std::size_t j = 0; j < n; ++j)
    start_velocity[j] = velocity_ + from3<Dim>(omega_.cross(to3<Dim>(particles_.position[j] - centre_)));

  Vec<3> torque = torque_;
  const Mat<3> inertia = rotation_ * inertia_body_ * rotation_.transpose();
  if (settings_.motion == RigidMotion::hinged) {
    Vec<Dim> com = Vec<Dim>::Zero();
    Real volume = 0;
    for (std::size_t j = 0; j < n; ++j) {
      com += particles_.volume[j] * particles_.position[j];
      volume += particles_.volume[j];
    }
    com /= volume;
    torque += to3<Dim>(com - centre_).cross(to3<Dim>(Vec<Dim>(mass_ * settings_.gravity)));
  } else {
    const Vec<Dim> acceleration = force_ / mass_ + settings_.gravity;
    const Vec<Dim> v_new = velocity_ + dt * acceleration;
    centre_ += Real(0.5) * dt * (velocity_ + v_new);
    velocity_ = v_new;
  }
  Vec<3> alpha = inertia.ldlt().solve(torque - omega_.cross(inertia * omega_));
  if constexpr (Dim == 2) alpha = Vec<3>(0, 0, torque[2] / inertia(2, 2));
  const Vec<3> omega_new = omega_ + dt * alpha;
  const Vec<3> turn = Real(0.5) * dt * (omega_ + omega_new);
  if (turn.norm() > 0) rotation_ = Eigen::AngleAxis<Real>(turn.norm(), turn / turn.norm()).toRotationMatrix() * rotation_;
  omega_ = omega_new;

  const Real inverse = Real(1) / dt;
  const Mat<Dim> R = rotation_.template topLeftCorner<Dim, Dim>();
  for (std::size_t j = 0; j < n; ++j) {
    particles_.position[j] = centre_ + R * offset_[j];
    normal[j] = R * reference_normal_[j];
    const Vec<Dim> u = velocity_ + from3<Dim>(omega_.cross(to3<Dim>(particles_.position[j] - centre_)));
    v_wall[j] = (particles_.position[j] - start_position[j]) * inverse;
    a_wall[j] = (u - start_velocity[j]) * inverse;
  }
}

template <int Dim>
void interact(RigidBody<Dim>& on, const WeaklyCompressibleFluid<Dim>&, const FluidWall<Dim>&, Real, Real dt) {
  on.advance(dt);
}

template class RigidBody<2>;
template class RigidBody<3>;
template void interact<2>(RigidBody<2>&, const WeaklyCompressibleFluid<2>&, const FluidWall<2>&, Real, Real);
template void interact<3>(RigidBody<3>&, const WeaklyCompressibleFluid<3>&, const FluidWall<3>&, Real, Real);

}  // namespace sph
