#include "cardio/cell_heterogeneity.hpp"

#include <cmath>
#include <map>
#include <stdexcept>
#include <tuple>

namespace cardio {

using TP06 = sph::TenTusscherPanfilov2006;

namespace {
constexpr int apicobasal_bands = 5;
bool known_region(const std::string& r) {
  return r == "all" || r == "lv" || r == "rv" || r == "endo" || r == "mid" || r == "epi";
}
void check_channel(const std::string& channel) {
  TP06::Parameters p;
  p.scale(channel, 1);  // throws for an unknown name
}
const char* type_name(TP06::CellType t) {
  return t == TP06::CellType::endocardial ? "endo" : t == TP06::CellType::mid_myocardial ? "mid" : "epi";
}
}  // namespace

void CellHeterogeneity::check() const {
  if (!(endocardial_layer >= 0 && mid_layer >= 0 && endocardial_layer + mid_layer <= 1))
    throw std::invalid_argument("the endocardial and M layers must be fractions of the wall that add up to at most 1");
  if (!(apicobasal_gks_ratio >= 0) || !std::isfinite(apicobasal_gks_ratio))
    throw std::invalid_argument("the apico-basal G_Ks ratio must be finite and >= 0");
  for (const auto& s : scalings) {
    check_channel(s.channel);
    if (!(s.factor >= 0) || !std::isfinite(s.factor))
      throw std::invalid_argument("the scaling of '" + s.channel + "' must be finite and >= 0");
    if (!known_region(s.region))
      throw std::invalid_argument("region '" + s.region + "' of the scaling of '" + s.channel +
                                  "' is not one of all, lv, rv, endo, mid, epi");
    if ((s.region == "endo" || s.region == "mid" || s.region == "epi") && !transmural)
      throw std::invalid_argument("region '" + s.region + "' needs the transmural layers");
  }
  for (const auto& d : drugs) {
    check_channel(d.channel);
    if (!(d.ic50 > 0) || !std::isfinite(d.ic50)) throw std::invalid_argument("the IC50 of '" + d.channel + "' must be positive");
    if (!(d.hill > 0) || !std::isfinite(d.hill))
      throw std::invalid_argument("the Hill coefficient of '" + d.channel + "' must be positive");
  }
  if (!(drug_concentration >= 0) || !std::isfinite(drug_concentration))
    throw std::invalid_argument("the drug concentration must be finite and >= 0");
}

bool CellHeterogeneity::needs_coordinates() const {
  if (transmural || apicobasal_gks_ratio != 1) return true;
  for (const auto& s : scalings)
    if (s.region != "all") return true;
  return false;
}

CellGroups ten_tusscher_groups(const CellHeterogeneity& h, std::size_t n, std::span<const double> transmural,
                               std::span<const double> apicobasal, std::span<const std::uint8_t> rv) {
  h.check();
  const bool coordinates = h.needs_coordinates();
  if (coordinates && (transmural.size() != n || apicobasal.size() != n || rv.size() != n))
    throw std::invalid_argument("the cell heterogeneity needs the transmural and apico-basal coordinates and the ventricle of every "
                                "particle (fibres = ldrb)");
  // The key of a particle: cell type, apico-basal band, RV or not.
  using Key = std::tuple<int, int, bool>;
  std::map<Key, std::uint16_t> index;
  CellGroups groups;
  groups.group.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    TP06::CellType type = h.uniform_type;
    int band = 0;
    bool in_rv = false;
    if (coordinates) {
      if (h.transmural)
        type = transmural[i] < h.endocardial_layer               ? TP06::CellType::endocardial
               : transmural[i] < h.endocardial_layer + h.mid_layer ? TP06::CellType::mid_myocardial
                                                                   : TP06::CellType::epicardial;
      if (h.apicobasal_gks_ratio != 1)
        band = std::min(apicobasal_bands - 1, std::max(0, int(std::floor(apicobasal[i] * apicobasal_bands))));
      in_rv = rv[i] != 0;
    }
    const Key key{int(type), band, in_rv};
    auto found = index.find(key);
    if (found == index.end()) {
      if (groups.models.size() == 0xffff) throw std::logic_error("too many cell groups");
      TP06::Parameters p = TP06::Parameters::of(type);
      if (h.apicobasal_gks_ratio != 1) {
        const double a = (band + 0.5) / apicobasal_bands;  // band centre
        p.g_Ks *= h.apicobasal_gks_ratio + (1 - h.apicobasal_gks_ratio) * a;
      }
      const std::string layer = type_name(type);
      for (const auto& s : h.scalings) {
        const bool applies = s.region == "all" || s.region == layer || (s.region == "lv" && !in_rv) || (s.region == "rv" && in_rv);
        if (applies) p.scale(s.channel, s.factor);
      }
      for (const auto& d : h.drugs) p.scale(d.channel, 1 / (1 + std::pow(h.drug_concentration / d.ic50, d.hill)));
      found = index.emplace(key, std::uint16_t(groups.models.size())).first;
      groups.models.push_back(TP06(p).with_voltage_table(h.lookup_table));
      std::string name = layer;
      if (h.apicobasal_gks_ratio != 1) name += " band " + std::to_string(band + 1);
      if (coordinates) name += in_rv ? " rv" : " lv";
      groups.names.push_back(name);
      groups.counts.push_back(0);
    }
    groups.group[i] = found->second;
    ++groups.counts[found->second];
  }
  if (groups.models.size() == 1) groups.group.clear();
  return groups;
}

}  // namespace cardio
