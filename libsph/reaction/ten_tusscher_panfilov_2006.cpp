// ten Tusscher-Panfilov 2006 human ventricular cell model: epicardial, endocardial and M cell variants.
// Source: ten Tusscher & Panfilov 2006, Am. J. Physiol. Heart Circ. Physiol. 291:H1088,
//         doi:10.1152/ajpheart.00109.2006, appendix, with the currents carried over from
//         ten Tusscher, Noble, Noble & Panfilov 2004, Am. J. Physiol. Heart 286:H1573,
//         doi:10.1152/ajpheart.00794.2003.
// Every formula and number below was checked against the CellML file
// ten_tusscher_model_2006_epi (Physiome model repository, workspace 604), as read in two independent
// translations of it (gotran and Myokit). Where the authors' own C code is known to differ (the f2
// time constant; R = 8314.472, F = 96485.3415 in other units), the CellML form is used.
// Symbols: the paper's (V, E_X, I_X, J_X, x_inf, tau_x); phi = V F / (R T).
// Deviations from the CellML file: none in the equations. Guards for removable singularities:
//   I_CaL at V = 15 mV (0/0 in the GHK factor) and J_up at Ca_i = 0 (written as Ca^2/(Ca^2 + K^2)).

#include "libsph/reaction/ten_tusscher_panfilov_2006.hpp"

#include <string>

#include <stdexcept>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <optional>

namespace sph {

namespace {

using SI = TenTusscherPanfilov2006::StateIndex;

// The elementary functions for both number types: std:: for double, Eigen's (found by argument-
// dependent lookup) for lanes; expm1 is exp_minus_one (lanes.hpp).
using std::abs;
using std::exp;
using std::log;
using std::sqrt;

double square(double x) { return x * x; }
Lanes square(const Lanes& x) { return x * x; }

/// x / (exp(x) - 1), continued by its limit 1 at x = 0.
template <class T>
T x_over_expm1(const T& x) {
  return pick(abs(x) < 1e-12, [&]() -> T { return 1 - x / 2; }, [&]() -> T { return x / exp_minus_one(x); });
}

}  // namespace

TenTusscherPanfilov2006::Parameters TenTusscherPanfilov2006::Parameters::of(CellType type) {
  Parameters p;
  p.cell_type = type;
  if (type == CellType::endocardial) p.g_to = 0.073;
  if (type == CellType::mid_myocardial) p.g_Ks = 0.098;
  return p;
}

const std::array<std::string_view, 14>& TenTusscherPanfilov2006::Parameters::channels() {
  static const std::array<std::string_view, 14> names{"g_Na",  "g_K1",  "g_to",   "g_Kr",   "g_Ks",  "g_CaL", "g_bNa",
                                                      "g_bCa", "g_pK",  "g_pCa",  "g_NaCa", "g_NaK", "g_rel", "g_up"};
  return names;
}

void TenTusscherPanfilov2006::Parameters::scale(std::string_view channel, double factor) {
  if (!(factor >= 0) || !std::isfinite(factor))
    throw std::invalid_argument("ten Tusscher-Panfilov: the factor of '" + std::string(channel) + "' must be finite and >= 0");
  double* target = channel == "g_Na"     ? &g_Na
                    : channel == "g_K1"  ? &g_K1
                    : channel == "g_to"  ? &g_to
                    : channel == "g_Kr"  ? &g_Kr
                    : channel == "g_Ks"  ? &g_Ks
                    : channel == "g_CaL" ? &g_CaL
                    : channel == "g_bNa" ? &g_bNa
                    : channel == "g_bCa" ? &g_bCa
                    : channel == "g_pK"  ? &g_pK
                    : channel == "g_pCa" ? &g_pCa
                    : channel == "g_NaCa" ? &K_NaCa
                    : channel == "g_NaK" ? &P_NaK
                    : channel == "g_rel" ? &V_rel
                    : channel == "g_up"  ? &Vmax_up
                                         : nullptr;
  if (!target) {
    std::string known;
    for (auto name : channels()) known += (known.empty() ? "" : ", ") + std::string(name);
    throw std::invalid_argument("ten Tusscher-Panfilov has no channel '" + std::string(channel) + "' (known: " + known + ")");
  }
  *target *= factor;
}

TenTusscherPanfilov2006::TenTusscherPanfilov2006(Parameters parameters) : p_(parameters) {
  RT_over_F_ = p_.gas_constant * p_.temperature / p_.faraday_constant;
  sqrt_K_o_factor_ = std::sqrt(p_.K_o / 5.4);
  // [pA/pF] x [pF] / ([C/mmol] [um^3]) = 1e-15 mmol/ms / 1e-15 L = mM/ms.
  current_to_flux_c_ = p_.membrane_capacitance / (p_.cytoplasm_volume * p_.faraday_constant);
}

// ---------------------------------------------------------------------------------------------
// Lookup tables of the functions of V alone (with_voltage_table).
// ---------------------------------------------------------------------------------------------
int TenTusscherPanfilov2006::tabulated_gate(std::size_t k) {
  switch (k) {
    case SI::m: return 0;
    case SI::h: return 2;
    case SI::j: return 4;
    case SI::Xr1: return 6;
    case SI::Xr2: return 8;
    case SI::Xs: return 10;
    case SI::r: return 12;
    case SI::s: return 14;
    case SI::d: return 16;
    case SI::f: return 18;
    case SI::f2: return 20;
    default: return -1;
  }
}

TenTusscherPanfilov2006 TenTusscherPanfilov2006::with_voltage_table(double step) const {
  TenTusscherPanfilov2006 model(p_);
  if (step == 0) return model;
  if (!(step > 0) || !(step <= 1))
    throw std::invalid_argument("ten Tusscher-Panfilov: the lookup table step must lie in (0, 1] mV");
  auto table = std::make_shared<VoltageTable>();
  const VoltageRange range = valid_voltage();
  table->v_min = range.lower;
  table->step = step;
  table->rows = std::size_t(std::ceil((range.upper - range.lower) / step)) + 1;
  table->inverse_step = 1 / step;
  table->last_node = double(table->rows - 1) - 1e-9;  // u below it: row r + 1 exists
  table->values.resize(table->rows * n_columns);
  for (std::size_t r = 0; r < table->rows; ++r) {
    const double V = range.lower + double(r) * step;
    double* row = &table->values[r * n_columns];
    for (std::size_t k = SI::Xr1; k <= SI::r; ++k)
      if (const int column = tabulated_gate(k); column >= 0) {
        const GateKinetics<double> g = gate_kinetics<double>(k, V, 0.0);
        row[column] = g.steady_state / g.time_constant;
        row[column + 1] = 1 / g.time_constant;
      }
    const double phi = V / RT_over_F_;
    const double e_reverse = std::exp((p_.gamma_NaCa - 1) * phi);
    const double x = 2 * (V - 15) / RT_over_F_;
    row[pK] = 1 / (1 + std::exp((25 - V) / 5.98));
    row[NaK] = 1 / (1 + 0.1245 * std::exp(-0.1 * phi) + 0.0353 * std::exp(-phi));
    row[NaCa_forward] = std::exp(p_.gamma_NaCa * phi) / (1 + p_.K_sat * e_reverse);
    row[NaCa_reverse] = e_reverse / (1 + p_.K_sat * e_reverse);
    row[CaL] = x_over_expm1(x);
    row[CaL_ss] = x_over_expm1(x) * std::exp(x);
  }
  model.table_ = std::move(table);
  return model;
}

// Linear interpolation between the rows around V; V outside the table takes the end row's value
// (valid_voltage(), outside which the reaction system stops the run).
double TenTusscherPanfilov2006::VoltageTable::at(int column, double V) const {
  const double u = std::clamp((V - v_min) * inverse_step, 0.0, last_node);
  const auto r = std::size_t(u);
  const double w = u - double(r);
  const double* row = &values[r * n_columns + std::size_t(column)];
  return row[0] + w * (row[n_columns] - row[0]);
}

// The rows and weights of all lanes at once; the values gathered lane by lane.
Lanes TenTusscherPanfilov2006::VoltageTable::at(int column, const Lanes& V) const {
  const Lanes u = ((V - v_min) * inverse_step).max(0.0).min(last_node);
  const Lanes r = u.floor();
  const Lanes w = u - r;
  Lanes low, high;
  for (int l = 0; l < lane_count; ++l) {
    const double* row = &values[std::size_t(r[l]) * n_columns + std::size_t(column)];
    low[l] = row[0];
    high[l] = row[n_columns];
  }
  return low + w * (high - low);
}

TenTusscherPanfilov2006::State TenTusscherPanfilov2006::initial_state() const {
  State y{};
  y[SI::V] = -85.23;
  y[SI::Xr1] = 0.00621;
  y[SI::Xr2] = 0.4712;
  y[SI::Xs] = 0.0095;
  y[SI::m] = 0.00172;
  y[SI::h] = 0.7444;
  y[SI::j] = 0.7045;
  y[SI::d] = 3.373e-5;
  y[SI::f] = 0.7888;
  y[SI::f2] = 0.9755;
  y[SI::fCass] = 0.9953;
  y[SI::s] = 0.999998;
  y[SI::r] = 2.42e-8;
  y[SI::Ca_i] = 1.26e-4;
  y[SI::R_prime] = 0.9073;
  y[SI::Ca_SR] = 3.64;
  y[SI::Ca_ss] = 3.6e-4;
  y[SI::Na_i] = 8.604;
  y[SI::K_i] = 136.89;
  return y;
}

// ---------------------------------------------------------------------------------------------
// Gates: dx/dt = (x_inf - x) / tau_x, tau_x [ms] (TP06 appendix).
// ---------------------------------------------------------------------------------------------
template <class T>
TenTusscherPanfilov2006::GateKinetics<T> TenTusscherPanfilov2006::gate_kinetics(std::size_t k, const T& V,
                                                                                const T& Ca_ss) const {
  switch (k) {
    case SI::m: {  // I_Na activation
      const T inf = 1 / square(1 + exp((-56.86 - V) / 9.03));
      const T alpha = 1 / (1 + exp((-60 - V) / 5));
      const T beta = 0.1 / (1 + exp((V + 35) / 5)) + 0.1 / (1 + exp((V - 50) / 200));
      return {inf, alpha * beta};
    }
    case SI::h: {  // I_Na fast inactivation; the rates switch at V = -40 mV
      const T inf = 1 / square(1 + exp((V + 71.55) / 7.43));
      const T rate = pick(  // alpha + beta [1/ms]
          V < -40,
          [&]() -> T {
            const T alpha = 0.057 * exp(-(V + 80) / 6.8);
            const T beta = 2.7 * exp(0.079 * V) + 3.1e5 * exp(0.3485 * V);
            return alpha + beta;
          },
          [&]() -> T { return 0.77 / (0.13 * (1 + exp(-(V + 10.66) / 11.1))); });  // alpha = 0
      return {inf, 1 / rate};
    }
    case SI::j: {  // I_Na slow inactivation
      const T inf = 1 / square(1 + exp((V + 71.55) / 7.43));
      const T rate = pick(  // alpha + beta [1/ms]
          V < -40,
          [&]() -> T {
            const T alpha = (-25428 * exp(0.2444 * V) - 6.948e-6 * exp(-0.04391 * V)) * (V + 37.78) /
                            (1 + exp(0.311 * (V + 79.23)));
            const T beta = 0.02424 * exp(-0.01052 * V) / (1 + exp(-0.1378 * (V + 40.14)));
            return alpha + beta;
          },
          [&]() -> T { return 0.6 * exp(0.057 * V) / (1 + exp(-0.1 * (V + 32))); });  // alpha = 0
      return {inf, 1 / rate};
    }
    case SI::Xr1: {  // I_Kr activation
      const T inf = 1 / (1 + exp((-26 - V) / 7));
      const T alpha = 450 / (1 + exp((-45 - V) / 10));
      const T beta = 6 / (1 + exp((V + 30) / 11.5));
      return {inf, alpha * beta};
    }
    case SI::Xr2: {  // I_Kr inactivation
      const T inf = 1 / (1 + exp((V + 88) / 24));
      const T alpha = 3 / (1 + exp((-60 - V) / 20));
      const T beta = 1.12 / (1 + exp((V - 60) / 20));
      return {inf, alpha * beta};
    }
    case SI::Xs: {  // I_Ks activation (TP06 time constant, with the 80 ms offset)
      const T inf = 1 / (1 + exp((-5 - V) / 14));
      const T alpha = 1400 / sqrt(1 + exp((5 - V) / 6));
      const T beta = 1 / (1 + exp((V - 35) / 15));
      return {inf, alpha * beta + 80};
    }
    case SI::r:  // I_to activation
      return {1 / (1 + exp((20 - V) / 6)), 9.5 * exp(-square(V + 40) / 1800) + 0.8};
    case SI::s:  // I_to inactivation: endocardial form, or the epicardial one (also the M cell's)
      if (p_.cell_type == CellType::endocardial)
        return {1 / (1 + exp((V + 28) / 5)), 1000 * exp(-square(V + 67) / 1000) + 8};
      return {1 / (1 + exp((V + 20) / 5)), 85 * exp(-square(V + 45) / 320) + 5 / (1 + exp((V - 20) / 5)) + 3};
    case SI::d: {  // I_CaL activation
      const T inf = 1 / (1 + exp((-8 - V) / 7.5));
      const T alpha = 1.4 / (1 + exp((-35 - V) / 13)) + 0.25;
      const T beta = 1.4 / (1 + exp((V + 5) / 5));
      const T gamma = 1 / (1 + exp((50 - V) / 20));
      return {inf, alpha * beta + gamma};
    }
    case SI::f: {  // I_CaL slow voltage inactivation
      const T inf = 1 / (1 + exp((V + 20) / 7));
      const T tau = 1102.5 * exp(-square(V + 27) / 225) + 200 / (1 + exp((13 - V) / 10)) +
                    180 / (1 + exp((V + 30) / 10)) + 20;
      return {inf, tau};
    }
    case SI::f2: {  // I_CaL fast voltage inactivation. The CellML file divides (V + 27)^2 by 240; the
                    // authors' C code is reported to use 170 (not checked here).
      const T inf = 0.67 / (1 + exp((V + 35) / 7)) + 0.33;
      const T tau = 562 * exp(-square(V + 27) / 240) + 31 / (1 + exp((25 - V) / 10)) + 80 / (1 + exp((V + 30) / 10));
      return {inf, tau};
    }
    case SI::fCass: {  // I_CaL inactivation by subspace calcium
      const T c = 1 + square(Ca_ss / 0.05);
      return {0.6 / c + 0.4, 80 / c + 2};
    }
    default:  // not a gate; production_loss() and rates() never ask
      return {constant<T>(0), constant<T>(1)};
  }
}

// ---------------------------------------------------------------------------------------------
// Currents [pA/pF] (TP06 appendix; TNNP04 for the unchanged ones).
// ---------------------------------------------------------------------------------------------
template <class T>
T TenTusscherPanfilov2006::reversal_potential_Na(const T& Na_i) const {
  return RT_over_F_ * log(p_.Na_o / Na_i);
}
template <class T>
T TenTusscherPanfilov2006::reversal_potential_K(const T& K_i) const {
  return RT_over_F_ * log(p_.K_o / K_i);
}
template <class T>
T TenTusscherPanfilov2006::reversal_potential_Ks(const T& K_i, const T& Na_i) const {
  return RT_over_F_ * log((p_.K_o + p_.P_kna * p_.Na_o) / (K_i + p_.P_kna * Na_i));
}
template <class T>
T TenTusscherPanfilov2006::reversal_potential_Ca(const T& Ca_i) const {
  return 0.5 * RT_over_F_ * log(p_.Ca_o / Ca_i);
}

template <class T>
TenTusscherPanfilov2006::PotassiumCurrents<T> TenTusscherPanfilov2006::potassium_currents(const StateOf<T>& y) const {
  const T& V = y[SI::V];
  const T E_K = reversal_potential_K(y[SI::K_i]);
  const T E_Ks = reversal_potential_Ks(y[SI::K_i], y[SI::Na_i]);
  // I_K1 = g_K1 sqrt(K_o/5.4) x_K1_inf (V - E_K), x_K1_inf = alpha / (alpha + beta), instantaneous.
  const T alpha_K1 = 0.1 / (1 + exp(0.06 * (V - E_K - 200)));
  const T beta_K1 = (3 * exp(0.0002 * (V - E_K + 100)) + exp(0.1 * (V - E_K - 10))) / (1 + exp(-0.5 * (V - E_K)));
  const T g_K1 = p_.g_K1 * sqrt_K_o_factor_ * alpha_K1 / (alpha_K1 + beta_K1);
  const T g_to = p_.g_to * y[SI::r] * y[SI::s];                         // I_to = g_to r s (V - E_K)
  const T g_Kr = p_.g_Kr * sqrt_K_o_factor_ * y[SI::Xr1] * y[SI::Xr2];  // I_Kr
  const T g_Ks = p_.g_Ks * square(y[SI::Xs]);                           // I_Ks = g_Ks Xs^2 (V - E_Ks)
  const T g_pK = table_ ? T(p_.g_pK * table_->at(pK, V)) : T(p_.g_pK / (1 + exp((25 - V) / 5.98)));  // I_pK
  PotassiumCurrents<T> I;
  I.I_K1 = g_K1 * (V - E_K);
  I.I_to = g_to * (V - E_K);
  I.I_Kr = g_Kr * (V - E_K);
  I.I_Ks = g_Ks * (V - E_Ks);
  I.I_pK = g_pK * (V - E_K);
  I.conductance = g_K1 + g_to + g_Kr + g_Ks + g_pK;
  return I;
}

template <class T>
TenTusscherPanfilov2006::SodiumCurrents<T> TenTusscherPanfilov2006::sodium_currents(const StateOf<T>& y) const {
  const T& V = y[SI::V];
  const T E_Na = reversal_potential_Na(y[SI::Na_i]);
  const T g_Na = p_.g_Na * y[SI::m] * y[SI::m] * y[SI::m] * y[SI::h] * y[SI::j];  // I_Na = g m^3 h j (V - E_Na)
  SodiumCurrents<T> I;
  I.I_Na = g_Na * (V - E_Na);
  I.I_bNa = p_.g_bNa * (V - E_Na);
  I.conductance = g_Na + p_.g_bNa;
  return I;
}

template <class T>
T TenTusscherPanfilov2006::background_calcium(const T& V, const T& Ca_i) const {
  return p_.g_bCa * (V - reversal_potential_Ca(Ca_i));
}

// I_CaL = g_CaL d f f2 fCass 4 (V - 15) F^2/(RT) (0.25 Ca_ss e^x - Ca_o) / (e^x - 1), x = 2 (V - 15) F/(RT);
// rewritten as g_CaL d f f2 fCass 2 F (x / (e^x - 1)) (0.25 Ca_ss e^x - Ca_o), finite at V = 15 mV.
// The term in Ca_ss has coefficient g_CaL d f f2 fCass 2 F (x / (e^x - 1)) 0.25 e^x >= 0.
template <class T>
TenTusscherPanfilov2006::Split<T> TenTusscherPanfilov2006::l_type_calcium(const StateOf<T>& y) const {
  const T gates = p_.g_CaL * y[SI::d] * y[SI::f] * y[SI::f2] * y[SI::fCass] * 2 * p_.faraday_constant;
  if (table_) {
    const T scale = gates * table_->at(CaL, y[SI::V]);
    const T ca_ss_coefficient = gates * table_->at(CaL_ss, y[SI::V]) * 0.25;
    return {ca_ss_coefficient * y[SI::Ca_ss] - scale * p_.Ca_o, ca_ss_coefficient};
  }
  const T x = 2 * (y[SI::V] - 15) / RT_over_F_;
  const T scale = gates * x_over_expm1(x);
  const T ca_ss_coefficient = scale * 0.25 * exp(x);
  return {ca_ss_coefficient * y[SI::Ca_ss] - scale * p_.Ca_o, ca_ss_coefficient};
}

// I_NaCa = K_NaCa (e^{gamma phi} Na_i^3 Ca_o - e^{(gamma-1) phi} Na_o^3 Ca_i alpha)
//          / ((Km_Nai^3 + Na_o^3)(Km_Ca + Ca_o)(1 + K_sat e^{(gamma-1) phi})).
// The reverse-mode term is the part proportional to Ca_i.
template <class T>
TenTusscherPanfilov2006::Split<T> TenTusscherPanfilov2006::sodium_calcium_exchange(const T& V, const T& Na_i,
                                                                                   const T& Ca_i) const {
  if (table_) {
    const double scale = p_.K_NaCa / ((p_.Km_Nai * p_.Km_Nai * p_.Km_Nai + p_.Na_o * p_.Na_o * p_.Na_o) * (p_.Km_Ca + p_.Ca_o));
    const T ca_i_coefficient = scale * table_->at(NaCa_reverse, V) * (p_.Na_o * p_.Na_o * p_.Na_o * p_.alpha_NaCa);
    return {scale * table_->at(NaCa_forward, V) * Na_i * Na_i * Na_i * p_.Ca_o - ca_i_coefficient * Ca_i, ca_i_coefficient};
  }
  const T phi = V / RT_over_F_;
  const T e_forward = exp(p_.gamma_NaCa * phi);
  const T e_reverse = exp((p_.gamma_NaCa - 1) * phi);
  const T scale = p_.K_NaCa / ((p_.Km_Nai * p_.Km_Nai * p_.Km_Nai + p_.Na_o * p_.Na_o * p_.Na_o) *
                               (p_.Km_Ca + p_.Ca_o) * (1 + p_.K_sat * e_reverse));
  const T ca_i_coefficient = scale * e_reverse * p_.Na_o * p_.Na_o * p_.Na_o * p_.alpha_NaCa;
  return {scale * e_forward * Na_i * Na_i * Na_i * p_.Ca_o - ca_i_coefficient * Ca_i, ca_i_coefficient};
}

// I_pCa = g_pCa Ca_i / (Ca_i + K_pCa).
template <class T>
TenTusscherPanfilov2006::Split<T> TenTusscherPanfilov2006::calcium_pump(const T& Ca_i) const {
  const T coefficient = p_.g_pCa / (Ca_i + p_.K_pCa);
  return {coefficient * Ca_i, coefficient};
}

// I_NaK = P_NaK K_o/(K_o + K_mK) Na_i/(Na_i + K_mNa) / (1 + 0.1245 e^{-0.1 phi} + 0.0353 e^{-phi}).
template <class T>
T TenTusscherPanfilov2006::sodium_potassium_pump(const T& V, const T& Na_i) const {
  if (table_) return p_.P_NaK * p_.K_o / (p_.K_o + p_.K_mK) * Na_i / (Na_i + p_.K_mNa) * table_->at(NaK, V);
  const T phi = V / RT_over_F_;
  return p_.P_NaK * p_.K_o / (p_.K_o + p_.K_mK) * Na_i / (Na_i + p_.K_mNa) /
         (1 + 0.1245 * exp(-0.1 * phi) + 0.0353 * exp(-phi));
}

template <class T>
TenTusscherPanfilov2006::MembraneCurrents<T> TenTusscherPanfilov2006::membrane_currents(const StateOf<T>& y) const {
  MembraneCurrents<T> I;
  I.K = potassium_currents(y);
  I.Na = sodium_currents(y);
  I.I_bCa = background_calcium(y[SI::V], y[SI::Ca_i]);
  I.I_NaK = sodium_potassium_pump(y[SI::V], y[SI::Na_i]);
  I.I_CaL = l_type_calcium(y);
  I.I_NaCa = sodium_calcium_exchange(y[SI::V], y[SI::Na_i], y[SI::Ca_i]);
  I.I_pCa = calcium_pump(y[SI::Ca_i]);
  I.linear_conductance = I.K.conductance + I.Na.conductance + p_.g_bCa;
  return I;
}

// ---------------------------------------------------------------------------------------------
// Calcium dynamics: SR fluxes [mM/ms], RyR (TP06 appendix).
// ---------------------------------------------------------------------------------------------
// J_up = Vmax_up / (1 + K_up^2 / Ca_i^2) = Vmax_up Ca_i^2 / (Ca_i^2 + K_up^2), finite at Ca_i = 0.
template <class T>
TenTusscherPanfilov2006::Split<T> TenTusscherPanfilov2006::uptake(const T& Ca_i) const {
  const T coefficient = p_.Vmax_up * Ca_i / (Ca_i * Ca_i + p_.K_up * p_.K_up);
  return {coefficient * Ca_i, coefficient};
}

// k_casr = max_sr - (max_sr - min_sr) / (1 + (EC / Ca_SR)^2).
template <class T>
T TenTusscherPanfilov2006::casr_dependence(const T& Ca_SR) const {
  return p_.max_sr - (p_.max_sr - p_.min_sr) / (1 + square(p_.EC / Ca_SR));
}

// O = k1 Ca_ss^2 R' / (k3 + k1 Ca_ss^2), k1 = k1' / k_casr.
template <class T>
T TenTusscherPanfilov2006::ryanodine_open_probability(const StateOf<T>& y) const {
  const T k1 = p_.k1_prime / casr_dependence(y[SI::Ca_SR]);
  const T k1_ca2 = k1 * square(y[SI::Ca_ss]);
  return k1_ca2 * y[SI::R_prime] / (p_.k3 + k1_ca2);
}

// ---------------------------------------------------------------------------------------------
// Rates of V and the concentrations.
// ---------------------------------------------------------------------------------------------
// dV/dt = -(sum of the currents) - I_stim, I_stim = -stimulus.
template <class T>
TenTusscherPanfilov2006::RateAndLoss<T> TenTusscherPanfilov2006::potential_rate(const MembraneCurrents<T>& I,
                                                                                const T& stimulus) const {
  const T I_ion = I.Na.I_Na + I.K.I_K1 + I.K.I_to + I.K.I_Kr + I.K.I_Ks + I.I_CaL.value + I.I_NaK + I.I_NaCa.value +
                  I.I_pCa.value + I.K.I_pK + I.Na.I_bNa + I.I_bCa;
  return {stimulus - I_ion, I.linear_conductance};
}

// dCa_i/dt = B_i [-(I_bCa + I_pCa - 2 I_NaCa) C_m/(2 V_c F) + (J_leak - J_up) V_SR/V_c + J_xfer],
// J_leak = V_leak (Ca_SR - Ca_i), J_xfer = V_xfer (Ca_ss - Ca_i),
// B_i = 1 / (1 + Buf_c K_buf_c / (Ca_i + K_buf_c)^2) (rapid buffering).
template <class T>
TenTusscherPanfilov2006::RateAndLoss<T> TenTusscherPanfilov2006::calcium_intracellular_rate(
    const StateOf<T>& y, const T& I_bCa, const Split<T>& I_NaCa, const Split<T>& I_pCa, const Split<T>& J_up) const {
  const T& Ca_i = y[SI::Ca_i];
  const T buffering = 1 / (1 + p_.Buf_c * p_.K_buf_c / square(Ca_i + p_.K_buf_c));
  const double current_factor = current_to_flux_c_ / 2;  // C_m / (2 V_c F)
  const double volume_ratio = p_.sarcoplasmic_reticulum_volume / p_.cytoplasm_volume;
  const T J_leak = p_.V_leak * (y[SI::Ca_SR] - Ca_i);
  const T J_xfer = p_.V_xfer * (y[SI::Ca_ss] - Ca_i);
  const T total_rate =
      -(I_bCa + I_pCa.value - 2 * I_NaCa.value) * current_factor + (J_leak - J_up.value) * volume_ratio + J_xfer;
  const T total_loss = (I_pCa.coefficient + 2 * I_NaCa.coefficient) * current_factor +
                       (p_.V_leak + J_up.coefficient) * volume_ratio + p_.V_xfer;
  return {buffering * total_rate, buffering * total_loss};
}

// dCa_ss/dt = B_ss [-I_CaL C_m/(2 V_ss F) + J_rel V_SR/V_ss - J_xfer V_c/V_ss],
// J_rel = V_rel O (Ca_SR - Ca_ss).
template <class T>
TenTusscherPanfilov2006::RateAndLoss<T> TenTusscherPanfilov2006::calcium_subspace_rate(const StateOf<T>& y,
                                                                                       const Split<T>& I_CaL,
                                                                                       const T& open_probability) const {
  const T& Ca_ss = y[SI::Ca_ss];
  const T buffering = 1 / (1 + p_.Buf_ss * p_.K_buf_ss / square(Ca_ss + p_.K_buf_ss));
  const double current_factor = p_.membrane_capacitance / (2 * p_.subspace_volume * p_.faraday_constant);
  const double sr_ratio = p_.sarcoplasmic_reticulum_volume / p_.subspace_volume;
  const double cytoplasm_ratio = p_.cytoplasm_volume / p_.subspace_volume;
  const T J_rel = p_.V_rel * open_probability * (y[SI::Ca_SR] - Ca_ss);
  const T J_xfer = p_.V_xfer * (Ca_ss - y[SI::Ca_i]);
  const T total_rate = -I_CaL.value * current_factor + J_rel * sr_ratio - J_xfer * cytoplasm_ratio;
  const T total_loss =
      I_CaL.coefficient * current_factor + p_.V_rel * open_probability * sr_ratio + p_.V_xfer * cytoplasm_ratio;
  return {buffering * total_rate, buffering * total_loss};
}

// dCa_SR/dt = B_SR (J_up - J_rel - J_leak).
template <class T>
TenTusscherPanfilov2006::RateAndLoss<T> TenTusscherPanfilov2006::calcium_sr_rate(const StateOf<T>& y, const T& J_up,
                                                                                 const T& open_probability) const {
  const T& Ca_SR = y[SI::Ca_SR];
  const T buffering = 1 / (1 + p_.Buf_sr * p_.K_buf_sr / square(Ca_SR + p_.K_buf_sr));
  const T J_rel = p_.V_rel * open_probability * (Ca_SR - y[SI::Ca_ss]);
  const T J_leak = p_.V_leak * (Ca_SR - y[SI::Ca_i]);
  return {buffering * (J_up - J_rel - J_leak), buffering * (p_.V_rel * open_probability + p_.V_leak)};
}

// dR'/dt = -k2 Ca_ss R' + k4 (1 - R'), k2 = k2' k_casr.
template <class T>
TenTusscherPanfilov2006::RateAndLoss<T> TenTusscherPanfilov2006::ryanodine_rate(const StateOf<T>& y) const {
  const T k2 = p_.k2_prime * casr_dependence(y[SI::Ca_SR]);
  const T& R_prime = y[SI::R_prime];
  return {-k2 * y[SI::Ca_ss] * R_prime + p_.k4 * (1 - R_prime), k2 * y[SI::Ca_ss] + p_.k4};
}

// dNa_i/dt = -(I_Na + I_bNa + 3 I_NaK + 3 I_NaCa) C_m/(V_c F).
template <class T>
T TenTusscherPanfilov2006::sodium_rate(const SodiumCurrents<T>& I_Na, const T& I_NaK, const T& I_NaCa) const {
  return -(I_Na.I_Na + I_Na.I_bNa + 3 * I_NaK + 3 * I_NaCa) * current_to_flux_c_;
}

// dK_i/dt = -(I_K1 + I_to + I_Kr + I_Ks + I_pK + I_stim - 2 I_NaK) C_m/(V_c F). As in the CellML
// file, the stimulus current is carried by K+, so that the total charge of the cell stays consistent
// with V (charge conservation); I_stim = -stimulus.
template <class T>
T TenTusscherPanfilov2006::potassium_rate(const PotassiumCurrents<T>& I_K, const T& I_NaK, const T& stimulus) const {
  const T I_stim = -stimulus;
  return -(I_K.I_K1 + I_K.I_to + I_K.I_Kr + I_K.I_Ks + I_K.I_pK + I_stim - 2 * I_NaK) * current_to_flux_c_;
}

// ---------------------------------------------------------------------------------------------
// The interface.
// ---------------------------------------------------------------------------------------------
// Not inlined: rbr_qss_step() and the generic sweeps then round every production and loss the same
// way (inlined, the compiler may fuse a multiply of the rate with the loss term into one FMA).
template <class T>
[[gnu::noinline]] BasicProductionLoss<T> TenTusscherPanfilov2006::production_loss_of(std::size_t k,
                                                                                     const StateOf<T>& y,
                                                                                     const T& stimulus) const {
  const auto from_rate = [&](const RateAndLoss<T>& r) {
    return with_nonnegative_loss(BasicProductionLoss<T>{r.rate + r.loss * y[k], r.loss}, y[k]);
  };
  const auto without_loss = [](const T& rate) { return BasicProductionLoss<T>{rate, constant<T>(0)}; };
  switch (k) {
    case SI::V:
      return from_rate(potential_rate(membrane_currents(y), stimulus));
    case SI::Ca_i: {
      const T& V = y[SI::V];
      const T& Ca_i = y[SI::Ca_i];
      return from_rate(calcium_intracellular_rate(y, background_calcium(V, Ca_i),
                                                  sodium_calcium_exchange(V, y[SI::Na_i], Ca_i), calcium_pump(Ca_i),
                                                  uptake(Ca_i)));
    }
    case SI::Ca_ss:
      return from_rate(calcium_subspace_rate(y, l_type_calcium(y), ryanodine_open_probability(y)));
    case SI::Ca_SR:
      return from_rate(calcium_sr_rate(y, uptake(y[SI::Ca_i]).value, ryanodine_open_probability(y)));
    case SI::R_prime:
      return from_rate(ryanodine_rate(y));
    case SI::Na_i: {
      const T& V = y[SI::V];
      const T& Na_i = y[SI::Na_i];
      return without_loss(sodium_rate(sodium_currents(y), sodium_potassium_pump(V, Na_i),
                                      sodium_calcium_exchange(V, Na_i, y[SI::Ca_i]).value));
    }
    case SI::K_i:
      return without_loss(
          potassium_rate(potassium_currents(y), sodium_potassium_pump(y[SI::V], y[SI::Na_i]), stimulus));
    default: {  // a gate: Rush-Larsen form
      if (const int column = table_ ? tabulated_gate(k) : -1; column >= 0)
        return {table_->at(column, y[SI::V]), table_->at(column + 1, y[SI::V])};
      const GateKinetics<T> g = gate_kinetics(k, y[SI::V], y[SI::Ca_ss]);
      return {g.steady_state / g.time_constant, 1 / g.time_constant};
    }
  }
}

ProductionLoss TenTusscherPanfilov2006::production_loss(std::size_t k, const State& y, double stimulus) const {
  return production_loss_of<double>(k, y, stimulus);
}

TenTusscherPanfilov2006::State TenTusscherPanfilov2006::rates(const State& y, double stimulus) const {
  const MembraneCurrents<double> I = membrane_currents(y);
  const Split<double> J_up = uptake(y[SI::Ca_i]);
  const double open_probability = ryanodine_open_probability(y);
  State dy{};
  dy[SI::V] = potential_rate(I, stimulus).rate;
  dy[SI::Ca_i] = calcium_intracellular_rate(y, I.I_bCa, I.I_NaCa, I.I_pCa, J_up).rate;
  dy[SI::Ca_ss] = calcium_subspace_rate(y, I.I_CaL, open_probability).rate;
  dy[SI::Ca_SR] = calcium_sr_rate(y, J_up.value, open_probability).rate;
  dy[SI::R_prime] = ryanodine_rate(y).rate;
  dy[SI::Na_i] = sodium_rate(I.Na, I.I_NaK, I.I_NaCa.value);
  dy[SI::K_i] = potassium_rate(I.K, I.I_NaK, stimulus);
  for (std::size_t k : {SI::Xr1, SI::Xr2, SI::Xs, SI::m, SI::h, SI::j, SI::d, SI::f, SI::f2, SI::fCass, SI::s, SI::r}) {
    const GateKinetics<double> g = gate_kinetics(k, y[SI::V], y[SI::Ca_ss]);
    dy[k] = (g.steady_state - y[k]) / g.time_constant;
  }
  return dy;
}

template <class T>
void TenTusscherPanfilov2006::rbr_qss_step_of(StateOf<T>& y, const T& stimulus, double dt) const {
  // The order of rbr_qss_sweeps: forward V, the gates Xr1 ... r, Ca_i ... K_i; backward K_i ...
  // Ca_i, the gates r ... Xr1, V. Between the forward and backward update of a gate only the
  // gates after it and the non-gate states change; of these, a gate's kinetics read Ca_ss only for
  // fCass, which is evaluated anew.
  static_assert(SI::Xr1 == 1 && SI::r == 12 && SI::Ca_i == 13 && SI::K_i == n_states - 1);
  const double half = 0.5 * dt;
  const auto update = [&](std::size_t k) {
    y[k] = BasicQssStep<T>(production_loss_of<T>(k, y, stimulus), half).apply(y[k]);
  };
  update(SI::V);
  std::array<std::optional<BasicQssStep<T>>, SI::r + 1> gate;
  for (std::size_t k = SI::Xr1; k <= SI::r; ++k) {
    gate[k].emplace(production_loss_of<T>(k, y, stimulus), half);
    y[k] = gate[k]->apply(y[k]);
  }
  for (std::size_t k = SI::Ca_i; k < n_states; ++k) update(k);
  for (std::size_t k = n_states; k-- > SI::Ca_i;) update(k);
  for (std::size_t k = SI::r; k >= SI::Xr1; --k) {
    if (k == SI::fCass) update(k);
    else y[k] = gate[k]->apply(y[k]);
  }
  update(SI::V);
}

void TenTusscherPanfilov2006::rbr_qss_step(State& y, double stimulus, double dt) const {
  rbr_qss_step_of<double>(y, stimulus, dt);
}

void TenTusscherPanfilov2006::rbr_qss_step(LaneState& y, const Lanes& stimulus, double dt) const {
  rbr_qss_step_of<Lanes>(y, stimulus, dt);
}

}  // namespace sph
