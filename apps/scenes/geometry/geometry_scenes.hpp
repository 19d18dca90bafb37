#pragma once
// Scenes of the geometry stage.

#include <memory>

#include "apps/scenes/scene.hpp"

namespace cardiosph {

std::unique_ptr<Scene> make_particles_scene();

}  // namespace cardiosph
