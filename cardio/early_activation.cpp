#include "cardio/early_activation.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "libsph/io/parameters.hpp"

namespace cardio {

using Vec3 = sph::Vec<3>;

std::vector<EarlySite> parse_early_sites(const std::string& text) {
  std::vector<EarlySite> sites;
  std::istringstream entries(text);
  std::string entry;
  while (std::getline(entries, entry, ';')) {
    if (entry.find_first_not_of(" \t") == std::string::npos) continue;
    auto fail = [&] {
      return sph::ParameterError("parameter 'early_site_list': entry '" + entry + "' is not x,y,z@t (mm, ms)");
    };
    double x = 0, y = 0, z = 0, t = 0;
    char c1 = 0, c2 = 0, at = 0;
    std::istringstream in(entry);
    if (!(in >> x >> c1 >> y >> c2 >> z >> at >> t) || c1 != ',' || c2 != ',' || at != '@') throw fail();
    std::string rest;
    if (in >> rest || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z) || !(t >= 0) || !std::isfinite(t)) throw fail();
    sites.push_back({Vec3(Real(x), Real(y), Real(z)), t});
  }
  if (sites.empty()) throw sph::ParameterError("parameter 'early_site_list' names no site (early_sites = list)");
  return sites;
}

Vec3 lv_apex(const HeartGeometry& g, std::span<const Vec3> x) {
  const Vec3 normal = g.base_normal.cast<Real>();
  Real farthest = -std::numeric_limits<Real>::infinity();
  Vec3 apex = Vec3::Zero();
  for (std::size_t i = 0; i < x.size(); ++i)
    if (g.labels[i] == label_lv_endo && -normal.dot(x[i]) > farthest) {
      farthest = -normal.dot(x[i]);
      apex = x[i];
    }
  if (!std::isfinite(farthest)) throw std::invalid_argument("heart: no LV endocardium labelled, so no lv-apex stimulus site");
  return apex;
}

namespace {

std::vector<EarlySite> durrer_sites(const HeartGeometry& g, std::span<const Vec3> x) {
  const std::size_t n = x.size();
  const auto& labels = g.labels;
  const auto& a = g.fibres.apicobasal;
  if (a.size() != n)
    throw sph::ParameterError("parameter 'early_sites' = durrer places its sites by the LDRB apico-basal coordinate, "
                              "which needs labelled epicardium, LV endocardium and base (fibres = ldrb or mesh)");
  Vec3 c_lv = Vec3::Zero(), c_rv = Vec3::Zero();
  std::size_t n_lv = 0, n_rv = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (labels[i] == label_lv_endo) c_lv += x[i], ++n_lv;
    if (labels[i] == label_rv_endo) c_rv += x[i], ++n_rv;
  }
  if (n_lv == 0 || n_rv == 0) throw sph::ParameterError("parameter 'early_sites' = durrer needs labelled LV and RV endocardia");
  c_lv /= Real(n_lv);
  c_rv /= Real(n_rv);
  const Vec3 apex = -g.base_normal.cast<Real>().normalized();
  const Vec3 r = (c_rv - c_lv - (c_rv - c_lv).dot(apex) * apex).normalized();
  const Vec3 normal = apex.cross(r);
  // The body's anterior direction in the heart frame (apex (1,1,-1)/sqrt3, RV (-1,1,0)/sqrt2 in
  // body axes left, anterior, superior), without its long-axis part.
  const Vec3 anterior = (Real(std::sqrt(0.5)) * r + Real(std::sqrt(1.0 / 6.0)) * normal).normalized();
  // Bands of a are taken over each endocardium's own range of a (the RV endocardium does not
  // reach the apex).
  auto site = [&](SurfaceLabel label, double lo, double hi, const Vec3& towards, const Vec3& centre, double time,
                  const char* name) {
    double a_min = std::numeric_limits<double>::infinity(), a_max = -a_min;
    for (std::size_t i = 0; i < n; ++i)
      if (labels[i] == label) a_min = std::min(a_min, a[i]), a_max = std::max(a_max, a[i]);
    const double from = a_min + lo * (a_max - a_min), to = a_min + hi * (a_max - a_min);
    std::optional<std::size_t> best;
    for (std::size_t i = 0; i < n; ++i)
      if (labels[i] == label && a[i] >= from && a[i] <= to &&
          (!best || (x[i] - centre).dot(towards) > (x[*best] - centre).dot(towards)))
        best = i;
    if (!best)
      throw sph::ParameterError(std::string("parameter 'early_sites' = durrer: no endocardial particle for the ") + name + " site");
    return EarlySite{x[*best], time};
  };
  return {site(label_lv_endo, 0.7, 0.9, (r + anterior).normalized(), c_lv, 0, "LV anterior paraseptal"),
          site(label_lv_endo, 0.4, 0.6, r, c_lv, 0, "LV septal"),
          site(label_lv_endo, 0.23, 0.43, (r - anterior).normalized(), c_lv, 0, "LV posterior paraseptal"),
          site(label_rv_endo, 0.4, 0.6, anterior, c_rv, 5, "RV anterior")};
}

}  // namespace

std::vector<EarlySite> early_activation_sites(const std::string& early_sites, const std::string& list, const HeartGeometry& g,
                                              std::span<const Vec3> x, const Vec3& apex) {
  if (early_sites == "lv_apex") return {{apex, 0}};
  if (early_sites == "list") return parse_early_sites(list);
  if (early_sites == "durrer") return durrer_sites(g, x);
  throw sph::ParameterError("parameter 'early_sites' = " + early_sites + ": not lv_apex, durrer or list");
}

std::vector<Monodomain<3>::StimulusRegion> endocardial_stimuli(const std::vector<EarlySite>& sites, double velocity, double bin,
                                                              const sph::StimulusProtocol& first,
                                                              std::span<const std::int8_t> labels, std::span<const Vec3> x) {
  std::map<long, Monodomain<3>::StimulusRegion> regions;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (labels[i] != label_lv_endo && labels[i] != label_rv_endo) continue;
    double delay = std::numeric_limits<double>::infinity();
    for (const auto& site : sites) delay = std::min(delay, site.time + double((x[i] - site.position).norm()) / velocity);
    regions[std::lround(delay / bin)].particles.push_back(i);
  }
  if (regions.empty()) throw sph::ParameterError("parameter 'stimulus_site' = endocardium: no particle is labelled LV or RV endocardium");
  std::vector<Monodomain<3>::StimulusRegion> stimuli;
  for (auto& [k, region] : regions) {
    char name[64];
    std::snprintf(name, sizeof name, "endocardium +%.2f ms", double(k) * bin);
    region.name = name;
    region.protocol = first;
    region.protocol.start = first.start + double(k) * bin;
    stimuli.push_back(std::move(region));
  }
  return stimuli;
}

}  // namespace cardio
