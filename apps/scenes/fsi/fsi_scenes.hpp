#pragma once
// Fluid-structure interaction scenes (libsph/fsi; docs/fsi.md). Each writes report.json with its
// error against its reference next to its run time.
//
// hydrostatic-plate (2D, SI units): a water column 1 m wide and 2 m tall on an elastic plate clamped
//   at both ends (Fourey et al. 2017); mid-span deflection against the clamped-plate value.
// turek-hron-fsi2 (2D, nondimensional, the SPHinXsys setup): a flexible bar behind a fixed cylinder
//   in a channel with a parabolic inflow, Re 100 (Turek & Hron 2006); tip displacement amplitude and
//   frequency, drag and lift.
// cylinder-flow (2D): the same channel without the bar, Re 100 (Schaefer & Turek 1996, case 2D-2);
//   Strouhal number and drag coefficient.
// elastic-gate (2D, mm and ms): dam break through an elastic gate (Antoci et al. 2007, SPHinXsys
//   setup); gate-tip displacement x(t), y(t).
#include <memory>
#include <string>

#include "apps/scenes/fluid/fluid_run.hpp"
#include "apps/scenes/scene.hpp"
#include "libsph/solid/elastic_solid.hpp"

namespace cardiosph {

/// The solid's numerical choices in an FSI scene (named apart from the fluid's): its own kernel and
/// smoothing length, hourglass control, its own acoustic CFL, whether it sub-cycles inside the
/// fluid's acoustic step, and the relaxation of the acceleration the fluid sees.
struct FsiSolidNumerics {
  std::string kernel = "wendland_c4";   ///< the solid's own kernel (its inner relation)
  double smoothing_length_ratio = 1.3;  ///< the solid's h / solid spacing
  double hourglass_coefficient = 0.1;
  double acoustic_cfl = 0.6;
  bool sub_cycling = true;
  double acceleration_relaxation = 0.1;
  /// s >= 1: the solid's inertia is rho0 s (its weight stays physical), for quasi-static scenes; the
  /// solid's step grows by sqrt(s) (sph::SolidNumerics::mass_scaling).
  double mass_scaling = 1;
  sph::HourglassControl hourglass_control = sph::HourglassControl::penalty;
  sph::DeformationGradient deformation_gradient = sph::DeformationGradient::corrected;
  sph::Quadrature quadrature = sph::Quadrature::nodal;
  /// How the clamped particles are held: "fixed" (at rest) or "reflection" (odd reflection of the
  /// displacement across a flat clamp face; scenes whose clamp has flat faces only).
  std::string clamp = "fixed";
};

void declare_fsi_solid_numerics(sph::Parameters& p, FsiSolidNumerics& n);

struct HydrostaticPlateParameters {
  long resolution = 4;          ///< solid particles across the plate thickness
  long fluid_ratio = 2;         ///< fluid spacing / solid spacing: 1, 2 or 4
  double end_time = 0.5;        ///< [s]
  double water_width = 1, water_height = 2;  ///< [m]; the plate spans the water width
  double plate_thickness = 0.05;             ///< [m]
  double fluid_density = 1000, gravity = 9.81;
  double sound_speed = 88.6;    ///< [m/s]: 10 times 2 sqrt(g H)
  double viscosity = 0;         ///< [Pa s]
  double solid_density = 2700, young_modulus = 6.75e10, poisson_ratio = 0.34;
  double solid_damping = 200;   ///< [1/s] rate of the plate's velocity damping (a quasi-static solve)
  FluidSceneNumerics numerics;
  /// The plate alone (a water film, the same load) at 4 particles across: the kernel-corrected F with
  /// nodal integration and a fixed clamp sags 64 % more than the thin plate with Timoshenko's shear;
  /// the quadratic reconstruction with Gauss points and the clamp by reflection is within 0.1 % of
  /// it (docs/fsi.md). The plate's inertia is scaled by 100 (a quasi-static solve: the mean sag is
  /// unchanged, within 0.2 %, and the solid takes 10 times fewer steps). Wendland C2 as before.
  FsiSolidNumerics solid{.kernel = "wendland_c2", .mass_scaling = 100,
                         .deformation_gradient = sph::DeformationGradient::quadratic,
                         .quadrature = sph::Quadrature::gauss, .clamp = "reflection"};
};

struct ChannelFlowParameters {
  long resolution = 10;         ///< fluid particles across the cylinder diameter (dp = D / resolution)
  long solid_ratio = 2;         ///< fluid spacing / solid spacing of the bar and cylinder: 1, 2 or 4
  double end_time = 200;
  double channel_length = 11, channel_height = 4.1;  ///< fluid from x = 0 to the outlet (periodic)
  double buffer_length = 2;     ///< inflow buffer upstream of x = 0
  double cylinder_x = 2, cylinder_y = 2, diameter = 1;
  double bar_length = 3.5, bar_thickness = 0.2;      ///< 0 length: no bar (cylinder-flow)
  double density = 1, mean_inflow = 1, reynolds = 100;
  double sound_speed = 10;
  double ramp_time = 2;         ///< the inflow ramps up as (1 - cos(pi t / ramp)) / 2
  double solid_density = 10, young_modulus = 1400, poisson_ratio = 0.4;
  double analysis_start = 0.5;  ///< fraction of the run after which amplitudes and frequencies are taken
  FluidSceneNumerics numerics;
  FsiSolidNumerics solid;
};

/// The Turek-Hron FSI2 defaults (SPHinXsys's nondimensional setup, dp 0.1, t = 200).
ChannelFlowParameters turek_hron_defaults();
/// The cylinder-flow defaults: the same channel without the bar, to t = 100.
ChannelFlowParameters cylinder_flow_defaults();

struct ElasticGateParameters {
  long resolution = 2;          ///< fluid particles across the gate width (5 mm)
  long solid_ratio = 2;
  double end_time = 400;        ///< [ms]
  double tank_length = 500, tank_height = 200.1, water_width = 100, water_height = 140;
  double gate_width = 5, gate_clamp_height = 79;     ///< the gate is clamped above this height
  double density = 1, gravity = 9.8e-3;
  double sound_speed = 23.43;   ///< 20 sqrt(g H)
  double solid_density = 1.1, young_modulus = 7.8e3, poisson_ratio = 0.47;
  FluidSceneNumerics numerics;
  FsiSolidNumerics solid;
};

std::unique_ptr<Scene> make_hydrostatic_plate_scene(HydrostaticPlateParameters parameters = {});
std::unique_ptr<Scene> make_channel_flow_scene(std::string name, ChannelFlowParameters parameters);
std::unique_ptr<Scene> make_elastic_gate_scene(ElasticGateParameters parameters = {});

}  // namespace cardiosph
