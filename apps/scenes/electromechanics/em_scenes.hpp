#pragma once
// Electromechanics scenes (3D, mm / ms / kPa, density in mg/mm^3; kPa = mg / (mm ms^2)).
//
// heart: excitation-contraction of a ventricular mesh (default: the shipped biventricular heart):
//   monodomain (Aliev-Panfilov or ten Tusscher-Panfilov 2006) + Nash-Panfilov active tension +
//   Holzapfel-Ogden TLSPH on one particle set; cavity volumes and ejection fractions.
// myocardium-cube: the active myocardium cube (SPHinXsys muscle-activation case) with a prescribed
//   active tension; corner displacements and the equilibrium residual of the held state.
// land-lv: problems 2 and 3 of Land et al. 2015 on the idealised LV (passive inflation; inflation
//   with active tension); apex positions against the published ones.

#include <memory>

#include "apps/scenes/scene.hpp"

namespace cardiosph {

std::unique_ptr<Scene> make_heart_scene();
std::unique_ptr<Scene> make_myocardium_cube_scene();
std::unique_ptr<Scene> make_land_lv_scene();

}  // namespace cardiosph
