#pragma once
// The parameters of a heterogeneous ten Tusscher-Panfilov tissue (cardio/cell_heterogeneity.hpp):
// cell type or transmural layers, apico-basal G_Ks gradient, conductance scaling by region, drug
// block, and a population member read from a CSV file.
//
// Text forms:
//   conductance_scaling = "g_Kr*0.5@lv; g_CaL*1.2"   channel*factor[@region], region all (default),
//                                                     lv, rv, endo, mid, epi
//   drug_block          = "g_Kr:0.1:1; g_CaL:0.5:1"  channel:IC50:Hill, IC50 in the unit of
//                                                     drug_concentration (e.g. uM)
//   population_file     a CSV whose header names channels (g_Kr, g_CaL, ...) and whose rows are
//                       factors; population_member picks the row (0 = first), applied everywhere.

#include <filesystem>
#include <string>

#include "cardio/cell_heterogeneity.hpp"
#include "libsph/io/parameters.hpp"

namespace cardiosph {

struct CellVariationParameters {
  std::string heterogeneity = "none";  ///< none or transmural (scenes with a wall)
  double endocardial_layer = 0.3, mid_layer = 0.3;
  double apicobasal_gks_ratio = 1;
  std::string cell_type = "epicardial";  ///< epicardial, endocardial or mid_myocardial (without layers)
  std::string scaling, drugs;
  double drug_concentration = 0;
  std::filesystem::path population_file;
  long population_member = 0;
  double lookup_table = 0;  ///< [mV] reaction_lookup_table: the cells' functions of V tabulated (0: exact)
};

/// Declares the parameters; `wall`: the scene has transmural and apico-basal coordinates and LV/RV
/// regions (cell_heterogeneity, endocardial_layer, mid_layer, apicobasal_gks_ratio).
void declare_parameters(sph::Parameters& p, CellVariationParameters& c, bool wall);

/// The heterogeneity they describe; throws sph::ParameterError naming the parameter and the problem
/// (and, for a population file, the file, line and column).
cardio::CellHeterogeneity cell_heterogeneity(const CellVariationParameters& c);

}  // namespace cardiosph
