#pragma once
// A heterogeneous ten Tusscher-Panfilov 2006 tissue: the cell type of each particle by its
// transmural coordinate (endocardial, M and epicardial layers), an apico-basal gradient of G_Ks,
// conductance scalings by region, drug block and the scalings of a population member. Particles
// with the same parameters share one model (one group of the reaction system, libsph/reaction).
//
// Drug block of a channel at concentration C (simple pore block, e.g. Mirams et al. 2011,
// Cardiovasc. Res. 91:53, eq. 1): g = g_0 / (1 + (C / IC50)^h), h the Hill coefficient.
// Apico-basal gradient: G_Ks scaled by r + (1 - r) a, with a the apico-basal coordinate of the LDRB
// field (0 at the apex, 1 at the base) and r = apicobasal_gks_ratio, quantised into five bands
// (a larger G_Ks at the apex shortens its APD, as measured in human ventricles; Keller et al. 2012,
// Front. Physiol. 3:158 use such a gradient).

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "libsph/reaction/cell_models.hpp"

namespace cardio {

/// factor times the conductance of `channel` in `region`: all, lv, rv, endo, mid or epi.
struct ConductanceScaling {
  std::string channel;
  double factor = 1;
  std::string region = "all";
};

struct DrugBlock {
  std::string channel;
  double ic50 = 1;  ///< in the unit of the concentration
  double hill = 1;
};

struct CellHeterogeneity {
  bool transmural = false;         ///< endo / M / epi layers by the transmural coordinate
  double endocardial_layer = 0.3;  ///< fraction of the wall from the endocardium
  double mid_layer = 0.3;          ///< the M layer next to it; the rest is epicardial
  sph::TenTusscherPanfilov2006::CellType uniform_type = sph::TenTusscherPanfilov2006::CellType::epicardial;  ///< without layers
  double apicobasal_gks_ratio = 1;  ///< G_Ks at the apex over the base (1: no gradient)
  std::vector<ConductanceScaling> scalings;
  std::vector<DrugBlock> drugs;
  double drug_concentration = 0;
  /// [mV] every group's model with its functions of V in lookup tables of this step
  /// (TenTusscherPanfilov2006::with_voltage_table); 0: exact.
  double lookup_table = 0;

  /// Throws std::invalid_argument naming the problem (unknown channel or region, layers that do not
  /// fit in the wall, non-positive IC50 or Hill coefficient, negative factors or concentration).
  void check() const;
  /// Whether per-particle coordinates are needed (layers, gradient or a regional scaling).
  bool needs_coordinates() const;
};

struct CellGroups {
  std::vector<sph::AnyCellModel> models;  ///< one per group
  std::vector<std::uint16_t> group;       ///< per particle (empty: one group)
  std::vector<std::string> names;         ///< of each group, for reports
  std::vector<std::size_t> counts;        ///< particles per group
};

/// The groups for n particles. transmural (0 endocardium, 1 epicardium), apicobasal (0 apex, 1 base)
/// and in_rv (1 for a particle of the RV, e.g. from rv_ventricle) may be empty when
/// needs_coordinates() is false.
CellGroups ten_tusscher_groups(const CellHeterogeneity& h, std::size_t n, std::span<const double> transmural,
                               std::span<const double> apicobasal, std::span<const std::uint8_t> in_rv);

/// Which ventricle each particle belongs to, from the LDRB coordinates: the RV where phi_rv > phi_lv.
/// Both vanish on the epicardium (their Dirichlet value), where the particle takes the side of the
/// sum of phi_rv - phi_lv over its neighbours in `relation` (the inner relation of the particles).
template <class Relation>
std::vector<std::uint8_t> rv_ventricle(std::span<const double> lv, std::span<const double> rv, const Relation& relation) {
  std::vector<std::uint8_t> in_rv(lv.size());
  for (std::size_t i = 0; i < lv.size(); ++i) {
    double difference = rv[i] - lv[i];
    if (lv[i] + rv[i] < 1e-9)
      for (const auto [k, j] : relation.row(i))
        difference += rv[j] - lv[j];
    in_rv[i] = difference > 0;
  }
  return in_rv;
}

}  // namespace cardio
