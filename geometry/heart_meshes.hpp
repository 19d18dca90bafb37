#pragma once
// Idealised ventricles defined analytically, as triangle meshes (the files in meshes/ are made by
// `cardiosph mesh ...` from these) and as analytic shapes (for exact volumes in tests).
//
// Region names shared by the mesh generator, the mesh reader (labelled OBJ groups) and the surface
// labelling of cardio/: "epi", "lv_endo", "rv_endo", "base".

#include <filesystem>
#include <string>
#include <vector>

#include "geometry/mesh.hpp"
#include "geometry/shape.hpp"

namespace geometry {

inline constexpr const char* region_epi = "epi";
inline constexpr const char* region_lv_endo = "lv_endo";
inline constexpr const char* region_rv_endo = "rv_endo";
inline constexpr const char* region_base = "base";

/// Truncated ellipsoidal left ventricle of the cardiac mechanics benchmark (Land et al. 2015,
/// Proc. R. Soc. A 471:20150641, problem 2): x = r_s sin u cos v, y = r_s sin u sin v, z = r_l cos u,
/// cut by the base plane z = base_z. Lengths in mm.
struct LvEllipsoid {
  double endo_rs = 7, endo_rl = 17;
  double epi_rs = 10, epi_rl = 20;
  double base_z = 5;
};

/// Idealised biventricular heart: LV cavity E1 inside the LV wall E2; RV cavity E3 with RV wall E4,
/// centred to the -x side so that E3 \ E2 is the crescent-shaped RV cavity and the septum is the
/// part of the LV wall E2 \ E1 facing it. Myocardium = (E2 u E4) \ (E1 u (E3 \ E2)), cut by the base
/// plane z = base_z. All ellipsoids are axis-aligned with their long axis along z. Lengths in mm.
struct Biventricular {
  Vec3 lv_centre{0, 0, 0};
  Vec3 lv_endo_radii{20, 20, 50};
  Vec3 lv_epi_radii{30, 30, 58};
  Vec3 rv_centre{-14, 0, 0};
  Vec3 rv_endo_radii{30, 24, 44};
  Vec3 rv_epi_radii{34, 28, 47};
  double base_z = 10;
};

/// Closed, outward triangle mesh with regions epi, lv_endo, base; `edge_length` is the target
/// triangle edge length [mm].
TriangleMesh lv_ellipsoid_mesh(const LvEllipsoid& lv, double edge_length);
/// Closed, outward triangle mesh with regions epi, lv_endo, rv_endo, base: CGAL corefinement of
/// ellipsoid meshes, then isotropic remeshing of each surface to `edge_length` [mm]. Throws
/// std::invalid_argument for inconsistent dimensions and MeshError if the result is not a valid
/// closed mesh with four non-empty regions.
TriangleMesh biventricular_mesh(const Biventricular& biv, double edge_length);

/// The same geometries as analytic shapes.
ShapePtr lv_ellipsoid_shape(const LvEllipsoid& lv);
ShapePtr biventricular_shape(const Biventricular& biv);
/// Exact volume of the LV wall: truncated epicardial ellipsoid minus truncated endocardial one,
/// V(r_s, r_l) = pi r_s^2 [z - z^3 / (3 r_l^2)] from z = -r_l to z = base_z.
double lv_ellipsoid_volume(const LvEllipsoid& lv);

/// Writes <folder>/<stem>.stl (the closed mesh, binary), <stem>.obj (the closed mesh with one group
/// per region) and <stem>_<region>.stl for every region; returns the files written.
std::vector<std::filesystem::path> write_heart_mesh_files(const TriangleMesh& mesh, const std::filesystem::path& folder,
                                                          const std::string& stem);

}  // namespace geometry
