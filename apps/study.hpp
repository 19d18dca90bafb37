#pragma once
// `cardiosph study SCENE --sweep key=a,b,c`: runs a scene once per value into <output>/<key>-<value>/,
// writes study.csv (value, particles, steps, wall time, every error of the report), plots the
// errors against wall time on log-log axes (study.png, with gnuplot) and prints the observed order
// of convergence between consecutive values: p = log(e_k / e_k+1) / log(v_k+1 / v_k).

#include <string>

#include "apps/run_scene.hpp"

namespace cardiosph {

int run_study(const std::string& scene_name, const std::string& sweep, const CommonOptions& options);

}  // namespace cardiosph
