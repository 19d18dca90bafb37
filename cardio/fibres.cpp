#include "cardio/fibres.hpp"

#include <Eigen/Geometry>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "cardio/surface_labels.hpp"
#include "libsph/core/correction_matrix.hpp"
#include "libsph/core/kernels.hpp"
#include "libsph/core/neighbour_relation.hpp"
#include "libsph/core/parallel.hpp"

namespace cardio {
namespace {

using geometry::Vec3;
using Frame = Eigen::Matrix3d;  // columns e0, e1, e2
using Clock = std::chrono::steady_clock;

constexpr double degree = 3.14159265358979323846 / 180.0;

Vec3 any_perpendicular(const Vec3& v) {
  const Vec3 trial = std::abs(v.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  return (trial - trial.dot(v) * v).normalized();
}

// [e0 e1 e2]: e1 along u (apex to base), e2 along v orthogonalised (transmural), e0 = e1 x e2.
Frame axis(const Vec3& u, const Vec3& v, const Vec3& fallback_u) {
  Vec3 e1 = u.norm() > 0 ? Vec3(u.normalized()) : fallback_u;
  Vec3 e2 = v - e1.dot(v) * e1;
  e2 = e2.norm() > 1e-12 * std::max(1.0, v.norm()) ? Vec3(e2.normalized()) : any_perpendicular(e1);
  Frame q;
  q.col(0) = e1.cross(e2);
  q.col(1) = e1;
  q.col(2) = e2;
  return q;
}

// Rotates e0 by alpha about e2 (towards e1), then the frame by beta about the new e0.
Frame orient(const Frame& q, double alpha, double beta) {
  Eigen::Matrix3d rz, rx;
  rz << std::cos(alpha), -std::sin(alpha), 0, std::sin(alpha), std::cos(alpha), 0, 0, 0, 1;
  rx << 1, 0, 0, 0, std::cos(beta), -std::sin(beta), 0, std::sin(beta), std::cos(beta);
  return q * rz * rx;
}

// Slerp from a to the frame equivalent to b (axes flipped in pairs) nearest to a.
Frame bislerp(const Frame& a, const Frame& b, double t) {
  const Eigen::Quaterniond qa(a), qb(b);
  const Eigen::Quaterniond candidates[4] = {qb, qb * Eigen::Quaterniond(0, 1, 0, 0), qb * Eigen::Quaterniond(0, 0, 1, 0),
                                            qb * Eigen::Quaterniond(0, 0, 0, 1)};
  int best = 0;
  for (int k = 1; k < 4; ++k)
    if (std::abs(qa.dot(candidates[k])) > std::abs(qa.dot(candidates[best]))) best = k;
  return qa.slerp(std::clamp(t, 0.0, 1.0), candidates[best]).toRotationMatrix();
}

struct DirichletProblem {
  std::vector<char> fixed;  // per particle
  std::vector<std::vector<double>> values;  // per right-hand side, per particle (used where fixed)
};

// Solves the SPH Laplace equation for each right-hand side of `problem`.
std::vector<std::vector<double>> solve_laplace(const sph::InnerRelation<3>& relation, const std::vector<double>& volumes,
                                               const DirichletProblem& problem, double tolerance, FibreField& out) {
  const std::size_t n = volumes.size();
  std::vector<long> unknown(n, -1);
  long n_free = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (!problem.fixed[i]) unknown[i] = n_free++;
  std::vector<Eigen::Triplet<double, long>> triplets;
  triplets.reserve(relation.n_pairs() + n);
  const std::size_t n_rhs = problem.values.size();
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n_free, long(n_rhs));
  for (std::size_t i = 0; i < n; ++i) {
    if (problem.fixed[i]) continue;
    double diagonal = 0;
    for (const auto [k, j] : relation.row(i)) {
      const double r = relation.distance[k];
      if (r <= 0) continue;
      const double c = volumes[i] * volumes[j] * 2 * std::abs(double(relation.kernel_derivative[k])) / r;
      diagonal += c;
      if (problem.fixed[j]) {
        for (std::size_t s = 0; s < n_rhs; ++s) rhs(unknown[i], long(s)) += c * problem.values[s][j];
      } else {
        triplets.emplace_back(unknown[i], unknown[j], -c);
      }
    }
    triplets.emplace_back(unknown[i], unknown[i], diagonal > 0 ? diagonal : 1.0);
  }
  Eigen::SparseMatrix<double, Eigen::RowMajor, long> matrix(n_free, n_free);
  matrix.setFromTriplets(triplets.begin(), triplets.end());
  triplets = {};
  out.matrix_nonzeros += std::size_t(matrix.nonZeros());
  const auto start = Clock::now();
  Eigen::ConjugateGradient<decltype(matrix), Eigen::Lower | Eigen::Upper> solver;
  solver.setTolerance(tolerance);
  solver.setMaxIterations(std::max<long>(1000, 4 * long(std::cbrt(double(n_free))) * 100));
  solver.compute(matrix);
  std::vector<std::vector<double>> solutions(n_rhs, std::vector<double>(n));
  for (std::size_t s = 0; s < n_rhs; ++s) {
    const Eigen::VectorXd x = solver.solve(rhs.col(long(s)));
    if (solver.info() != Eigen::Success)
      throw std::runtime_error("fibres: Laplace solve did not converge (" + std::to_string(solver.iterations()) +
                               " iterations, residual " + std::to_string(solver.error()) +
                               "); is some part of the body disconnected from the labelled surfaces?");
    out.solver_iterations += solver.iterations();
    for (std::size_t i = 0; i < n; ++i) solutions[s][i] = problem.fixed[i] ? problem.values[s][i] : x(unknown[i]);
  }
  out.solver_seconds += std::chrono::duration<double>(Clock::now() - start).count();
  return solutions;
}

std::vector<Vec3> corrected_gradient(const sph::InnerRelation<3>& relation, const std::vector<sph::Mat<3>>& correction,
                                     const std::vector<double>& volumes, const std::vector<double>& u) {
  std::vector<Vec3> g(u.size());
  sph::parallel_for(u.size(), [&](std::size_t i) {
    Vec3 sum = Vec3::Zero();
    for (const auto [k, j] : relation.row(i)) {
      sum += volumes[j] * (u[j] - u[i]) * double(relation.kernel_derivative[k]) * relation.unit_vector[k].cast<double>();
    }
    g[i] = correction[i].cast<double>() * sum;
  });
  return g;
}

}  // namespace

double helix_angle_deg(const Vec3& fibre, const Vec3& circumferential, const Vec3& longitudinal) {
  double angle = std::atan2(fibre.dot(longitudinal), fibre.dot(circumferential)) / degree;
  if (angle > 90) angle -= 180;
  if (angle <= -90) angle += 180;
  return angle;
}

FibreField ldrb_fibres(const std::vector<Vec3>& positions, const std::vector<double>& volumes,
                       const std::vector<std::int8_t>& labels, const Vec3& base_normal, double spacing,
                       const LdrbSettings& settings) {
  const auto start = Clock::now();
  const std::size_t n = positions.size();
  auto count = [&](SurfaceLabel l) { return std::count(labels.begin(), labels.end(), std::int8_t(l)); };
  if (!count(label_epi)) throw std::invalid_argument("fibres: no particle is labelled epicardium");
  if (!count(label_lv_endo)) throw std::invalid_argument("fibres: no particle is labelled LV endocardium");
  if (!count(label_base)) throw std::invalid_argument("fibres: no particle is labelled base (needed for the apico-basal direction)");
  const bool has_rv = count(label_rv_endo) > 0;

  std::vector<sph::Vec<3>> x(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = positions[i].cast<sph::Real>();
  const auto kernel = sph::make_kernel<3>(settings.kernel);
  const auto relation = sph::build_inner_relation<3>(x, kernel, sph::Real(settings.smoothing_ratio * spacing));
  std::vector<sph::Real> real_volumes(volumes.begin(), volumes.end());
  std::vector<sph::Mat<3>> correction(n);
  sph::compute_correction_matrix<3>(relation, real_volumes, correction);

  FibreField field;
  // Transmural problems: one matrix, three right-hand sides.
  DirichletProblem wall;
  wall.fixed.assign(n, 0);
  wall.values.assign(3, std::vector<double>(n, 0.0));
  for (std::size_t i = 0; i < n; ++i) {
    const auto l = labels[i];
    if (l != label_epi && l != label_lv_endo && l != label_rv_endo) continue;
    wall.fixed[i] = 1;
    wall.values[0][i] = l == label_epi ? 1 : 0;
    wall.values[1][i] = l == label_lv_endo ? 1 : 0;
    wall.values[2][i] = l == label_rv_endo ? 1 : 0;
  }
  if (!has_rv) wall.values.pop_back();
  auto coordinates = solve_laplace(relation, volumes, wall, settings.tolerance, field);
  field.transmural = std::move(coordinates[0]);
  field.lv = std::move(coordinates[1]);
  field.rv = has_rv ? std::move(coordinates[2]) : std::vector<double>(n, 0.0);

  // Apico-basal: base 1, apex 0.
  std::size_t apex = n;
  for (std::size_t i = 0; i < n; ++i)
    if (labels[i] == label_epi && (apex == n || positions[i].dot(base_normal) < positions[apex].dot(base_normal))) apex = i;
  DirichletProblem longitudinal;
  longitudinal.fixed.assign(n, 0);
  longitudinal.values.assign(1, std::vector<double>(n, 0.0));
  for (std::size_t i = 0; i < n; ++i) {
    if (labels[i] == label_base) {
      longitudinal.fixed[i] = 1;
      longitudinal.values[0][i] = 1;
    } else if (labels[i] == label_epi && (positions[i] - positions[apex]).norm() < 2 * spacing) {
      longitudinal.fixed[i] = 1;
    }
  }
  field.apicobasal = std::move(solve_laplace(relation, volumes, longitudinal, settings.tolerance, field)[0]);

  const auto g_epi = corrected_gradient(relation, correction, volumes, field.transmural);
  const auto g_lv = corrected_gradient(relation, correction, volumes, field.lv);
  const auto g_rv = corrected_gradient(relation, correction, volumes, field.rv);
  const auto g_psi = corrected_gradient(relation, correction, volumes, field.apicobasal);

  const double alpha_endo = settings.alpha_endo_deg * degree, alpha_epi = settings.alpha_epi_deg * degree;
  const double beta_endo = settings.beta_endo_deg * degree, beta_epi = settings.beta_epi_deg * degree;
  field.fibre.resize(n);
  field.sheet.resize(n);
  sph::parallel_for(n, [&](std::size_t i) {
    const double lv = std::clamp(field.lv[i], 0.0, 1.0), rv = std::clamp(field.rv[i], 0.0, 1.0);
    const double d = lv + rv > 0 ? rv / (lv + rv) : 0.0;
    const double e = std::clamp(field.transmural[i], 0.0, 1.0);
    const double alpha_s = alpha_endo * (1 - 2 * d), beta_s = beta_endo * (1 - 2 * d);
    // Unrotated frames first (they differ little, so the slerps never take the long way round),
    // then the angles, interpolated linearly in e in the final frame.
    Frame a_endo = axis(g_psi[i], -g_lv[i], base_normal);
    if (has_rv) a_endo = bislerp(a_endo, axis(g_psi[i], g_rv[i], base_normal), d);
    const Frame a = bislerp(a_endo, axis(g_psi[i], g_epi[i], base_normal), e);
    // Where the frame was flipped to face the epicardium (RV free wall: grad phi_rv points into the
    // cavity), the endocardial angles change sign.
    const double sign = a_endo.col(2).dot(a.col(2)) >= 0 ? 1.0 : -1.0;
    const Frame q = orient(a, sign * alpha_s * (1 - e) + alpha_epi * e, sign * beta_s * (1 - e) + beta_epi * e);
    field.fibre[i] = q.col(0);
    field.sheet[i] = q.col(2);
  });
  field.total_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return field;
}

FibreField fibres_from_tet_mesh(const std::vector<Vec3>& positions, const geometry::TetMesh& mesh, std::size_t* outside) {
  using Location = geometry::TetMesh::FibreLocation;
  if (mesh.fibre_location == Location::none) throw std::invalid_argument("fibres from the mesh: the mesh has no fibres");
  const geometry::TetLocator locator(mesh);
  const bool sheets = !mesh.sheet.empty();
  FibreField field;
  field.fibre.resize(positions.size());
  if (sheets) field.sheet.resize(positions.size());
  std::vector<std::uint8_t> out(positions.size(), 0);
  sph::parallel_for(positions.size(), [&](std::size_t i) {
    const auto hit = locator.locate(positions[i]);
    out[i] = hit.inside ? 0 : 1;
    Vec3 f, s = Vec3::Zero();
    if (mesh.fibre_location == Location::cells) {
      f = mesh.fibre[hit.tet];
      if (sheets) s = mesh.sheet[hit.tet];
    } else {
      // Blend with signs aligned to the first vertex's vectors.
      const auto& v = mesh.tets[hit.tet];
      const Vec3 f0 = mesh.fibre[v[0]], s0 = sheets ? mesh.sheet[v[0]] : Vec3::Zero();
      f = Vec3::Zero();
      for (std::size_t k = 0; k < 4; ++k) {
        const Vec3& fk = mesh.fibre[v[k]];
        f += hit.weights[k] * (fk.dot(f0) < 0 ? Vec3(-fk) : fk);
        if (sheets) {
          const Vec3& sk = mesh.sheet[v[k]];
          s += hit.weights[k] * (sk.dot(s0) < 0 ? Vec3(-sk) : sk);
        }
      }
    }
    // Four fibres that cancel (a crossing of directions inside one tetrahedron): the largest weight's.
    if (f.norm() < 1e-12) f = mesh.fibre[mesh.tets[hit.tet][std::size_t(std::max_element(hit.weights.begin(), hit.weights.end()) - hit.weights.begin())]];
    f.normalize();
    field.fibre[i] = f;
    if (sheets) {
      s -= s.dot(f) * f;
      field.sheet[i] = s.norm() > 1e-12 ? Vec3(s.normalized()) : any_perpendicular(f);
    }
  });
  if (outside) *outside = std::size_t(std::count(out.begin(), out.end(), std::uint8_t(1)));
  return field;
}

LvEllipsoidFrame lv_ellipsoid_frame(const Vec3& p, const geometry::LvEllipsoid& lv) {
  LvEllipsoidFrame frame;
  const double r = std::hypot(p.x(), p.y());
  // t with (x^2 + y^2) / rs(t)^2 + z^2 / rl(t)^2 = 1, by bisection (the left side falls with t).
  auto level = [&](double t) {
    const double rs = lv.endo_rs + t * (lv.epi_rs - lv.endo_rs), rl = lv.endo_rl + t * (lv.epi_rl - lv.endo_rl);
    return r * r / (rs * rs) + p.z() * p.z() / (rl * rl) - 1;
  };
  double lo = -0.5, hi = 1.5;
  for (int k = 0; k < 60; ++k) (level(0.5 * (lo + hi)) > 0 ? lo : hi) = 0.5 * (lo + hi);
  frame.t = 0.5 * (lo + hi);
  const double rs = lv.endo_rs + frame.t * (lv.epi_rs - lv.endo_rs), rl = lv.endo_rl + frame.t * (lv.epi_rl - lv.endo_rl);
  frame.normal = Vec3(p.x() / (rs * rs), p.y() / (rs * rs), p.z() / (rl * rl)).normalized();
  frame.circumferential = r > 0 ? Vec3(Vec3(-p.y(), p.x(), 0) / r) : Vec3(Vec3::UnitX());
  frame.longitudinal = (Vec3::UnitZ() - frame.normal.z() * frame.normal).normalized();
  return frame;
}

FibreAngleCheck check_lv_ellipsoid_fibres(const std::vector<Vec3>& positions, const FibreField& field,
                                          const geometry::LvEllipsoid& lv, const LdrbSettings& settings, double rim,
                                          double axis) {
  FibreAngleCheck check;
  if (field.transmural.size() != positions.size()) throw std::invalid_argument("fibre check: no transmural coordinate");
  double sum = 0;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const Vec3& p = positions[i];
    if (p.z() > lv.base_z - rim || std::hypot(p.x(), p.y()) < axis) continue;
    const LvEllipsoidFrame frame = lv_ellipsoid_frame(p, lv);
    const double e = std::clamp(field.transmural[i], 0.0, 1.0);
    const double expected = settings.alpha_endo_deg * (1 - e) + settings.alpha_epi_deg * e;
    double deviation = std::abs(helix_angle_deg(field.fibre[i], frame.circumferential, frame.longitudinal) - expected);
    deviation = std::min(deviation, 180 - deviation);  // fibres have no sign
    sum += deviation;
    check.max_deg = std::max(check.max_deg, deviation);
    ++check.particles;
  }
  if (check.particles) check.mad_deg = sum / double(check.particles);
  return check;
}

FibreField uniform_fibres(std::size_t n, const Vec3& fibre, const Vec3& sheet) {
  if (fibre.norm() == 0) throw std::invalid_argument("fibres: the uniform fibre direction is zero");
  const Vec3 f = fibre.normalized();
  Vec3 s = sheet - sheet.dot(f) * f;
  if (s.norm() < 1e-9) throw std::invalid_argument("fibres: the uniform sheet direction is parallel to the fibre");
  FibreField field;
  field.fibre.assign(n, f);
  field.sheet.assign(n, s.normalized());
  return field;
}

FibreField fibres_from_file(const std::vector<Vec3>& positions, const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument("fibre file '" + path.string() + "': cannot be opened");
  std::vector<Vec3> points, fibres, sheets;
  std::string line;
  long number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream words(line);
    std::vector<double> v;
    double value;
    while (words >> value) v.push_back(value);
    if (!words.eof())
      throw std::invalid_argument("fibre file '" + path.string() + "' line " + std::to_string(number) + ": not a number");
    if (v.empty()) continue;
    if (v.size() != 6 && v.size() != 9)
      throw std::invalid_argument("fibre file '" + path.string() + "' line " + std::to_string(number) + ": " +
                                  std::to_string(v.size()) + " values (expected x y z fx fy fz [sx sy sz])");
    for (double c : v)
      if (!std::isfinite(c))
        throw std::invalid_argument("fibre file '" + path.string() + "' line " + std::to_string(number) + ": non-finite value");
    const Vec3 f(v[3], v[4], v[5]);
    if (f.norm() == 0)
      throw std::invalid_argument("fibre file '" + path.string() + "' line " + std::to_string(number) + ": zero fibre");
    points.emplace_back(v[0], v[1], v[2]);
    fibres.push_back(f.normalized());
    Vec3 s = v.size() == 9 ? Vec3(v[6], v[7], v[8]) : any_perpendicular(fibres.back());
    s -= s.dot(fibres.back()) * fibres.back();
    sheets.push_back(s.norm() > 1e-12 ? Vec3(s.normalized()) : any_perpendicular(fibres.back()));
  }
  if (points.empty()) throw std::invalid_argument("fibre file '" + path.string() + "': no points");

  // Nearest point by a uniform grid searched in growing shells.
  Vec3 lower = points[0], upper = points[0];
  for (const auto& p : points) {
    lower = lower.cwiseMin(p);
    upper = upper.cwiseMax(p);
  }
  // About one point per cell; flat or linear point sets are padded so that cells stay cubic.
  const Vec3 extent = (upper - lower).cwiseMax((upper - lower).maxCoeff() / 64 + 1e-9);
  const double cell = 1.5 * std::cbrt(extent.prod() / double(points.size()));
  std::array<long, 3> cells{};
  for (int d = 0; d < 3; ++d) cells[d] = std::max(1L, long(std::ceil(extent[d] / cell)));
  auto cell_of = [&](const Vec3& p, int d) { return std::clamp(long(std::floor((p[d] - lower[d]) / cell)), 0L, cells[d] - 1); };
  std::vector<std::vector<std::size_t>> bins(std::size_t(cells[0] * cells[1] * cells[2]));
  for (std::size_t k = 0; k < points.size(); ++k)
    bins[std::size_t(cell_of(points[k], 0) + cells[0] * (cell_of(points[k], 1) + cells[1] * cell_of(points[k], 2)))].push_back(k);
  FibreField field;
  field.fibre.resize(positions.size());
  field.sheet.resize(positions.size());
  sph::parallel_for(positions.size(), [&](std::size_t i) {
    const Vec3& p = positions[i];
    const long c[3] = {cell_of(p, 0), cell_of(p, 1), cell_of(p, 2)};
    double best = 1e300;
    std::size_t nearest = 0;
    const long max_shell = std::max({cells[0], cells[1], cells[2]});
    for (long shell = 0; shell <= max_shell; ++shell) {
      for (long z = std::max(0L, c[2] - shell); z <= std::min(cells[2] - 1, c[2] + shell); ++z)
        for (long y = std::max(0L, c[1] - shell); y <= std::min(cells[1] - 1, c[1] + shell); ++y)
          for (long xx = std::max(0L, c[0] - shell); xx <= std::min(cells[0] - 1, c[0] + shell); ++xx) {
            if (std::max({std::abs(xx - c[0]), std::abs(y - c[1]), std::abs(z - c[2])}) != shell) continue;
            for (std::size_t k : bins[std::size_t(xx + cells[0] * (y + cells[1] * z))]) {
              const double d = (points[k] - p).squaredNorm();
              if (d < best) {
                best = d;
                nearest = k;
              }
            }
          }
      // Every point not yet visited lies at least shell * cell away (beyond the outer shell's reach).
      if (best < 1e300 && std::sqrt(best) <= double(shell) * cell) break;
    }
    field.fibre[i] = fibres[nearest];
    field.sheet[i] = sheets[nearest];
  });
  return field;
}

}  // namespace cardio
