#include "apps/scenes/diffusion_scenes.hpp"
#include "apps/scenes/scene.hpp"

namespace cardiosph {

const std::vector<SceneEntry>& scene_registry() {
  static const std::vector<SceneEntry> scenes{
      {"diffusion", "2D isotropic diffusion of a band, against the error-function solution",
       [] { return make_diffusion_band_scene(); }},
      {"diffusion-aniso", "2D anisotropic diffusion (ratio 10, at 30 degrees) of a Gaussian, against the exact Gaussian",
       [] { return make_diffusion_gaussian_scene(); }},
  };
  return scenes;
}

const SceneEntry* find_scene(const std::string& name) {
  for (const auto& s : scene_registry())
    if (s.name == name) return &s;
  return nullptr;
}

}  // namespace cardiosph
