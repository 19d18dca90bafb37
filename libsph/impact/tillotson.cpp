#include "libsph/impact/tillotson.hpp"

#include <cmath>
#include <stdexcept>

namespace sph {

void TillotsonParameters::check() const {
  auto fail = [](const std::string& what) { throw std::invalid_argument("Tillotson parameters: " + what); };
  if (!(reference_density > 0)) fail("reference density rho0 = " + std::to_string(reference_density) + " must be > 0");
  if (!(A > 0)) fail("A = " + std::to_string(A) + " (the bulk modulus) must be > 0");
  if (!(B >= 0)) fail("B = " + std::to_string(B) + " must be >= 0");
  if (!(e0 > 0)) fail("e0 = " + std::to_string(e0) + " must be > 0");
  if (!(a >= 0) || !(b >= 0)) fail("a = " + std::to_string(a) + " and b = " + std::to_string(b) + " must be >= 0");
  if (!(alpha >= 0) || !(beta >= 0))
    fail("alpha = " + std::to_string(alpha) + " and beta = " + std::to_string(beta) + " must be >= 0");
  if (!(e_iv >= 0) || !(e_cv > e_iv))
    fail("the vaporisation energies e_iv = " + std::to_string(e_iv) + " and e_cv = " + std::to_string(e_cv) +
         " must satisfy 0 <= e_iv < e_cv");
}

const std::vector<TillotsonMaterial>& tillotson_materials() {
  // Benz & Asphaug 1999, Icarus 142:5, table II (SI units).
  static const std::vector<TillotsonMaterial> materials{
      {"basalt", "Benz & Asphaug 1999, Icarus 142:5, table II",
       {2700, 26.7e9, 26.7e9, 487e6, 0.5, 1.5, 5, 5, 4.72e6, 18.2e6}},
      {"granite", "Benz & Asphaug 1999, Icarus 142:5, table II",
       {2680, 18.0e9, 18.0e9, 16.0e6, 0.5, 1.3, 5, 5, 3.5e6, 18.0e6}},
      {"ice", "Benz & Asphaug 1999, Icarus 142:5, table II",
       {917, 9.47e9, 9.47e9, 10.0e6, 0.3, 0.1, 10, 5, 0.773e6, 3.04e6}},
  };
  return materials;
}

const TillotsonMaterial& tillotson_material(const std::string& name) {
  std::string names;
  for (const auto& m : tillotson_materials()) {
    if (m.name == name) return m;
    names += (names.empty() ? "" : ", ") + m.name;
  }
  throw std::invalid_argument("unknown Tillotson material '" + name + "' (known: " + names + ")");
}

namespace {

// The compressed (and cold expanded) branch p_c and its partial derivatives:
//   dp_c/de   = rho (a + b / (1 + z) - b z / (1 + z)^2)                 (dz/de = z / e = 1 / (e0 eta^2))
//   dp_c/drho = e (a + b / (1 + z) + 2 b z / (1 + z)^2) + (A + 2 B mu) / rho0   (dz/drho = -2 z / rho)
TillotsonState compressed(const TillotsonParameters& m, double rho, double e) {
  const double eta = rho / m.reference_density, mu = eta - 1;
  const double z = e / (m.e0 * eta * eta), q = 1 / (1 + z);
  TillotsonState s;
  s.pressure = (m.a + m.b * q) * rho * e + m.A * mu + m.B * mu * mu;
  s.dp_de = rho * (m.a + m.b * q - m.b * z * q * q);
  s.dp_drho = e * (m.a + m.b * q + 2 * m.b * z * q * q) + (m.A + 2 * m.B * mu) / m.reference_density;
  return s;
}

// The hot expanded branch p_e = a rho e + (G + H) E with G = b rho e / (1 + z), H = A mu exp(-beta nu),
// E = exp(-alpha nu^2), and dnu/drho = -(nu + 1) / rho:
//   dG/drho = b e (1 / (1 + z) + 2 z / (1 + z)^2),  dG/de = b rho (1 / (1 + z) - z / (1 + z)^2)
//   dH/drho = A exp(-beta nu) (1 / rho0 + beta mu (nu + 1) / rho),  dE/drho = 2 alpha nu (nu + 1) / rho E
TillotsonState hot_expanded(const TillotsonParameters& m, double rho, double e) {
  const double eta = rho / m.reference_density, mu = eta - 1, nu = 1 / eta - 1;
  const double z = e / (m.e0 * eta * eta), q = 1 / (1 + z);
  const double G = m.b * rho * e * q, decay = std::exp(-m.beta * nu), H = m.A * mu * decay;
  const double E = std::exp(-m.alpha * nu * nu);
  const double dG_drho = m.b * e * (q + 2 * z * q * q), dG_de = m.b * rho * (q - z * q * q);
  const double dH_drho = m.A * decay * (1 / m.reference_density + m.beta * mu * (nu + 1) / rho);
  const double dE_drho = 2 * m.alpha * nu * (nu + 1) / rho * E;
  TillotsonState s;
  s.pressure = m.a * rho * e + (G + H) * E;
  s.dp_de = m.a * rho + dG_de * E;
  s.dp_drho = m.a * e + (dG_drho + dH_drho) * E + (G + H) * dE_drho;
  return s;
}

}  // namespace

TillotsonState tillotson(const TillotsonParameters& m, double density, double energy) {
  if (density >= m.reference_density || energy <= m.e_iv) {
    auto s = compressed(m, density, energy);
    s.branch = density >= m.reference_density ? TillotsonState::Branch::compressed : TillotsonState::Branch::cold_expanded;
    return s;
  }
  if (energy >= m.e_cv) {
    auto s = hot_expanded(m, density, energy);
    s.branch = TillotsonState::Branch::hot_expanded;
    return s;
  }
  // Partly vaporised: p = (p_e (e - e_iv) + p_c (e_cv - e)) / (e_cv - e_iv).
  const auto c = compressed(m, density, energy), h = hot_expanded(m, density, energy);
  const double span = m.e_cv - m.e_iv, wh = (energy - m.e_iv) / span, wc = (m.e_cv - energy) / span;
  TillotsonState s;
  s.pressure = wh * h.pressure + wc * c.pressure;
  s.dp_drho = wh * h.dp_drho + wc * c.dp_drho;
  s.dp_de = wh * h.dp_de + wc * c.dp_de + (h.pressure - c.pressure) / span;
  s.branch = TillotsonState::Branch::interpolated;
  return s;
}

}  // namespace sph
