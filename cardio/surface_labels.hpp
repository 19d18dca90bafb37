#pragma once
// Surface labels of a ventricular geometry: epicardium, LV endocardium, RV endocardium, base.
//
// Faces of the mesh are labelled (from the mesh's named regions, or by the geometric rule below),
// then every surface particle takes the label of its nearest face; separate surface meshes
// (epi, LV endo, RV endo, base) label by the nearest surface instead.
//
// Geometric rule, for a closed mesh whose cavities are open at a flat base or closed shells:
//  1. Base: for each of the six axis directions, the area of the faces whose normal lies within
//     20 degrees of it and whose centroid lies within 1 % of the bounding-box diagonal of the
//     extreme plane in that direction; the direction with the largest such area is the base
//     normal and those faces are the base (none if no direction holds 1 % of the surface area).
//  2. The other faces split into edge-connected components. The largest by area is the
//     epicardium; components below 0.5 % of the surface area join it.
//  3. The others are endocardia. Each is closed by a fan from the centroid of its border (the base
//     opening) to measure the cavity volume V and compactness 36 pi V^2 / A^3 (1 for a sphere): the
//     most compact is the LV (round), the next the RV (crescent-shaped); further ones are reported
//     and labelled LV endocardium.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/mesh.hpp"

namespace cardio {

enum SurfaceLabel : std::int8_t { label_none = 0, label_epi = 1, label_lv_endo = 2, label_rv_endo = 3, label_base = 4 };

std::string_view surface_label_name(SurfaceLabel label);

/// The label a region or surface name stands for (names as in face_labels_from_regions), or
/// label_none.
SurfaceLabel label_of_surface_name(const std::string& name);

struct FaceLabels {
  std::vector<SurfaceLabel> face;   ///< per face of the mesh
  geometry::Vec3 base_normal = geometry::Vec3::UnitZ();  ///< outward normal of the base plane
  bool has_base = false;
  std::string method;               ///< "regions" or "geometric rule"
  std::vector<double> cavity_compactness;  ///< per endocardial component, LV first (geometric rule)
  std::size_t count(SurfaceLabel label) const;
};

/// Labels from the mesh's regions named epi, lv_endo, rv_endo, base (also: epicardium, lv, rv,
/// endo_lv, endo_rv, lv_endocardium, rv_endocardium; case-insensitive). Returns std::nullopt-like
/// empty `face` when the mesh has no such regions; throws geometry::MeshError when some regions are
/// named but others are not recognised.
FaceLabels face_labels_from_regions(const geometry::TriangleMesh& mesh);

/// Labels by the geometric rule of the file comment. Throws geometry::MeshError if no epicardium
/// or no endocardium can be found.
FaceLabels face_labels_by_rule(const geometry::TriangleMesh& mesh);

/// Regions when the mesh names them, else the geometric rule.
FaceLabels label_faces(const geometry::TriangleMesh& mesh);

/// Label of each particle: that of the nearest face for particles flagged as surface, none inside.
std::vector<std::int8_t> label_particles(const std::vector<geometry::Vec3>& positions,
                                         const std::vector<std::uint8_t>& surface, const geometry::MeshShape& mesh,
                                         const FaceLabels& labels);

/// One separate surface mesh (open or closed) and the label it gives.
struct LabelledSurface {
  SurfaceLabel label;
  const geometry::MeshShape* mesh;
};

/// Label of each surface particle: that of the nearest of the given surfaces.
std::vector<std::int8_t> label_particles_by_surfaces(const std::vector<geometry::Vec3>& positions,
                                                     const std::vector<std::uint8_t>& surface,
                                                     const std::vector<LabelledSurface>& surfaces);

}  // namespace cardio
