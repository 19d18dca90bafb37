#pragma once
// `cardiosph study SCENE --sweep key=a,b,c`: runs a scene once per value into <output>/<key>-<value>/,
// writes study.csv (value, particles, steps, wall time, every error of the report), plots the
// errors against wall time on log-log axes (study.png, with gnuplot) and prints the observed order
// of convergence between consecutive values: p = log(e_k / e_k+1) / |log(v_k+1 / v_k)| (positive when
// the error falls, whether the swept value is a resolution that grows or a spacing that shrinks).

#include <string>

#include "apps/run_scene.hpp"

namespace cardiosph {

/// Runs `scene_name` at each value of `sweep` (key=v1,v2,...) and writes study.csv and study.png (error
/// against wall time); with `compare` (key=a,b,..., may be empty) the sweep is run once for each of
/// its values, each in its subfolder <key>-<value>, and study.png shows them all.
int run_study(const std::string& scene_name, const std::string& sweep, const std::string& compare, const CommonOptions& options);

}  // namespace cardiosph
