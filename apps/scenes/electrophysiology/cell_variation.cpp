#include "apps/scenes/electrophysiology/cell_variation.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

namespace cardiosph {

using TP06 = sph::TenTusscherPanfilov2006;

void declare_parameters(sph::Parameters& p, CellVariationParameters& c, bool wall) {
  if (wall) {
    p.add_choice("cell_heterogeneity", c.heterogeneity, {"none", "transmural"},
                 "ten Tusscher-Panfilov cell types: cell_type everywhere (none), or endocardial, M and epicardial layers "
                 "by the transmural coordinate (transmural)");
    p.add("endocardial_layer", c.endocardial_layer, "1", "fraction of the wall from the endocardium made of endocardial cells",
          sph::Range::closed(0, 1));
    p.add("mid_layer", c.mid_layer, "1", "fraction of the wall next to it made of M cells (the rest is epicardial)",
          sph::Range::closed(0, 1));
    p.add("apicobasal_gks_ratio", c.apicobasal_gks_ratio, "1",
          "G_Ks at the apex over G_Ks at the base, linear along the apico-basal coordinate in five bands (1: none)",
          sph::Range::non_negative());
  }
  p.add_choice("cell_type", c.cell_type, {"epicardial", "endocardial", "mid_myocardial"},
               "ten Tusscher-Panfilov cell type" + std::string(wall ? " where cell_heterogeneity = none" : ""));
  p.add_text("conductance_scaling", c.scaling,
             "channel*factor[@region] separated by ';' (e.g. g_Kr*0.5@lv); regions all, lv, rv, endo, mid, epi; channels "
             "g_Na, g_K1, g_to, g_Kr, g_Ks, g_CaL, g_bNa, g_bCa, g_pK, g_pCa, g_NaCa, g_NaK, g_rel, g_up");
  p.add_text("drug_block", c.drugs, "channel:IC50:Hill separated by ';' (IC50 in the unit of drug_concentration)");
  p.add("drug_concentration", c.drug_concentration, "uM", "drug concentration; block 1/(1 + (C/IC50)^Hill)",
        sph::Range::non_negative());
  p.add_path("population_file", c.population_file,
             "CSV with a header of channels and one row of conductance factors per population member");
  p.add("population_member", c.population_member, "1", "row of population_file to use (0: the first)",
        sph::Range::closed(0, 1e9));
  p.add("reaction_lookup_table", c.lookup_table, "mV",
        "ten Tusscher-Panfilov's functions of V (gate rates, pump and exchanger factors) in lookup tables of this step, "
        "interpolated linearly (openCARP's tables; their error: the `cell` scene's rbr_qss_table row); 0: computed exactly",
        sph::Range::closed(0, 1));
}

namespace {
std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> items;
  std::istringstream in(text);
  std::string item;
  while (std::getline(in, item, separator)) {
    const auto a = item.find_first_not_of(" \t\r"), b = item.find_last_not_of(" \t\r");
    items.push_back(a == std::string::npos ? "" : item.substr(a, b - a + 1));
  }
  return items;
}
double number(const std::string& text, const std::string& where) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    throw sph::ParameterError(where + ": '" + text + "' is not a number");
  }
  if (used != text.size() || !std::isfinite(v)) throw sph::ParameterError(where + ": '" + text + "' is not a finite number");
  return v;
}
}  // namespace

cardio::CellHeterogeneity cell_heterogeneity(const CellVariationParameters& c) {
  cardio::CellHeterogeneity h;
  h.transmural = c.heterogeneity == "transmural";
  h.endocardial_layer = c.endocardial_layer;
  h.mid_layer = c.mid_layer;
  h.apicobasal_gks_ratio = c.apicobasal_gks_ratio;
  h.lookup_table = c.lookup_table;
  h.uniform_type = c.cell_type == "endocardial"      ? TP06::CellType::endocardial
                   : c.cell_type == "mid_myocardial" ? TP06::CellType::mid_myocardial
                                                     : TP06::CellType::epicardial;
  for (const auto& item : split(c.scaling, ';')) {
    if (item.empty()) continue;
    const std::string where = "parameter 'conductance_scaling', entry '" + item + "'";
    const auto star = item.find('*');
    if (star == std::string::npos) throw sph::ParameterError(where + ": expected channel*factor[@region]");
    const auto at = item.find('@', star);
    cardio::ConductanceScaling s;
    s.channel = split(item.substr(0, star), ';')[0];
    s.factor = number(split(item.substr(star + 1, at == std::string::npos ? std::string::npos : at - star - 1), ';')[0], where);
    if (at != std::string::npos) s.region = split(item.substr(at + 1), ';')[0];
    h.scalings.push_back(s);
  }
  for (const auto& item : split(c.drugs, ';')) {
    if (item.empty()) continue;
    const std::string where = "parameter 'drug_block', entry '" + item + "'";
    const auto parts = split(item, ':');
    if (parts.size() != 3) throw sph::ParameterError(where + ": expected channel:IC50:Hill");
    h.drugs.push_back({parts[0], number(parts[1], where), number(parts[2], where)});
  }
  h.drug_concentration = c.drug_concentration;
  if (!c.population_file.empty()) {
    const std::string file = c.population_file.string();
    std::ifstream in(c.population_file);
    if (!in) throw sph::ParameterError("parameter 'population_file' = '" + file + "': cannot be read");
    std::string line;
    if (!std::getline(in, line)) throw sph::ParameterError("parameter 'population_file' = '" + file + "': empty");
    const auto header = split(line, ',');
    for (const auto& channel : header) try {
        TP06::Parameters().scale(channel, 1);
      } catch (const std::invalid_argument& e) {
        throw sph::ParameterError("population file '" + file + "', header: " + e.what());
      }
    long row = -1;
    std::size_t line_number = 1;
    while (std::getline(in, line)) {
      ++line_number;
      if (split(line, ',').size() == 1 && split(line, ',')[0].empty()) continue;
      if (++row != c.population_member) continue;
      const auto values = split(line, ',');
      if (values.size() != header.size())
        throw sph::ParameterError("population file '" + file + "', line " + std::to_string(line_number) + ": " +
                                  std::to_string(values.size()) + " values for " + std::to_string(header.size()) + " channels");
      for (std::size_t k = 0; k < header.size(); ++k)
        h.scalings.push_back({header[k], number(values[k], "population file '" + file + "', line " +
                                                               std::to_string(line_number) + ", column '" + header[k] + "'")});
      break;
    }
    if (row < c.population_member)
      throw sph::ParameterError("parameter 'population_member' = " + std::to_string(c.population_member) + ": '" + file +
                                "' has " + std::to_string(row + 1) + " members");
  }
  try {
    h.check();
  } catch (const std::invalid_argument& e) {
    throw sph::ParameterError(std::string("cell parameters: ") + e.what());
  }
  return h;
}

}  // namespace cardiosph
