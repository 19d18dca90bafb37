#pragma once
// `cardiosph mesh KIND --out DIR [--edge L]`: writes the analytic heart meshes of
// geometry/heart_meshes.hpp (the files shipped in meshes/ are made this way).

#include <filesystem>
#include <string>

namespace cardiosph {

/// Kinds: lv-ellipsoid, biventricular. edge <= 0 takes the kind's default. Returns the exit code.
int run_mesh_command(const std::string& kind, const std::filesystem::path& folder, double edge, bool quiet);

}  // namespace cardiosph
