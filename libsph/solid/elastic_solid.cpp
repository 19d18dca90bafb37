#include "libsph/solid/elastic_solid.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "libsph/core/distribution.hpp"
#include "libsph/core/numerical_failure.hpp"
#include "libsph/core/parallel.hpp"
#include "libsph/io/parameters.hpp"

namespace sph {

void declare_parameters(Parameters& p, SolidNumerics& n, const std::string& time_unit) {
  p.add("hourglass_coefficient", n.hourglass_coefficient, "-",
        "alpha of the hourglass penalty force (Ganzenmueller 2015); 0 turns it off", Range::non_negative());
  p.add("artificial_viscosity", n.artificial_viscosity, "-",
        "eta of the pair viscosity (the numerical damping of SPHinXsys solids, 0.25 there); 0 turns it off",
        Range::non_negative());
  p.add("acoustic_cfl", n.cfl, "-", "solid time step as a fraction of the acoustic limit", {0, 1, true, false});
  p.add("tangent_time_step", n.tangent_time_step,
        "size the acoustic step by the largest current tangent modulus (stable as exponential laws stiffen); false: "
        "by the small-strain modulus only, as SPHinXsys (fewer steps, no guarantee at large strain)");
  p.add("mass_scaling", n.mass_scaling, "-",
        "factor on the solid's inertia (density) for quasi-static runs: the acoustic step grows by its square root; "
        "1 = physical inertia", Range::closed(1, 1e6));
  p.add_enum("hourglass_control", n.hourglass_control, hourglass_control_names(),
               "zero-energy-mode control: penalty (Ganzenmueller 2015, not conservative) or energy (the derivative of "
               "alpha E / 4 sum_ij V_i V_j W_ij / r0^2 |F_i X_ij - x_ij|^2: conservative)");
  p.add_enum("deformation_gradient", n.deformation_gradient, deformation_gradient_names(),
               "reconstruction of F: corrected (kernel-corrected gradient, exact for linear motion) or quadratic (weighted "
               "least squares, exact for quadratic motion, also at free surfaces)");
  p.add_enum("quadrature", n.quadrature, quadrature_names(),
               "integration of each particle's energy: nodal (at the particle) or gauss (Dim + 1 Gauss points in its cell, F "
               "continued by its gradient; needs deformation_gradient = quadratic)");
  p.add("fixed_time_step", n.fixed_time_step, time_unit,
        "fixed solid time step instead of the acoustic one (0: acoustic); no stability guarantee", Range::non_negative());
}

template <int Dim>
ElasticSolid<Dim>::ElasticSolid(ParticleSet<Dim>& particles, const InnerRelation<Dim>& relation, Settings settings)
    : particles_(particles), relation_(relation), settings_(std::move(settings)) {
  const std::string body = "solid '" + particles_.name() + "'";
  if (relation_.n_targets() != particles_.n_owned())
    throw std::invalid_argument(body + ": relation does not match the particles");
  if (particles_.partition() && settings_.numerics.deformation_gradient == DeformationGradient::quadratic)
    throw std::invalid_argument(body + ": deformation_gradient 'quadratic' does not run on several ranks (its force needs "
                                "the fit weights of the ghosts' own neighbourhoods, a second ring of ghosts); use 'corrected'");
  if (!(settings_.density > 0)) throw std::invalid_argument(body + ": density must be positive");
  if (!(settings_.numerics.cfl > 0 && settings_.numerics.cfl <= 1)) throw std::invalid_argument(body + ": cfl must lie in (0, 1]");
  if (!(settings_.numerics.hourglass_coefficient >= 0)) throw std::invalid_argument(body + ": hourglass coefficient must be >= 0");
  if (!(settings_.numerics.fixed_time_step >= 0)) throw std::invalid_argument(body + ": fixed time step must be >= 0");
  if (!(settings_.damping_rate >= 0)) throw std::invalid_argument(body + ": damping rate must be >= 0");
  check_material<Dim>(settings_.material);

  const Real wave_modulus = std::visit([](const auto& m) { return m.wave_modulus(); }, settings_.material);
  if (!(settings_.numerics.mass_scaling >= 1 && std::isfinite(settings_.numerics.mass_scaling)))
    throw std::invalid_argument(body + ": mass scaling must be >= 1");
  inverse_inertia_ = 1 / (settings_.density * settings_.numerics.mass_scaling);
  sound_speed_ = std::sqrt(wave_modulus * inverse_inertia_);
  current_sound_speed_ = sound_speed_;
  if (settings_.numerics.stiffness_update_interval < 1) throw std::invalid_argument(body + ": stiffness update interval must be >= 1");
  hourglass_factor_ = settings_.numerics.hourglass_coefficient / 2 * young_modulus_estimate<Dim>(settings_.material);
  if (!(settings_.numerics.artificial_viscosity >= 0)) throw std::invalid_argument(body + ": artificial viscosity must be >= 0");
  if (settings_.numerics.artificial_viscosity > 0)
    viscosity_factor_ = settings_.numerics.artificial_viscosity * settings_.density * settings_.numerics.mass_scaling * sound_speed_ *
                        relation_.smoothing_length * Real(Dim * Dim) / (4 * relation_.kernel_value_at_zero);

  const std::size_t n = particles_.n_particles();
  const std::size_t owned = particles_.n_owned();  // (the ghosts' B0 enters through their owners' P B0)
  reference_position_ = particles_.template register_field<Vec<Dim>>("reference_position", Vec<Dim>::Zero(), false);
  std::copy(particles_.position.begin(), particles_.position.end(), particles_.field(reference_position_).begin());
  velocity_ = particles_.template register_field<Vec<Dim>>("velocity", Vec<Dim>::Zero());
  acceleration_ = particles_.template register_field<Vec<Dim>>("acceleration", Vec<Dim>::Zero(), false);
  displacement_ = particles_.template register_field<Vec<Dim>>("displacement", Vec<Dim>::Zero());
  jacobian_ = particles_.template register_field<Real>("jacobian", Real(1));
  von_mises_ = particles_.template register_field<Real>("von_mises_stress", Real(0));
  deformation_gradient_ = particles_.template register_field<Mat<Dim>>("deformation_gradient", Mat<Dim>::Identity(), false);
  correction_matrix_ = particles_.template register_field<Mat<Dim>>("correction_matrix", Mat<Dim>::Identity(), false);
  stress_correction_ = particles_.template register_field<Mat<Dim>>("stress_times_correction", Mat<Dim>::Zero(), false);
  const bool anisotropic = std::visit([](const auto& m) { return std::decay_t<decltype(m)>::anisotropic; }, settings_.material);
  if (anisotropic) {
    const Vec<Dim> f = settings_.fibre.normalized(), s = settings_.sheet.normalized();
    if (!(std::abs(f.dot(s)) < Real(1e-6)) || !f.allFinite() || !s.allFinite())
      throw std::invalid_argument(body + ": fibre and sheet directions must be non-zero and orthogonal");
    fibre_ = particles_.template register_field<Vec<Dim>>("fibre_direction", f);
    sheet_ = particles_.template register_field<Vec<Dim>>("sheet_direction", s);
    fibre_stretch_ = particles_.template register_field<Real>("fibre_stretch", Real(1));
  }
  if (settings_.active_stress) {
    if (!anisotropic) throw std::invalid_argument(body + ": active stress needs a law with fibre directions");
    active_tension_ = particles_.template register_field<Real>("active_tension", Real(0));
    if (settings_.active_stiffness) {
      active_stiffness_ = particles_.template register_field<Real>("active_stiffness", Real(0), false);
      active_reference_stretch_ = particles_.template register_field<Real>("active_reference_stretch", Real(1), false);
    }
  }
  // The reference geometry of every pair, once, compactly (single precision, antisymmetric in i, j
  // exactly, so that the pair forces still cancel to round-off).
  const auto& rel = relation_;
  pair_gradient_.resize(rel.n_pairs());
  pair_offset_.resize(rel.n_pairs());
  parallel_for(rel.n_pairs(), [&](std::size_t k) {
    const Vec<Dim> e = rel.unit_vector[k];
    const Real r = rel.distance[k];
    PairGradient& g = pair_gradient_[k];
    for (int d = 0; d < Dim; ++d) {
      g.gradient[d] = static_cast<PairReal>(rel.kernel_derivative[k] * e[d]);
      pair_offset_[k][d] = static_cast<PairReal>(r * e[d]);
    }
    g.hourglass_weight = r > 0 ? static_cast<PairReal>(rel.kernel_value[k] / (r * r)) : PairReal(0);
  });
  // B0_i from the stored gradients, B0_i = M_i^-T with M_i = - sum_j V_j X_ij (x) grad0 W_ij
  // (libsph/core/correction_matrix.hpp; M_i is symmetric up to the rounding of the stored
  // gradients, and this form keeps F exact for linear motion to round-off in double precision).
  {
    const auto X = particles_.field(reference_position_);
    const auto& V = particles_.volume;
    auto B = particles_.field(correction_matrix_);
    parallel_for(owned, [&](std::size_t i) {
      Mat<Dim> moment = Mat<Dim>::Zero();
      for (const auto [k, j] : rel.row(i))
        moment.noalias() -= (V[j] * (X[i] - X[j])) * pair_gradient_[k].vector().template cast<Real>().transpose();
      B[i] = moment.determinant() > Real(1e-6) ? Mat<Dim>(moment.transpose().inverse()) : Mat<Dim>::Identity();
    });
  }
  energy_hourglass_ = settings_.numerics.hourglass_control == HourglassControl::energy && hourglass_factor_ > 0;
  if (energy_hourglass_) {
    const auto& V = particles_.volume;
    hourglass_moment_.resize(n);
    parallel_for(owned, [&](std::size_t i) {
      Mat<Dim> M = Mat<Dim>::Zero();
      for (const auto [k, j] : rel.row(i)) {
        const Vec<Dim> X_ij = pair_offset_[k].template cast<Real>();
        M.noalias() += (V[j] * Real(pair_gradient_[k].hourglass_weight)) * X_ij * X_ij.transpose();
      }
      hourglass_moment_[i] = M;
    });
  }
  if (settings_.numerics.quadrature == Quadrature::gauss && settings_.numerics.deformation_gradient != DeformationGradient::quadratic)
    throw std::invalid_argument(body + ": quadrature 'gauss' needs deformation_gradient 'quadratic' (the gradient of F)");
  if (settings_.numerics.deformation_gradient == DeformationGradient::quadratic) build_quadratic_reconstruction();
  previous_position_.resize(n);
  previous_velocity_.resize(n);
  load_acceleration_.resize(n);
}

namespace {

// The Gauss points of a particle's cell of edge l = V^(1/Dim), as offsets l * u_k from the particle:
// the Dim + 1 vertices of a regular simplex at the radius l sqrt(Dim / 12), so that the mean of the
// offsets is 0 and the mean of xi xi^T is l^2 / 12 I, the second moment of the cell: the rule
// integrates any quadratic over the cell exactly, as the 2^Dim-point product rule does, with half
// the points in 3D.
template <int Dim>
std::array<Vec<Dim>, Dim + 1> cell_quadrature_points() {
  std::array<Vec<Dim>, Dim + 1> u;
  if constexpr (Dim == 2) {
    u = {Vec<2>(0, 1), Vec<2>(-std::sqrt(Real(3)) / 2, Real(-0.5)), Vec<2>(std::sqrt(Real(3)) / 2, Real(-0.5))};
  } else {
    u = {Vec<3>(1, 1, 1), Vec<3>(1, -1, -1), Vec<3>(-1, 1, -1), Vec<3>(-1, -1, 1)};
  }
  for (auto& v : u) v *= std::sqrt(Real(Dim) / 12) / v.norm();
  return u;
}

}  // namespace

template <int Dim>
void ElasticSolid<Dim>::build_quadratic_reconstruction() {
  // Weighted least squares on the basis p(xi) = (xi, the Dim (Dim + 1) / 2 quadratic monomials of xi),
  // xi = (X_j - X_i) / h, weights V_j W_ij: x_j - x_i = F xi h + (quadratic terms) is fitted by
  //   M_i c = sum_j V_j W_ij p(xi_ij) (x) (x_j - x_i),   M_i = sum_j V_j W_ij p(xi_ij) p(xi_ij)^T,
  // so F_i = sum_j (x_j - x_i) (x) a_ij with a_ij = V_j W_ij [M_i^-1 p(xi_ij)]_(1..Dim) / h, exact for
  // any quadratic motion whatever the neighbourhood (the finite-particle / moving-least-squares
  // gradient of second order; Liu & Liu 2006, Comput. Mech. 38:106; Belytschko et al. 1996, CMAME
  // 139:3). A particle whose moment matrix is ill-conditioned (too few neighbours on a corner) keeps
  // the corrected gradient a_ij = V_j B0_i grad0 W_ij.
  constexpr int Q = Dim + Dim * (Dim + 1) / 2;
  using Basis = Eigen::Matrix<Real, Q, 1>;
  using Moment = Eigen::Matrix<Real, Q, Q>;
  const auto& rel = relation_;
  const auto X = particles_.field(reference_position_);
  const auto& V = particles_.volume;
  auto B = particles_.field(correction_matrix_);
  const Real h = rel.smoothing_length;
  const std::size_t n = particles_.n_particles();
  auto basis = [](const Vec<Dim>& xi) {
    Basis p;
    p.template head<Dim>() = xi;
    int m = Dim;
    for (int a = 0; a < Dim; ++a)
      for (int b = a; b < Dim; ++b) p[m++] = xi[a] * xi[b];
    return p;
  };
  // Second derivatives (quadrature = "gauss"): d2x/dX_a dX_b = c_(ab) (a == b ? 2 : 1) / h^2 from the
  // coefficient c_(ab) of the monomial xi_a xi_b, so that G_d = dF/dX_d has the column
  // G_d e = sum_j (x_j - x_i) C_ij(e, d).
  const bool gauss = settings_.numerics.quadrature == Quadrature::gauss;
  int monomial[Dim][Dim];
  for (int a = 0, m = Dim; a < Dim; ++a)
    for (int b = a; b < Dim; ++b) monomial[a][b] = monomial[b][a] = m++;
  std::vector<Mat<Dim>> curvature(gauss ? rel.n_pairs() : 0);
  std::vector<Vec<Dim>> corrected(rel.n_pairs()), weights(rel.n_pairs());
  parallel_for(n, [&](std::size_t i) {
    Moment M = Moment::Zero();
    for (const auto [k, j] : rel.row(i)) {
      const Basis p = basis((X[j] - X[i]) / h);
      M.noalias() += (V[j] * rel.kernel_value[k]) * (p * p.transpose());
    }
    const Eigen::LDLT<Moment> ldlt(M);
    const bool quadratic = ldlt.info() == Eigen::Success && ldlt.isPositive() && ldlt.rcond() > Real(1e-4);
    for (const auto [k, j] : rel.row(i)) {
      corrected[k] = V[j] * (B[i] * pair_gradient_[k].vector().template cast<Real>());
      if (!quadratic) {
        weights[k] = corrected[k];
        if (gauss) curvature[k].setZero();  // no gradient of F: the Gauss points see F_i
        continue;
      }
      const Basis solution = (V[j] * rel.kernel_value[k]) * ldlt.solve(basis((X[j] - X[i]) / h));
      weights[k] = solution.template head<Dim>() / h;
      if (gauss)
        for (int d = 0; d < Dim; ++d)
          for (int e = 0; e < Dim; ++e) curvature[k](e, d) = solution[monomial[d][e]] * Real(d == e ? 2 : 1) / (h * h);
    }
  });
  // a_ji beside a_ij (the relation is symmetric: i is among the neighbours of j), and sum_j a_ij.
  std::vector<std::size_t> reverse(rel.n_pairs());
  parallel_for(n, [&](std::size_t i) {
    for (const auto [k, j] : rel.row(i)) {
      std::size_t r = rel.offsets[j];
      while (r < rel.offsets[j + 1] && rel.neighbour[r] != i) ++r;
      if (r == rel.offsets[j + 1]) throw std::logic_error("solid: the inner relation is not symmetric");
      reverse[k] = r;
    }
  });
  // The stiffest mode: a Gershgorin bound of the stiffness sum_i V_i G_i^T G_i of the map G_i from
  // the positions to F_i (G_ik = a_ik for a neighbour k, -sum_j a_ij for k = i), per unit volume,
  //   lambda = max_k 1/V_k sum_i V_i |G_ik| sum_l |G_il|,
  // for both reconstructions. The acoustic step is divided by sqrt(lambda_quadratic / lambda_corrected),
  // so that acoustic_cfl keeps the meaning it has for the corrected gradient.
  auto gershgorin = [&](const std::vector<Vec<Dim>>& a) {
    std::vector<Vec<Dim>> sum(n, Vec<Dim>::Zero());
    std::vector<Real> row(n, 0);
    parallel_for(n, [&](std::size_t i) {
      for (const auto [k, j] : rel.row(i)) {
        sum[i] += a[k];
        row[i] += a[k].norm();
      }
      row[i] += sum[i].norm();
    });
    return parallel_max(n, Real(0), [&](std::size_t i) {
      Real bound = sum[i].norm() * row[i];
      for (const auto [k, j] : rel.row(i))
        bound += V[j] / V[i] * a[reverse[k]].norm() * row[j];
      return bound;
    });
  };
  if (gauss) {
    cell_size_.resize(n);
    parallel_for(n, [&](std::size_t i) { cell_size_[i] = std::pow(V[i], Real(1) / Dim); });
  }
  // With Gauss points the stiffness is the mean over the points of the maps to F_g, whose weights
  // are a_ij + sum_d xi_gd c_ij.col(d): bounded by the largest of their bounds.
  Real stiffest = gershgorin(weights);
  if (gauss) {
    std::vector<Vec<Dim>> point(rel.n_pairs());
    for (const Vec<Dim>& u : cell_quadrature_points<Dim>()) {
      parallel_for(n, [&](std::size_t i) {
        for (const auto [k, j] : rel.row(i)) point[k] = weights[k] + cell_size_[i] * (curvature[k] * u);
      });
      stiffest = std::max(stiffest, gershgorin(point));
    }
  }
  const Real ratio = stiffest / gershgorin(corrected);
  step_factor_ = ratio > 1 ? 1 / std::sqrt(ratio) : Real(1);
  if (gauss) {
    pair_curvature_.resize(rel.n_pairs());
    c_sum_.assign(n, Mat<Dim>::Zero());
    gauss_moment_.assign(n, {});
    parallel_for(n, [&](std::size_t i) {
      for (const auto [k, j] : rel.row(i)) {
        pair_curvature_[k].c = curvature[k].template cast<PairReal>();
        pair_curvature_[k].reverse = curvature[reverse[k]].template cast<PairReal>();
        c_sum_[i] += pair_curvature_[k].c.template cast<Real>();
      }
      for (auto& moment : gauss_moment_[i]) moment.setZero();
    });
  }
  pair_weights_.resize(rel.n_pairs());
  a_sum_.assign(n, Vec<Dim>::Zero());
  parallel_for(n, [&](std::size_t i) {
    for (const auto [k, j] : rel.row(i)) {
      pair_weights_[k].a = weights[k].template cast<PairReal>();
      pair_weights_[k].reverse = weights[reverse[k]].template cast<PairReal>();
      a_sum_[i] += pair_weights_[k].a.template cast<Real>();
    }
    B[i].setIdentity();
  });
}

template <int Dim>
void ElasticSolid<Dim>::check_indices(const std::vector<Index>& particles, const char* what) const {
  for (const Index i : particles)
    if (i >= particles_.n_particles())
      throw std::invalid_argument("solid '" + particles_.name() + "': " + what + " names particle " +
                                  std::to_string(i) + " of " + std::to_string(particles_.n_particles()));
}

template <int Dim>
void ElasticSolid<Dim>::clamp(std::vector<Index> particles) {
  check_indices(particles, "clamp");
  clamped_.insert(clamped_.end(), particles.begin(), particles.end());
}

template <int Dim>
void ElasticSolid<Dim>::clamp_by_reflection(std::vector<Index> particles, const Vec<Dim>& point, const Vec<Dim>& normal) {
  check_indices(particles, "clamp by reflection");
  if (particles_.partition())
    throw std::invalid_argument("solid '" + particles_.name() + "': a clamp by reflection does not run on several ranks (a "
                                "held particle's mirror may lie on another rank); use a fixed clamp");
  if (!(normal.norm() > 0) || !normal.allFinite() || !point.allFinite())
    throw std::invalid_argument("solid '" + particles_.name() + "': clamp by reflection needs a finite point and a non-zero normal");
  const std::size_t n = particles_.n_particles();
  const Vec<Dim> unit = normal.normalized();
  const auto X = particles_.field(reference_position_);
  const auto& rel = relation_;
  clamped_.insert(clamped_.end(), particles.begin(), particles.end());
  std::vector<char> clamped(n, 0);
  for (const Index i : clamped_) clamped[i] = 1;
  if (rigid_.empty()) rigid_.assign(n, 0);
  for (const Index i : particles) rigid_[i] = 1;
  const Real tolerance = Real(1e-3) * rel.smoothing_length;
  for (const Index g : particles) {
    std::size_t k = rel.offsets[g];
    while (k < rel.offsets[g + 1] && clamped[rel.neighbour[k]]) ++k;
    if (k == rel.offsets[g + 1]) continue;  // no free neighbour: simply held
    // Walk from the free neighbour towards the mirror image through the neighbour lists.
    const Vec<Dim> image = X[g] - 2 * (X[g] - point).dot(unit) * unit;
    Index m = rel.neighbour[k];
    for (bool closer = true; closer;) {
      closer = false;
      for (std::size_t r = rel.offsets[m]; r < rel.offsets[m + 1]; ++r)
        if ((X[rel.neighbour[r]] - image).squaredNorm() < (X[m] - image).squaredNorm()) {
          m = rel.neighbour[r];
          closer = true;
        }
    }
    if ((X[m] - image).norm() > tolerance || clamped[m])
      throw std::invalid_argument("solid '" + particles_.name() + "': clamp by reflection: particle " + std::to_string(g) + " at " +
                                  NumericalFailure::format_position(X[g]) + " has no free particle at its mirror image " +
                                  NumericalFailure::format_position(image));
    reflected_.emplace_back(g, m);
  }
  mirror_force_.assign(n, Vec<Dim>::Zero());
}

template <int Dim>
void ElasticSolid<Dim>::slide(std::vector<Index> particles, int component) {
  check_indices(particles, "slide");
  if (component < 0 || component >= Dim) throw std::invalid_argument("solid: sliding component out of range");
  sliding_.emplace_back(std::move(particles), component);
}

template <int Dim>
void ElasticSolid<Dim>::prescribe_motion(std::vector<Index> particles, Motion position, Motion velocity) {
  check_indices(particles, "prescribed motion");
  prescribed_.push_back({std::move(particles), std::move(position), std::move(velocity)});
}

template <int Dim>
void ElasticSolid<Dim>::add_pressure_load(std::vector<Index> particles, std::vector<Vec<Dim>> area_normal,
                                          std::function<Real(Real)> pressure) {
  check_indices(particles, "pressure load");
  if (area_normal.size() != particles.size()) throw std::invalid_argument("solid: one area normal per loaded particle");
  pressure_loads_.push_back({std::move(particles), std::move(area_normal), std::move(pressure)});
}

template <int Dim>
void ElasticSolid<Dim>::add_traction_load(std::vector<Index> particles, std::vector<Real> area,
                                          std::function<Vec<Dim>(Real)> traction) {
  check_indices(particles, "traction load");
  if (area.size() != particles.size()) throw std::invalid_argument("solid: one area per loaded particle");
  traction_loads_.push_back({std::move(particles), std::move(area), std::move(traction)});
}

template <int Dim>
FieldHandle<Vec<Dim>> ElasticSolid<Dim>::external_force_field() {
  if (!external_force_.valid())
    external_force_ = particles_.template register_field<Vec<Dim>>("external_force", Vec<Dim>::Zero(), false);
  return external_force_;
}

template <int Dim>
void ElasticSolid<Dim>::compute_deformation_gradient() {
  update_ghosts(particles_, std::span<Vec<Dim>>(particles_.position));  // the ghosts as their owners left them
  const auto& x = particles_.position;
  const auto& V = particles_.volume;
  const auto B = particles_.field(correction_matrix_);
  auto F = particles_.field(deformation_gradient_);
  parallel_for(particles_.n_owned(), [&](std::size_t i) { F[i] = deformation_gradient_of(i, x, V, B); });
}

template <int Dim>
Mat<Dim> ElasticSolid<Dim>::deformation_gradient_of(std::size_t i, std::span<const Vec<Dim>> x, std::span<const Real> V,
                                                    std::span<const Mat<Dim>> B, Mat<Dim>* hourglass_sum) const {
  // F_i = - sum_j V_j x_ij (x) (B_i grad0 W_ij) = - (sum_j V_j x_ij (x) grad0 W_ij) B_i^T
  const auto& rel = relation_;
  const Vec<Dim> x_i = x[i];
  Mat<Dim> moment = Mat<Dim>::Zero(), S = Mat<Dim>::Zero();
  const auto add_hourglass = [&](std::size_t k, std::size_t j) {
    if (hourglass_sum)
      S.noalias() += (V[j] * Real(pair_gradient_[k].hourglass_weight)) * (x_i - x[j]) *
                     pair_offset_[k].template cast<Real>().transpose();
  };
  if (!pair_weights_.empty()) {  // quadratic: F_i = sum_j (x_j - x_i) (x) a_ij
    for (const auto [k, j] : rel.row(i)) {
      moment.noalias() += (x[j] - x_i) * pair_weights_[k].a.transpose().template cast<Real>();
      add_hourglass(k, j);
    }
    if (hourglass_sum) *hourglass_sum = S;
    return moment;
  }
  for (const auto [k, j] : rel.row(i)) {
    const Vec<Dim> w = V[j] * pair_gradient_[k].vector().template cast<Real>();
    moment.noalias() += (x_i - x[j]) * w.transpose();
    add_hourglass(k, j);
  }
  if (hourglass_sum) *hourglass_sum = S;
  return -moment * B[i].transpose();
}

template <int Dim>
std::array<Mat<Dim>, Dim> ElasticSolid<Dim>::gradient_of_deformation(std::size_t i, std::span<const Vec<Dim>> x) const {
  const auto& rel = relation_;
  std::array<Mat<Dim>, Dim> G;
  for (auto& Gd : G) Gd.setZero();
  const Vec<Dim> x_i = x[i];
  for (const auto [k, j] : rel.row(i)) {
    const Vec<Dim> dx = x[j] - x_i;
    const Mat<Dim> c = pair_curvature_[k].c.template cast<Real>();
    for (int d = 0; d < Dim; ++d) G[d].noalias() += dx * c.col(d).transpose();
  }
  return G;
}

template <int Dim>
template <class Law>
Real ElasticSolid<Dim>::cell_energy(std::size_t i, const Law& law, const Mat<Dim>& F_i, std::span<const Vec<Dim>> x) const {
  const Vec<Dim> f = fibre_.valid() ? particles_.field(fibre_)[i] : Vec<Dim>::Zero();
  const Vec<Dim> s = sheet_.valid() ? particles_.field(sheet_)[i] : Vec<Dim>::Zero();
  if (pair_curvature_.empty()) return law.energy(F_i, f, s);
  const auto G = gradient_of_deformation(i, x);
  Real sum = 0;
  for (const Vec<Dim>& u : cell_quadrature_points<Dim>()) {
    Mat<Dim> Fg = F_i;
    for (int d = 0; d < Dim; ++d) Fg += (cell_size_[i] * u[d]) * G[d];
    sum += law.energy(Fg, f, s);
  }
  return sum / Real(Dim + 1);
}

template <int Dim>
std::size_t ElasticSolid<Dim>::compute_deformation_and_stress() {
  // One pass over the particles: F_i from its pair sum, then, if F_i is valid, P_i B0_i from the
  // law (only particle i's stress needs F_i). Returns the first particle with an invalid F (or n).
  const auto& x = particles_.position;
  const auto& V = particles_.volume;
  const auto B = particles_.field(correction_matrix_);
  auto F = particles_.field(deformation_gradient_);
  auto PB = particles_.field(stress_correction_);
  const std::size_t n = particles_.n_owned();
  const bool gauss = !pair_curvature_.empty();
  const auto points = cell_quadrature_points<Dim>();
  return std::visit(
      [&](const auto& law) {
        using Law = std::decay_t<decltype(law)>;
        const auto f = anisotropic_field(fibre_);
        const auto s = anisotropic_field(sheet_);
        const std::span<const Real> T =
            active_tension_.valid() ? std::span<const Real>(particles_.field(active_tension_)) : std::span<const Real>();
        const std::span<const Real> K =
            active_stiffness_.valid() ? std::span<const Real>(particles_.field(active_stiffness_)) : std::span<const Real>();
        const std::span<const Real> L0 = active_reference_stretch_.valid()
                                             ? std::span<const Real>(particles_.field(active_reference_stretch_))
                                             : std::span<const Real>();
        const bool non_negative = settings_.active_tension_non_negative;
        return first_index_where(n, [&](std::size_t i) {
          Mat<Dim> S;  // with energy-based hourglass control, H_i = F_i M_i - S_i (docs/solid.md)
          const Mat<Dim> Fi = deformation_gradient_of(i, x, V, B, energy_hourglass_ ? &S : nullptr);
          F[i] = Fi;
          const bool rigid = !rigid_.empty() && rigid_[i];  // in a clamp by reflection: F is a mirror image
          const Real J = Fi.determinant();
          if (!rigid && (!(J > 0) || !Fi.allFinite())) {
            PB[i].setZero();
            return true;
          }
          auto stress_at = [&](const Mat<Dim>& Fg) -> Mat<Dim> {
            if constexpr (Law::anisotropic) {
              Mat<Dim> Sg = law.second_piola(Fg, f[i], s[i]);
              if (!T.empty()) {
                Real tension = T[i];
                if (!K.empty()) {
                  tension += K[i] * ((Fg * f[i]).norm() - L0[i]);
                  if (non_negative) tension = std::max(tension, Real(0));
                }
                Sg.noalias() += tension * (f[i] * f[i].transpose());
              }
              return Fg * Sg;
            }
            const Vec<Dim> none = Vec<Dim>::Zero();
            return Fg * law.second_piola(Fg, none, none);
          };
          Mat<Dim> P = Mat<Dim>::Zero();
          if (gauss) {
            auto& Q = gauss_moment_[i];
            for (auto& Qd : Q) Qd.setZero();
            if (!rigid) {  // the mean of P and of xi_d P over the Dim + 1 Gauss points of the cell
              const auto G = gradient_of_deformation(i, x);
              for (const Vec<Dim>& u : points) {
                const Vec<Dim> xi = cell_size_[i] * u;
                Mat<Dim> Fg = Fi;
                for (int d = 0; d < Dim; ++d) Fg += xi[d] * G[d];
                if (!(Fg.determinant() > 0) || !Fg.allFinite()) {
                  PB[i].setZero();
                  return true;
                }
                const Mat<Dim> Pg = stress_at(Fg);
                P += Pg;
                for (int d = 0; d < Dim; ++d) Q[d] += xi[d] * Pg;
              }
              P /= Real(Dim + 1);
              for (auto& Qd : Q) Qd /= Real(Dim + 1);
            }
          } else if (!rigid) {
            P = stress_at(Fi);  // (a clamp by reflection stores no strain energy)
          }
          if (energy_hourglass_) P.noalias() += hourglass_factor_ * (Fi * hourglass_moment_[i] - S);
          PB[i].noalias() = P * B[i];
          return false;
        });
      },
      settings_.material);
}

template <int Dim>
void ElasticSolid<Dim>::update_current_sound_speed() {
  const auto F = particles_.field(deformation_gradient_);
  const bool anisotropic = fibre_.valid();
  const Real largest = std::visit(
      [&](const auto& law) {
        return parallel_max(particles_.n_owned(), Real(0), [&](std::size_t i) {
          const Vec<Dim> f = anisotropic ? particles_.field(fibre_)[i] : Vec<Dim>::Zero();
          const Vec<Dim> s = anisotropic ? particles_.field(sheet_)[i] : Vec<Dim>::Zero();
          const Mat<Dim> P = first_piola<Dim>(law, F[i], f, s);
          const Real delta = Real(1e-6);
          Real modulus = 0;
          for (int d = 0; d <= Dim; ++d) {
            const Vec<Dim> e = d < Dim ? Vec<Dim>::Unit(d) : f;
            if (d == Dim && !anisotropic) break;
            const Mat<Dim> E = e * e.transpose();
            const Mat<Dim> dP = first_piola<Dim>(law, Mat<Dim>(F[i] + delta * E), f, s) - P;
            modulus = std::max(modulus, (dP.cwiseProduct(E)).sum() / delta);
          }
          if (active_stiffness_.valid()) modulus += particles_.field(active_stiffness_)[i];
          return std::isfinite(modulus) ? modulus : Real(0);
        });
      },
      settings_.material);
  current_sound_speed_ = std::max(sound_speed_, std::sqrt(global_max(particles_, largest) * inverse_inertia_));
}

template <int Dim>
Vec<Dim> ElasticSolid<Dim>::stress_divergence_of(std::size_t i, std::span<const Real> V, std::span<const Mat<Dim>> PB) const {
  const auto& rel = relation_;
  Vec<Dim> force = Vec<Dim>::Zero();
  if (!pair_weights_.empty()) {  // P_i sum_j a_ij - sum_j (V_j / V_i) P_j a_ji
    for (const auto [k, j] : rel.row(i))
      force.noalias() += V[j] * (PB[j] * pair_weights_[k].reverse.template cast<Real>());
    return PB[i] * a_sum_[i] - force / V[i];
  }
  Vec<Dim> weighted_sum = Vec<Dim>::Zero();  // sum_j V_j (P_i B_i + P_j B_j) grad0 W_ij
  for (const auto [k, j] : rel.row(i)) {
    const Vec<Dim> w = V[j] * pair_gradient_[k].vector().template cast<Real>();
    weighted_sum += w;
    force.noalias() += PB[j] * w;
  }
  return force + PB[i] * weighted_sum;
}

template <int Dim>
template <bool Quadratic, int Hourglass, bool Viscous>
Vec<Dim> ElasticSolid<Dim>::internal_force_of(std::size_t i, std::span<const Vec<Dim>> x, std::span<const Real> V,
                                              std::span<const Mat<Dim>> F, std::span<const Mat<Dim>> PB) const {
  // sum_j V_j (P_i B_i + P_j B_j) grad0 W_ij + alpha E / 2 sum_j V_j W_ij / |X_ij|^2 (delta_ij^i + delta_ij^j) x_ij / |x_ij|
  // (divided by V_i: the force per unit reference volume), with the P_i B_i term taken out of the loop.
  // Quadratic: P_i sum_j a_ij - sum_j (V_j / V_i) P_j a_ji in place of the first sum. Energy-based
  // hourglass control: the pair part alpha E / 2 sum_j V_j W_ij / |X_ij|^2 ((F_i + F_j) X_ij - 2 x_ij)
  // in place of the second (its F-part is in PB).
  const auto& rel = relation_;
  const Vec<Dim> x_i = x[i];
  const Mat<Dim> F_i = F[i];
  Vec<Dim> weighted_sum = Vec<Dim>::Zero(), stress_force = Vec<Dim>::Zero(), hourglass_force = Vec<Dim>::Zero(),
           viscous_force = Vec<Dim>::Zero(), viscous_weighted_sum = Vec<Dim>::Zero();
  const auto& v = previous_velocity_;  // the velocities at the start of the step (the field is being updated)
  const Vec<Dim> v_i = v[i];
  const bool gauss = !pair_curvature_.empty();  // Gauss points: + sum_d Q_d,i c_sum_i.col(d) - sum_j (V_j / V_i) sum_d Q_d,j c_ji.col(d)
  for (const auto [k, j] : rel.row(i)) {
    const PairGradient& g = pair_gradient_[k];
    const Vec<Dim> w = V[j] * g.vector().template cast<Real>();  // V_j grad0 W_ij
    if constexpr (Quadratic) {
      stress_force.noalias() += V[j] * (PB[j] * pair_weights_[k].reverse.template cast<Real>());
      if (gauss) {  // sum_d Q_d,j c_ji.col(d)
        const Mat<Dim> c = pair_curvature_[k].reverse.template cast<Real>();
        for (int d = 0; d < Dim; ++d) stress_force.noalias() += V[j] * (gauss_moment_[j][d] * c.col(d));
      }
    } else {
      weighted_sum += w;
      stress_force.noalias() += PB[j] * w;
    }
    if constexpr (Hourglass == penalty_hourglass) {
      const Vec<Dim> x_ij = x_i - x[j];
      const Vec<Dim> X_ij = pair_offset_[k].template cast<Real>();
      const Real delta_r = ((F_i + F[j]) * X_ij - 2 * x_ij).dot(x_ij);  // (delta_i + delta_j) |x_ij|
      hourglass_force += (V[j] * Real(g.hourglass_weight) * delta_r / x_ij.squaredNorm()) * x_ij;
    } else if constexpr (Hourglass == energy_hourglass) {  // e_ij - e_ji, the rest is in the stress
      const Vec<Dim> X_ij = pair_offset_[k].template cast<Real>();
      hourglass_force += (V[j] * Real(g.hourglass_weight)) * ((F_i + F[j]) * X_ij - 2 * (x_i - x[j]));
    }
    if constexpr (Viscous) {  // W_ij / |X_ij|^2 (x_ij . v_ij) (F_i + F_j) V_j grad0 W_ij, the F_i part summed apart
      const Real rate = Real(g.hourglass_weight) * (x_i - x[j]).dot(v_i - v[j]);
      const Vec<Dim> rate_w = rate * w;
      viscous_weighted_sum += rate_w;
      viscous_force.noalias() += F[j] * rate_w;
    }
  }
  if constexpr (Quadratic) {
    Vec<Dim> own = PB[i] * a_sum_[i];
    if (gauss)
      for (int d = 0; d < Dim; ++d) own.noalias() += gauss_moment_[i][d] * c_sum_[i].col(d);
    stress_force = own - stress_force / V[i];
  }
  else
    stress_force.noalias() += PB[i] * weighted_sum;
  if constexpr (Viscous) stress_force += viscosity_factor_ * (viscous_force + F_i * viscous_weighted_sum);
  if constexpr (Hourglass != no_hourglass) return stress_force + hourglass_factor_ * hourglass_force;
  return stress_force;
}

template <int Dim>
void ElasticSolid<Dim>::compute_load_accelerations(Real time) {
  // Pressure, force and traction loads at the current positions and F, as accelerations.
  if (pressure_loads_.empty() && !external_force_.valid() && traction_loads_.empty()) return;
  const auto& V = particles_.volume;
  const auto F = particles_.field(deformation_gradient_);
  std::fill(load_acceleration_.begin(), load_acceleration_.end(), Vec<Dim>::Zero());
  for (const auto& load : pressure_loads_) {
    const Real p = load.pressure(time);
    for (std::size_t k = 0; k < load.particles.size(); ++k) {
      const Index i = load.particles[k];
      // Nanson: n da = J F^-T N dA.
      const Mat<Dim> cofactor = F[i].determinant() * F[i].inverse().transpose();
      load_acceleration_[i] -= p * (cofactor * load.area_normal[k]) * (inverse_inertia_ / V[i]);
    }
  }
  if (external_force_.valid()) {
    const auto f = particles_.field(external_force_);
    parallel_for(f.size(), [&](std::size_t i) { load_acceleration_[i] += f[i] * (inverse_inertia_ / V[i]); });
  }
  for (const auto& load : traction_loads_) {
    const Vec<Dim> t = load.traction(time);
    for (std::size_t k = 0; k < load.particles.size(); ++k) {
      const Index i = load.particles[k];
      load_acceleration_[i] += t * (load.area[k] * inverse_inertia_ / V[i]);
    }
  }
}

template <int Dim>
template <class Finish>
typename ElasticSolid<Dim>::StepCheck ElasticSolid<Dim>::accelerations(Real time, Finish&& finish) {
  // a_i = (internal force + loads) / (rho0 s) + g / s for every particle, handed to finish(i, a_i),
  // which returns whether particle i's state is finite; the largest |a| and the first non-finite
  // particle come back (a reduction in fixed blocks: the same for any thread count).
  compute_load_accelerations(time);
  const auto& x = particles_.position;
  const auto& V = particles_.volume;
  const auto F = particles_.field(deformation_gradient_);
  const auto PB = particles_.field(stress_correction_);
  const bool loads = !(pressure_loads_.empty() && !external_force_.valid() && traction_loads_.empty());
  const Vec<Dim> g = settings_.body_force * (1 / settings_.numerics.mass_scaling);
  const std::size_t n = particles_.n_owned();
  const bool reflections = !reflected_.empty();
  auto run = [&]<bool Quadratic, int Hourglass, bool Viscous>() {
    if (reflections) {  // the force on a reflected particle acts on its mirror, reversed (u' = -u)
      std::fill(mirror_force_.begin(), mirror_force_.end(), Vec<Dim>::Zero());
      for (const auto& [held, m] : reflected_)
        mirror_force_[m] -= (V[held] / V[m]) * internal_force_of<Quadratic, Hourglass, Viscous>(held, x, V, F, PB);
    }
    return parallel_reduce(
        n, StepCheck{0, n},
        [&](std::size_t i) {
          Vec<Dim> a_i = inverse_inertia_ * internal_force_of<Quadratic, Hourglass, Viscous>(i, x, V, F, PB) + g;
          if (loads) a_i += load_acceleration_[i];
          if (reflections) a_i += inverse_inertia_ * mirror_force_[i];
          const bool finite = finish(i, a_i);
          return StepCheck{finite ? a_i.norm() : Real(0), finite ? n : i};
        },
        [](const StepCheck& p, const StepCheck& q) { return StepCheck{std::max(p.max_acceleration, q.max_acceleration), std::min(p.first_bad, q.first_bad)}; });
  };
  auto with_hourglass = [&]<bool Quadratic, bool Viscous>() {
    if (hourglass_factor_ == 0) return run.template operator()<Quadratic, no_hourglass, Viscous>();
    if (energy_hourglass_) return run.template operator()<Quadratic, energy_hourglass, Viscous>();
    return run.template operator()<Quadratic, penalty_hourglass, Viscous>();
  };
  auto with_terms = [&]<bool Quadratic>() {
    if (viscosity_factor_ > 0) return with_hourglass.template operator()<Quadratic, true>();
    return with_hourglass.template operator()<Quadratic, false>();
  };
  if (!pair_weights_.empty()) return with_terms.template operator()<true>();
  return with_terms.template operator()<false>();
}

template <int Dim>
void ElasticSolid<Dim>::compute_acceleration(Real time) {
  auto a = particles_.field(acceleration_);
  accelerations(time, [&](std::size_t i, const Vec<Dim>& a_i) {
    a[i] = a_i;
    return true;
  });
}

template <int Dim>
void ElasticSolid<Dim>::apply_position_constraints(Real time) {
  auto& x = particles_.position;
  const auto X = particles_.field(reference_position_);
  for (const Index i : clamped_) x[i] = X[i];
  for (const auto& [g, m] : reflected_) x[g] = X[g] - (x[m] - X[m]);
  for (const auto& [set, component] : sliding_)
    for (const Index i : set) x[i][component] = X[i][component];
  for (const auto& motion : prescribed_)
    for (const Index i : motion.particles) x[i] = motion.position(X[i], time);
}

template <int Dim>
void ElasticSolid<Dim>::apply_velocity_constraints(Real time) {
  auto v = particles_.field(velocity_);
  const auto X = particles_.field(reference_position_);
  for (const Index i : clamped_) v[i].setZero();
  for (const auto& [g, m] : reflected_) v[g] = -v[m];
  for (const auto& [set, component] : sliding_)
    for (const Index i : set) v[i][component] = 0;
  for (const auto& motion : prescribed_)
    for (const Index i : motion.particles) v[i] = motion.velocity(X[i], time);
}

template <int Dim>
void ElasticSolid<Dim>::fail(const GlobalParticle<Dim>& particle, Real time, const std::string& quantity, const std::string& problem) {
  // Undo the step on every rank: the particle set is left in the last good state, consistent with its F.
  const std::size_t owned = particles_.n_owned();
  std::copy_n(previous_position_.begin(), owned, particles_.position.begin());
  const auto v = particles_.field(velocity_);
  std::copy_n(previous_velocity_.begin(), owned, v.begin());
  update_output_fields();
  throw NumericalFailure(particles_.name(), particle.id, NumericalFailure::format_position(particle.position), time, quantity, problem);
}

template <int Dim>
Stage ElasticSolid<Dim>::stage(std::string name) {
  Stage step{std::move(name), [this] { return stable_time_step(); }, {}};
  step.then("half drift", [this](Real t, Real dt) { half_drift(t, dt); })
      .then("deformation and stress", [this](Real t, Real dt) { deformation_and_stress(t, dt); })
      .slot(loads_slot())
      .then("kick and drift", [this](Real t, Real dt) { kick_and_drift(t, dt); });
  return step;
}

template <int Dim>
void ElasticSolid<Dim>::half_drift(Real time, Real dt) {
  auto& x = particles_.position;
  auto v = particles_.field(velocity_);
  const Real half = dt / 2;
  parallel_for(particles_.n_owned(), [&](std::size_t i) {
    previous_position_[i] = x[i];
    previous_velocity_[i] = v[i];
    x[i] += half * v[i];
  });
  apply_position_constraints(time + half);
  // Distributed: the ghosts' mid-step positions (and start velocities, read by the pair viscosity).
  if (viscosity_factor_ > 0) update_ghosts(particles_, std::span<Vec<Dim>>(x), std::span<Vec<Dim>>(previous_velocity_));
  else update_ghosts(particles_, std::span<Vec<Dim>>(x));
}

template <int Dim>
void ElasticSolid<Dim>::deformation_and_stress(Real time, Real dt) {
  // Two passes over the pairs in a step: this one (F and the stress), then the forces with the
  // velocity update (kick_and_drift).
  const Real half = dt / 2;
  const std::size_t bad = compute_deformation_and_stress();
  if (const auto first = first_over_ranks(particles_, bad); first.found) {
    const double J = value_of_owner(particles_, first, bad, bad < particles_.n_owned() ? double(particles_.field(deformation_gradient_)[bad].determinant()) : 0.0);
    const std::string problem = !std::isfinite(J) ? "is not finite"
                                : J > 0 ? "is inverted at a Gauss point of the particle's cell (J = " + NumericalFailure::format_value(J) + " at the particle)"
                                        : "has J = " + NumericalFailure::format_value(J) + " <= 0 (inverted)";
    fail(first, time + half, "deformation gradient", problem);
  }
  update_ghosts(particles_, particles_.field(deformation_gradient_), particles_.field(stress_correction_));
  if (steps_++ % static_cast<std::size_t>(settings_.numerics.stiffness_update_interval) == 0 &&
      settings_.numerics.tangent_time_step)
    update_current_sound_speed();
  if (external_force_.valid()) {
    auto f = particles_.field(external_force_);
    std::fill(f.begin(), f.end(), Vec<Dim>::Zero());
  }
}

template <int Dim>
void ElasticSolid<Dim>::kick_and_drift(Real time, Real dt) {
  auto& x = particles_.position;
  auto v = particles_.field(velocity_);
  auto a = particles_.field(acceleration_);
  const std::size_t n = particles_.n_owned();
  const Real half = dt / 2;
  const Real damping = 1 / (1 + settings_.damping_rate * dt);
  const StepCheck check = accelerations(time + half, [&](std::size_t i, const Vec<Dim>& a_i) {
    a[i] = a_i;
    v[i] = (v[i] + dt * a_i) * damping;
    return a_i.allFinite() && v[i].allFinite();
  });
  if (const auto first = first_over_ranks(particles_, check.first_bad); first.found) {
    const std::size_t bad = check.first_bad;
    const bool acceleration_finite = value_of_owner(particles_, first, bad, bad < n && a[bad].allFinite() ? 1.0 : 0.0) > 0;
    fail(first, time + dt, acceleration_finite ? "velocity" : "acceleration", "is not finite");
  }
  apply_velocity_constraints(time + dt);
  parallel_for(n, [&](std::size_t i) { x[i] += half * v[i]; });
  apply_position_constraints(time + dt);
  max_acceleration_ = global_max(particles_, check.max_acceleration);
}

template <int Dim>
Real ElasticSolid<Dim>::stable_time_step() const {
  if (settings_.numerics.fixed_time_step > 0) return settings_.numerics.fixed_time_step;
  const auto v = particles_.field(velocity_);
  const Real max_speed = global_max(particles_, parallel_max(particles_.n_owned(), Real(0), [&](std::size_t i) { return v[i].norm(); }));
  const Real h = relation_.smoothing_length;
  Real dt = h / (current_sound_speed_ + max_speed);
  if (max_acceleration_ > 0) dt = std::min(dt, std::sqrt(h / max_acceleration_));
  return settings_.numerics.cfl * step_factor_ * dt;
}

template <int Dim>
Mat<Dim> ElasticSolid<Dim>::cauchy_stress_of(std::size_t i) const {
  const Mat<Dim>& F = particles_.field(deformation_gradient_)[i];
  return std::visit(
      [&](const auto& law) {
        using Law = std::decay_t<decltype(law)>;
        if constexpr (Law::anisotropic) {
          const Vec<Dim>& f = particles_.field(fibre_)[i];
          Mat<Dim> sigma = cauchy_stress<Dim>(law, F, f, particles_.field(sheet_)[i]);
          if (active_tension_.valid()) {  // J^-1 F (T_a f0 (x) f0) F^T
            const Vec<Dim> Ff = F * f;
            sigma += particles_.field(active_tension_)[i] / F.determinant() * (Ff * Ff.transpose());
          }
          return sigma;
        } else
          return cauchy_stress<Dim>(law, F, Vec<Dim>::Zero().eval(), Vec<Dim>::Zero().eval());
      },
      settings_.material);
}

template <int Dim>
void ElasticSolid<Dim>::update_output_fields() {
  compute_deformation_gradient();
  const auto F = particles_.field(deformation_gradient_);
  const auto X = particles_.field(reference_position_);
  auto u = particles_.field(displacement_);
  auto J = particles_.field(jacobian_);
  auto von_mises = particles_.field(von_mises_);
  parallel_for(particles_.n_owned(), [&](std::size_t i) {
    u[i] = particles_.position[i] - X[i];
    J[i] = F[i].determinant();
    const Mat<Dim> sigma = cauchy_stress_of(i);
    if constexpr (Dim == 3) {
      const Mat<Dim> deviator = sigma - sigma.trace() / 3 * Mat<Dim>::Identity();
      von_mises[i] = std::sqrt(Real(1.5) * deviator.squaredNorm());
    } else {  // in-plane components only
      von_mises[i] = std::sqrt(sigma(0, 0) * sigma(0, 0) - sigma(0, 0) * sigma(1, 1) + sigma(1, 1) * sigma(1, 1) +
                               3 * sigma(0, 1) * sigma(0, 1));
    }
  });
  if (fibre_stretch_.valid()) {
    const auto f = particles_.field(fibre_);
    auto stretch = particles_.field(fibre_stretch_);
    parallel_for(particles_.n_owned(), [&](std::size_t i) { stretch[i] = (F[i] * f[i]).norm(); });
  }
}

template <int Dim>
typename ElasticSolid<Dim>::Energies ElasticSolid<Dim>::energies() {
  compute_deformation_gradient();
  const auto F = particles_.field(deformation_gradient_);
  const auto v = particles_.field(velocity_);
  const auto& V = particles_.volume;
  Energies e;
  const auto rigid = [&](std::size_t i) { return !rigid_.empty() && rigid_[i]; };
  // Sums over the particles in global-id order (the same for any rank count).
  e.kinetic = global_sum(particles_, [&](std::size_t i) {
    return rigid(i) ? 0.0 : 0.5 / inverse_inertia_ * V[i] * v[i].squaredNorm();
  });
  std::visit(
      [&](const auto& law) {
        e.strain = global_sum(particles_, [&](std::size_t i) {
          return rigid(i) ? 0.0 : double(V[i] * cell_energy(i, law, F[i], particles_.position));
        });
      },
      settings_.material);
  if (energy_hourglass_) {  // alpha E / 4 sum_i sum_j V_i V_j W_ij / r0^2 |F_i X_ij - x_ij|^2
    const auto& rel = relation_;
    const auto& x = particles_.position;
    e.hourglass = hourglass_factor_ / 2 * global_sum(particles_, [&](std::size_t i) {
      double sum = 0;
      for (const auto [k, j] : rel.row(i)) {
        const Vec<Dim> X_ij = pair_offset_[k].template cast<Real>();
        sum += double(V[i] * V[j] * Real(pair_gradient_[k].hourglass_weight) * (F[i] * X_ij - (x[i] - x[j])).squaredNorm());
      }
      return sum;
    });
  }
  // The J range of the body (the particles of a clamp by reflection carry a mirrored F).
  const Real inf = std::numeric_limits<Real>::infinity();
  const std::size_t owned = particles_.n_owned();
  e.min_jacobian = -global_max(particles_, parallel_max(owned, -inf, [&](std::size_t i) { return rigid(i) ? -inf : -F[i].determinant(); }));
  e.max_jacobian = global_max(particles_, parallel_max(owned, -inf, [&](std::size_t i) { return rigid(i) ? -inf : F[i].determinant(); }));
  return e;
}

template <int Dim>
typename ElasticSolid<Dim>::Residual ElasticSolid<Dim>::equilibrium_residual(Real time) {
  const std::size_t n = particles_.n_particles();
  std::vector<char> constrained(n, 0);
  for (const Index i : clamped_) constrained[i] = 1;
  for (const auto& [set, component] : sliding_)
    for (const Index i : set) constrained[i] = 1;
  for (const auto& motion : prescribed_)
    for (const Index i : motion.particles) constrained[i] = 1;
  update_ghosts(particles_, std::span<Vec<Dim>>(particles_.position));
  compute_deformation_and_stress();
  update_ghosts(particles_, particles_.field(deformation_gradient_), particles_.field(stress_correction_));
  compute_acceleration(time);
  const auto a = particles_.field(acceleration_);
  const auto& V = particles_.volume;
  Residual r;
  r.net = std::sqrt(global_sum(particles_, [&](std::size_t i) {
    return constrained[i] ? 0.0 : double((V[i] / inverse_inertia_ * a[i]).squaredNorm());
  }));
  const bool loads = !(pressure_loads_.empty() && !external_force_.valid() && traction_loads_.empty());
  const Vec<Dim> g = settings_.body_force * (1 / settings_.numerics.mass_scaling);
  r.load = std::sqrt(global_sum(particles_, [&](std::size_t i) {
    if (constrained[i]) return 0.0;
    const Vec<Dim> load = loads ? Vec<Dim>(load_acceleration_[i] + g) : g;
    return double((V[i] / inverse_inertia_ * load).squaredNorm());
  }));
  if (active_tension_.valid()) {
    // The force of the active stress alone, Pa = T_a F f0 (x) f0 in place of P.
    const auto F = particles_.field(deformation_gradient_);
    const auto B = particles_.field(correction_matrix_);
    const auto f = particles_.field(fibre_);
    const auto T = particles_.field(active_tension_);
    std::vector<Mat<Dim>> PB(n);
    parallel_for(particles_.n_owned(), [&](std::size_t i) { PB[i] = T[i] * (F[i] * f[i]) * (B[i].transpose() * f[i]).transpose(); });
    update_ghosts(particles_, std::span<Mat<Dim>>(PB));
    r.active = std::sqrt(global_sum(particles_, [&](std::size_t i) {
      return constrained[i] ? 0.0 : double((V[i] * stress_divergence_of(i, V, PB)).squaredNorm());
    }));
  }
  return r;
}

template <int Dim>
double ElasticSolid<Dim>::hourglass_measure() {
  compute_deformation_gradient();
  const auto F = particles_.field(deformation_gradient_);
  const auto& x = particles_.position;
  const auto& rel = relation_;
  const double sum = global_sum(particles_, [&](std::size_t i) {
    double row = 0;
    for (const auto [k, j] : rel.row(i)) {
      const Vec<Dim> X_ij = rel.distance[k] * rel.unit_vector[k];
      row += (F[i] * X_ij - (x[i] - x[j])).norm() / rel.distance[k];
    }
    return row;
  });
  const double pairs = global_sum(particles_, [&](std::size_t i) { return double(rel.offsets[i + 1] - rel.offsets[i]); });
  return pairs > 0 ? sum / pairs : 0.0;
}

template class ElasticSolid<2>;
template class ElasticSolid<3>;

}  // namespace sph
