#include "cardio/pseudo_ecg.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "libsph/core/correction_matrix.hpp"
#include "libsph/core/numerical_failure.hpp"
#include "libsph/core/distribution.hpp"
#include "libsph/core/parallel.hpp"

namespace cardio {

using Vec3 = sph::Vec<3>;
using Mat3 = sph::Mat<3>;

std::vector<Lead> twelve_leads(const std::vector<Electrode>& electrodes) {
  auto index = [&](const std::string& name) {
    for (std::size_t e = 0; e < electrodes.size(); ++e)
      if (electrodes[e].name == name) return e;
    throw std::invalid_argument("the 12-lead ECG needs an electrode named '" + name + "'");
  };
  const std::size_t RA = index("RA"), LA = index("LA"), LL = index("LL");
  std::vector<Lead> leads{{"I", {{LA, 1}, {RA, -1}}},
                          {"II", {{LL, 1}, {RA, -1}}},
                          {"III", {{LL, 1}, {LA, -1}}},
                          {"aVR", {{RA, 1}, {LA, -0.5}, {LL, -0.5}}},
                          {"aVL", {{LA, 1}, {RA, -0.5}, {LL, -0.5}}},
                          {"aVF", {{LL, 1}, {RA, -0.5}, {LA, -0.5}}}};
  const double third = 1.0 / 3.0;
  for (int v = 1; v <= 6; ++v) {
    const std::string name = "V" + std::to_string(v);
    leads.push_back({name, {{index(name), 1}, {RA, -third}, {LA, -third}, {LL, -third}}});
  }
  return leads;
}

std::vector<Electrode> twelve_lead_electrodes(const Vec3& centre, const Vec3& base_to_apex, const Vec3& lv_to_rv,
                                              double chest_radius, double limb_distance) {
  // Body frame: x to the patient's left, y anterior, z superior.
  const Vec3 apex_body = Vec3(1, 1, -1).normalized(), rv_body = Vec3(-1, 1, 0).normalized();
  const Vec3 apex = base_to_apex.normalized();
  const Vec3 rv_raw = lv_to_rv - lv_to_rv.dot(apex) * apex;
  if (!(rv_raw.norm() > 1e-9 * lv_to_rv.norm()) || !std::isfinite(rv_raw.norm()))
    throw std::invalid_argument("12-lead electrodes: the LV-to-RV direction is parallel to the long axis");
  const Vec3 rv = rv_raw.normalized();
  Mat3 body, heart;
  body << apex_body, rv_body, apex_body.cross(rv_body);
  heart << apex, rv, apex.cross(rv);
  const Mat3 to_mesh = heart * body.transpose();
  auto place = [&](const std::string& name, const Vec3& p) { return Electrode{name, centre + to_mesh * p}; };
  std::vector<Electrode> e;
  const double degrees[6] = {-20, 10, 35, 60, 85, 110};
  for (int v = 0; v < 6; ++v) {
    const double a = degrees[v] * std::numbers::pi / 180;
    e.push_back(place("V" + std::to_string(v + 1), Real(chest_radius) * Vec3(Real(std::sin(a)), Real(std::cos(a)), 0)));
  }
  e.push_back(place("RA", Real(limb_distance) * Vec3(-1, 0, 1).normalized()));
  e.push_back(place("LA", Real(limb_distance) * Vec3(1, 0, 1).normalized()));
  e.push_back(place("LL", Real(limb_distance) * Vec3(Real(0.3), 0, -1).normalized()));
  return e;
}

PseudoEcg::PseudoEcg(std::vector<Electrode> electrodes, const sph::NeighbourList<3>& relation,
                     std::span<const Vec3> reference_positions, std::span<const Real> volumes, double source_to_bath,
                     double min_distance, const sph::ParticleSet<3>* particles)
    : electrodes_(std::move(electrodes)),
      relation_(relation),
      particles_(particles && particles->partition() ? particles : nullptr),
      reference_(reference_positions),
      volume_(volumes),
      scale_(source_to_bath / (4 * std::numbers::pi)),
      correction_(reference_positions.size()),
      flux_(reference_positions.size()) {
  if (!(source_to_bath > 0) || !std::isfinite(source_to_bath))
    throw std::invalid_argument("pseudo-ECG: chi C_m / sigma_b must be positive");
  for (const auto& e : electrodes_) {
    if (!e.position.allFinite()) throw std::invalid_argument("pseudo-ECG: electrode '" + e.name + "' has no finite position");
    for (std::size_t i = 0; i < reference_positions.size(); ++i)
      if ((reference_positions[i] - e.position).norm() < min_distance)
        throw std::invalid_argument("pseudo-ECG: electrode '" + e.name + "' at " +
                                    sph::NumericalFailure::format_position(e.position) + " lies within " +
                                    std::to_string(min_distance) + " mm of the tissue (particle " +
                                    std::to_string(particles ? sph::global_index(*particles, i) : i) +
                                    "); electrodes must lie outside it");
  }
  sph::compute_correction_matrix<3>(relation, volumes, correction_);
}

std::vector<double> PseudoEcg::potentials(std::span<const Real> V, std::span<const Mat3> D0, std::span<const Vec3> x,
                                          std::span<const Mat3> F) const {
  const std::size_t n = relation_.n_targets();  // (a distributed tissue: this rank's owned particles)
  const bool deformed = !F.empty();
  // flux_j = J_j F_j D0_j G_j V0_j, the volume-weighted current-configuration flux of particle j.
  sph::parallel_for(n, [&](std::size_t i) {
    Vec3 sum = Vec3::Zero();
    for (const auto [k, j] : relation_.row(i)) {
      sum += volume_[j] * (V[j] - V[i]) * relation_.kernel_derivative[k] * relation_.unit_vector[k];
    }
    const Vec3 q = D0[D0.size() == 1 ? 0 : i] * (correction_[i] * sum);
    flux_[i] = volume_[i] * (deformed ? Vec3(F[i].determinant() * (F[i] * q)) : q);
  });
  // The sums over the whole tissue in particle order: on several ranks over its gathered fluxes
  // and positions (the same terms, added as on one rank).
  std::span<const Vec3> flux(flux_), at(x);
  if (particles_) {
    flux = sph::gather_all(*particles_, std::span<const Vec3>(flux_), whole_flux_);
    at = sph::gather_all(*particles_, x, whole_x_);
  }
  std::vector<double> phi(electrodes_.size());
  for (std::size_t e = 0; e < electrodes_.size(); ++e) {
    const Vec3 xe = electrodes_[e].position;
    phi[e] = scale_ * sph::parallel_sum(flux.size(), 0.0, [&](std::size_t j) {
               const Vec3 d = at[j] - xe;
               const double r = d.norm();
               return double(flux[j].dot(d)) / (r * r * r);
             });
  }
  return phi;
}

std::vector<double> lead_values(const std::vector<Lead>& leads, const std::vector<double>& potentials) {
  std::vector<double> values;
  for (const auto& lead : leads) {
    double v = 0;
    for (const auto& [e, w] : lead.terms) v += w * potentials.at(e);
    values.push_back(v);
  }
  return values;
}

}  // namespace cardio
