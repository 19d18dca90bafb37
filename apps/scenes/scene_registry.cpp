#include "apps/scenes/diffusion_scenes.hpp"
#include "apps/scenes/electromechanics/em_scenes.hpp"
#include "apps/scenes/electrophysiology/ep_scenes.hpp"
#include "apps/scenes/fluid/fluid_scenes.hpp"
#include "apps/scenes/fsi/fsi_scenes.hpp"
#include "apps/scenes/geometry/geometry_scenes.hpp"
#include "apps/scenes/impact/impact_scenes.hpp"
#include "apps/scenes/scene.hpp"
#include "apps/scenes/solid/solid_scenes.hpp"

namespace cardiosph {

const std::vector<SceneEntry>& scene_registry() {
  static const std::vector<SceneEntry> scenes{
      {"heart", "excitation-contraction of a ventricular mesh (default: the shipped biventricular heart): activation, "
                "active tension, cavity volumes and ejection fractions",
       [] { return make_heart_scene(); }, {"mesh"}, {"dp", "preset", "beats"}},
      {"diffusion", "2D isotropic diffusion of a band, against the error-function solution",
       [] { return make_diffusion_band_scene(); }},
      {"diffusion-aniso", "2D anisotropic diffusion (ratio 10, at 30 degrees) of a Gaussian, against the exact Gaussian",
       [] { return make_diffusion_gaussian_scene(); }},
      {"oscillating-beam", "2D plate clamped at one end in its first bending mode, against the thin-plate period",
       [] { return make_oscillating_beam_scene(); }},
      {"cantilever", "3D passive myocardium cantilever (isotropic exponential law) after a transverse kick",
       [] { return make_cantilever_scene(); }},
      {"twisting-column", "3D column twisted by an initial angular velocity: twist and zero-energy-mode measure",
       [] { return make_twisting_column_scene(); }},
      {"land-beam", "3D Guccione beam under follower pressure (Land et al. 2015, problem 1), against the published tip z",
       [] { return make_land_beam_scene(); }},
      {"homogeneous-deformation", "3D Holzapfel-Ogden cube in fibre/sheet stretch and shear, against the closed-form stress",
       [] { return make_homogeneous_deformation_scene(); }},
      {"cell", "single-cell action potentials of every model and scheme against CVODE: error against wall time",
       [] { return make_cell_scene(); }},
      {"depolarization", "2D Aliev-Panfilov excitation from a corner bump (SPHinXsys case), observer against a converged run",
       [] { return make_depolarization_scene(); }},
      {"spiral-wave", "2D Aliev-Panfilov spiral from an S1-S2 cross-field stimulus: rotation period and stability",
       [] { return make_spiral_wave_scene(); }},
      {"niederer-slab", "3D ten Tusscher-Panfilov slab benchmark (Niederer et al. 2011): activation times at P1..P9",
       [] { return make_niederer_slab_scene(); }},
      {"cable", "3D strand of ten Tusscher-Panfilov cells under a pacing protocol (train, S1-S2, restitution): APD and "
                "CV per beat, restitution curves against the single cell",
       [] { return make_cable_scene(); }},
      {"particles", "heart mesh to body-fitted particles, surface labels and LDRB fibres (cached): volume and fibre-angle errors",
       [] { return make_particles_scene(); }, {"mesh"}, {"dp"}},
      {"myocardium-cube", "active myocardium cube on a sliding holder (prescribed tension): corner displacements and "
                          "equilibrium residual",
       [] { return make_myocardium_cube_scene(); }, {}, {"preset"}},
      {"land-lv", "Land et al. 2015 problems 2 and 3 on the idealised LV: apex positions against the published ones",
       [] { return make_land_lv_scene(); }},
      {"dambreak", "2D dam break (SPHinXsys setup): surge front against Martin & Moyce and Koshizuka & Oka, wall pressure",
       [] { return make_dambreak_scene(); }},
      {"dambreak-3d", "3D dam break, the column extruded across a tank of finite depth: surge front",
       [] { return make_dambreak_3d_scene(); }},
      {"hydrostatic-tank", "2D water at rest in a tank, long run: bottom pressure against rho g H, spurious speed",
       [] { return make_hydrostatic_tank_scene(); }},
      {"taylor-green", "2D periodic Taylor-Green vortex at Re 100: kinetic-energy decay rate and L2 velocity error",
       [] { return make_taylor_green_scene(); }},
      {"poiseuille", "2D body-force driven channel (periodic): steady profile against the parabola",
       [] { return make_poiseuille_scene(); }},
      {"lid-driven-cavity", "2D lid-driven cavity at Re 100 (preset re1000): centre lines against Ghia et al. 1982",
       [] { return make_lid_driven_cavity_scene(); }},
      {"hydrostatic-plate", "2D water column on an elastic plate clamped at both ends (Fourey et al. 2017): mid-span "
                            "deflection against the clamped-plate value",
       [] { return make_hydrostatic_plate_scene(); }},
      {"turek-hron-fsi2", "2D flexible bar behind a cylinder in a channel, Re 100 (Turek & Hron 2006 FSI2): tip "
                          "amplitude and frequency, drag and lift",
       [] { return make_channel_flow_scene("turek-hron-fsi2", turek_hron_defaults()); }},
      {"cylinder-flow", "2D channel flow past a fixed cylinder, Re 100 (Schaefer & Turek 1996, 2D-2): Strouhal number, "
                        "drag and lift coefficients",
       [] { return make_channel_flow_scene("cylinder-flow", cylinder_flow_defaults()); }},
      {"elastic-gate", "2D dam break through an elastic gate (Antoci et al. 2007, SPHinXsys setup): gate-tip "
                       "displacement x(t), y(t)",
       [] { return make_elastic_gate_scene(); }},
      {"sod-shock-tube", "2D slab of Sod's shock tube, ideal gas, updated-Lagrangian SPH: L1 errors of density, "
                         "velocity and pressure against the exact Riemann solution",
       [] { return make_sod_shock_tube_scene(); }},
      {"rubber-rings", "two elastic rings colliding (Gray, Monaghan & Swift 2001), updated-Lagrangian SPH with strength: "
       "with artificial stress they bounce whole, without it they tear",
       [] { return make_rubber_rings_scene(); }},
      {"taylor-bar", "copper bar onto a rigid frictionless wall at 227 m/s (von Mises with linear hardening): final length "
                     "and mushroom radius against the reference",
       [] { return make_taylor_bar_scene(); }},
      {"evrard-collapse", "Evrard's adiabatic collapse of a self-gravitating gas sphere (Barnes-Hut gravity, variable h): "
                          "kinetic, thermal and potential energy, and their conservation",
       [] { return make_evrard_collapse_scene(); }},
      {"impact", "a basalt sphere struck at 3.2 km/s (Nakamura & Fujiwara 1991): Tillotson, strength, Grady-Kipp damage; "
                 "largest fragment and fragment masses",
       [] { return make_impact_scene(); }},
      {"sedov-blast", "2D point explosion in a cold gas (variable h): shock radius against time and density profile against "
                      "the self-similar Sedov-Taylor solution",
       [] { return make_sedov_blast_scene(); }},
  };
  return scenes;
}

const SceneEntry* find_scene(const std::string& name) {
  for (const auto& s : scene_registry())
    if (s.name == name) return &s;
  return nullptr;
}

}  // namespace cardiosph
