#pragma once
// Verification and stability scenes of the TLSPH solid (libsph/solid). Each writes report.json
// with its results and, where a reference exists, its error against it.
//
// oscillating-beam (2D, SI): a plate clamped at one end, started in its first bending mode
//   (Gray, Monaghan & Swift 2001); period against the thin-plate frequency, energy drift.
// cantilever (3D, SI): the passive myocardium cantilever (isotropic exponential law) given a
//   transverse kick; tip trajectory, J range, energy.
// twisting-column (3D, SI): a column twisted by an initial angular velocity; twist angle and the
//   zero-energy-mode measure with and without hourglass control.
// land-beam (3D, mm / ms / kPa, density in mg/mm^3): problem 1 of Land et al. 2015, Guccione law,
//   follower pressure on the bottom face, quasi-static by damped dynamics; final z of (10, 0.5, 1).
// homogeneous-deformation (3D, mm / ms / kPa): a cube of Holzapfel-Ogden myocardium driven through
//   fibre and sheet stretches and fs / sf shears by its boundary layer; interior Cauchy stress
//   against the closed form.

#include <memory>
#include <string>

#include "apps/scenes/scene.hpp"
#include "apps/scenes/solid/solid_run.hpp"

namespace cardiosph {

struct OscillatingBeamParameters {
  long resolution = 10;          ///< particles across the thickness H
  double end_time = 1.3;         ///< [s] about five periods
  double length = 0.2;           ///< [m] free length L
  double thickness = 0.02;       ///< [m] H
  double clamp_length = 0.06;    ///< [m] clamped part
  double density = 1000;         ///< [kg/m^3]
  double young_modulus = 2e6;    ///< [Pa]
  double poisson_ratio = 0.3975;
  long mode = 1;                  ///< bending mode: 1 or 2
  double velocity_factor = 0.05;  ///< vf: tip speed vf c0, c0 = sqrt(K / rho)
  std::string material = "neo_hookean";  ///< neo_hookean or saint_venant_kirchhoff
  std::string clamp = "reflection";  ///< reflection or fixed (see ElasticSolid::clamp_by_reflection)
  SolidSceneNumerics numerics{.solid = {.hourglass_control = sph::HourglassControl::energy, .deformation_gradient = sph::DeformationGradient::quadratic, .quadrature = sph::Quadrature::gauss}};
};

struct CantileverParameters {
  long resolution = 8;        ///< particles across the 1 m thickness
  double end_time = 3;        ///< [s]
  double length = 6;          ///< [m]
  double thickness = 1;       ///< [m] (square section)
  double holder_length = 0.5;  ///< [m] clamped
  double density = 1100;
  double young_modulus = 1.7e7;
  double poisson_ratio = 0.45;
  double exponent = 1;         ///< b of the isotropic exponential law
  double kick_y = 5 * 1.7320508075688772;  ///< [m/s] initial velocity of the free part
  double kick_z = 5;
  SolidSceneNumerics numerics;
};

struct TwistingColumnParameters {
  long resolution = 6;        ///< particles across the 1 m section
  double end_time = 0.3;      ///< [s]
  double height = 6;          ///< [m]
  double width = 1;           ///< [m]
  double density = 1100;
  double young_modulus = 1.7e7;
  double poisson_ratio = 0.45;
  double angular_velocity = 105;  ///< [rad/s] omega0: omega(z) = omega0 sin(pi z / (2 height))
  SolidSceneNumerics numerics;
};

struct LandBeamParameters {
  long resolution = 4;          ///< particles across the 1 mm thickness
  double end_time = 450;        ///< [ms]
  double pressure = 0.004;      ///< [kPa] on the bottom face
  double ramp_time = 0;         ///< [ms] linear ramp of the pressure (0: applied at once)
  double stiffness = 2;         ///< [kPa] C of the Guccione law
  double b_f = 8, b_t = 2, b_fs = 4;
  double bulk_modulus = 200;    ///< [kPa] volumetric penalty K (incompressibility)
  double density = 1;           ///< [mg/mm^3] (only sets the pseudo-dynamics of the relaxation)
  double damping_ratio = 1;     ///< fraction of critical damping of the first bending mode
  std::string solver = "quasi_static";  ///< quasi_static (stop on the residual) or dynamic (to end_time)
  std::string clamp = "reflection";     ///< reflection or fixed (see ElasticSolid::clamp_by_reflection)
  sph::RelaxationSettings relaxation;
  SolidSceneNumerics numerics{.solid = {.deformation_gradient = sph::DeformationGradient::quadratic, .quadrature = sph::Quadrature::gauss}};
};

struct HomogeneousDeformationParameters {
  long resolution = 16;        ///< particles across the unit cube
  double end_time = 4;         ///< [ms] per mode: ramp over ramp_time, then hold
  double ramp_time = 3;        ///< [ms]
  double stretch = 1.1;        ///< final stretch of the uniaxial modes (isochoric)
  double shear = 0.3;          ///< final amount of the simple shears
  double bulk_modulus = 100;   ///< [kPa]
  double density = 1;          ///< [mg/mm^3]
  double damping_rate = 2;     ///< [1/ms] velocity damping while driven
  double boundary_layers = 1;  ///< driven layer thickness, in kernel supports
  SolidSceneNumerics numerics;
};

std::unique_ptr<Scene> make_oscillating_beam_scene(OscillatingBeamParameters parameters = {});
std::unique_ptr<Scene> make_cantilever_scene(CantileverParameters parameters = {});
std::unique_ptr<Scene> make_twisting_column_scene(TwistingColumnParameters parameters = {});
std::unique_ptr<Scene> make_land_beam_scene(LandBeamParameters parameters = {});
std::unique_ptr<Scene> make_homogeneous_deformation_scene(HomogeneousDeformationParameters parameters = {});

}  // namespace cardiosph
