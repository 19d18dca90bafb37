#pragma once
// ten Tusscher-Panfilov 2006 human ventricular cell model: epicardial (default), endocardial and
// mid-myocardial (M) variants.
// Source: ten Tusscher & Panfilov 2006, Am. J. Physiol. Heart Circ. Physiol. 291:H1088,
//         doi:10.1152/ajpheart.00109.2006 (appendix; the currents it keeps unchanged are those of
//         ten Tusscher, Noble, Noble & Panfilov 2004, Am. J. Physiol. Heart 286:H1573), in the form
//         of the CellML file ten_tusscher_model_2006_epi (Physiome model repository, workspace 604).
// Units: V [mV], t [ms], currents normalised by capacitance [pA/pF], concentrations [mM].
//
// 19 states, V first; the order is that of the resting state of Niederer et al. 2011 (Phil. Trans.
// R. Soc. A 369:4331), see `StateIndex`. The equations, grouped as in the .cpp:
//   membrane:      dV/dt = -(I_Na + I_K1 + I_to + I_Kr + I_Ks + I_CaL + I_NaK + I_NaCa + I_pCa + I_pK
//                            + I_bNa + I_bCa + I_stim),   I_stim = -stimulus
//   gates:         dx/dt = (x_inf(V) - x) / tau_x(V)   (fCass: x_inf(Ca_ss), tau_x(Ca_ss))
//   calcium:       Ca_i, Ca_ss, Ca_SR free concentrations with rapid buffering, RyR state R'
//   concentrations: Na_i, K_i from the currents that carry them.
// The epicardial cell has G_to = 0.294 nS/pF, G_Ks = 0.392 nS/pF and the epicardial s_inf, tau_s;
// the endocardial cell G_to = 0.073 and the endocardial s gate (s_inf = 1/(1 + exp((V + 28)/5)),
// tau_s = 1000 exp(-(V + 67)^2/1000) + 8); the M cell G_Ks = 0.098 with the epicardial s gate
// (ten Tusscher & Panfilov 2006 appendix; ten Tusscher et al. 2004 for the s gates).
//
// Production/loss form (reaction_model.hpp), dy/dt = q - p y with p >= 0:
//   gates, R':      q = y_inf / tau, p = 1 / tau (Rush-Larsen); R': q = k4, p = k2 Ca_ss + k4
//   V:              p = sum of the chord conductances of the currents that are ohmic in V
//                   (g x gates for I_Na, I_K1, I_to, I_Kr, I_Ks, I_pK, I_bNa, I_bCa), q = dV/dt + p V
//   Ca_i, Ca_ss, Ca_SR: p = (buffering factor) x (sum of the coefficients of the fluxes that are
//                   proportional to the variable), q = dy/dt + p y
//   Na_i, K_i:      p = 0 (they change by well under 1% per beat)
// q - p y equals rates()[k] up to rounding.

#include <array>
#include <cstddef>
#include <memory>
#include <vector>
#include <string_view>

#include "libsph/reaction/reaction_model.hpp"

namespace sph {

class TenTusscherPanfilov2006 {
 public:
  /// The published constants (ten Tusscher & Panfilov 2006 appendix; CellML
  /// ten_tusscher_model_2006_epi). The numbers inside the gate formulas (half-activation voltages,
  /// slopes, time-constant fits) are written next to each formula in the .cpp.
  enum class CellType { epicardial, endocardial, mid_myocardial };
  struct Parameters {
    CellType cell_type = CellType::epicardial;    ///< chooses the I_to inactivation gate
    // Physical constants and cell geometry.
    double gas_constant = 8.314;                  ///< R [J mol^-1 K^-1]
    double temperature = 310;                     ///< T [K]
    double faraday_constant = 96.485;             ///< F [C mmol^-1]
    double membrane_capacitance = 185;            ///< C_m [pF]
    double cytoplasm_volume = 16404;              ///< V_c [um^3]
    double sarcoplasmic_reticulum_volume = 1094;  ///< V_SR [um^3]
    double subspace_volume = 54.68;               ///< V_ss [um^3]

    // Extracellular concentrations (fixed).
    double K_o = 5.4;   ///< [mM]
    double Na_o = 140;  ///< [mM]
    double Ca_o = 2;    ///< [mM]

    // Maximal conductances and currents (epicardial values where the cell types differ).
    double g_Na = 14.838;      ///< fast Na+ current [nS/pF]
    double g_K1 = 5.405;       ///< inward rectifier at K_o = 5.4 mM, scaled by sqrt(K_o / 5.4) [nS/pF]
    double g_to = 0.294;       ///< transient outward, epicardium (endocardium 0.073) [nS/pF]
    double g_Kr = 0.153;       ///< rapid delayed rectifier at K_o = 5.4 mM, scaled by sqrt(K_o / 5.4) [nS/pF]
    double g_Ks = 0.392;       ///< slow delayed rectifier, epicardium and endocardium (M cell 0.098) [nS/pF]
    double P_kna = 0.03;       ///< relative Na+ permeability of I_Ks [1]
    double g_CaL = 0.0398;     ///< L-type Ca2+ current [L F^-1 s^-1], as in the CellML file
    double g_bNa = 0.00029;    ///< background Na+ current [nS/pF]
    double g_bCa = 0.000592;   ///< background Ca2+ current [nS/pF]
    double g_pK = 0.0146;      ///< plateau K+ current [nS/pF]
    double g_pCa = 0.1238;     ///< sarcolemmal Ca2+ pump, maximal current [pA/pF]
    double K_pCa = 0.0005;     ///< half-saturation of I_pCa [mM]
    double P_NaK = 2.724;      ///< Na+/K+ pump, maximal current [pA/pF]
    double K_mK = 1;           ///< K_o half-saturation of I_NaK [mM]
    double K_mNa = 40;         ///< Na_i half-saturation of I_NaK [mM]
    double K_NaCa = 1000;      ///< Na+/Ca2+ exchanger, maximal current [pA/pF]
    double K_sat = 0.1;        ///< saturation of I_NaCa at negative potentials [1]
    double alpha_NaCa = 2.5;   ///< factor enhancing the outward mode of I_NaCa [1]
    double gamma_NaCa = 0.35;  ///< voltage-dependence parameter of I_NaCa [1]
    double Km_Ca = 1.38;       ///< Ca_o half-saturation of I_NaCa [mM]
    double Km_Nai = 87.5;      ///< Na_i half-saturation of I_NaCa [mM]

    // Calcium dynamics.
    double k1_prime = 0.15;     ///< R -> O rate of the RyR [mM^-2 ms^-1]
    double k2_prime = 0.045;    ///< R -> I rate of the RyR [mM^-1 ms^-1]
    double k3 = 0.06;           ///< O -> R rate [ms^-1]
    double k4 = 0.005;          ///< I -> R rate (recovery from inactivation) [ms^-1]
    double EC = 1.5;            ///< Ca_SR half-saturation of k_casr [mM]
    double max_sr = 2.5;        ///< maximum of k_casr [1]
    double min_sr = 1;          ///< minimum of k_casr [1]
    double V_rel = 0.102;       ///< maximal SR release rate (J_rel) [ms^-1]
    double V_xfer = 0.0038;     ///< subspace -> cytoplasm transfer rate (J_xfer) [ms^-1]
    double V_leak = 0.00036;    ///< SR leak rate (J_leak) [ms^-1]
    double Vmax_up = 0.006375;  ///< maximal SERCA uptake (J_up) [mM ms^-1]
    double K_up = 0.00025;      ///< half-saturation of J_up [mM]
    double Buf_c = 0.2;         ///< total cytoplasmic buffer [mM]
    double K_buf_c = 0.001;     ///< Ca_i half-saturation of the cytoplasmic buffer [mM]
    double Buf_sr = 10;         ///< total SR buffer [mM]
    double K_buf_sr = 0.3;      ///< Ca_SR half-saturation of the SR buffer [mM]
    double Buf_ss = 0.4;        ///< total subspace buffer [mM]
    double K_buf_ss = 0.00025;  ///< Ca_ss half-saturation of the subspace buffer [mM]

    /// The published parameters of a cell type (G_to, G_Ks and the s gate differ).
    static Parameters of(CellType type);
    /// Multiplies the maximal conductance or current of `channel` by `factor` (>= 0): g_Na, g_K1,
    /// g_to, g_Kr, g_Ks, g_CaL, g_bNa, g_bCa, g_pK, g_pCa, g_NaCa (K_NaCa), g_NaK (P_NaK), g_rel
    /// (V_rel), g_up (Vmax_up). Throws std::invalid_argument for another name or a negative factor.
    void scale(std::string_view channel, double factor);
    /// The channel names scale() accepts.
    static const std::array<std::string_view, 14>& channels();
  };

  static constexpr std::size_t n_states = 19;
  using State = std::array<double, n_states>;

  /// Position of each state variable (paper notation).
  struct StateIndex {
    enum : std::size_t {
      V = 0,    ///< transmembrane potential [mV]
      Xr1,      ///< I_Kr activation
      Xr2,      ///< I_Kr inactivation
      Xs,       ///< I_Ks activation
      m,        ///< I_Na activation
      h,        ///< I_Na fast inactivation
      j,        ///< I_Na slow inactivation
      d,        ///< I_CaL activation
      f,        ///< I_CaL slow voltage inactivation
      f2,       ///< I_CaL fast voltage inactivation
      fCass,    ///< I_CaL subspace-calcium inactivation
      s,        ///< I_to inactivation
      r,        ///< I_to activation
      Ca_i,     ///< free cytoplasmic Ca2+ [mM]
      R_prime,  ///< RyR fraction not inactivated (R-bar of the paper)
      Ca_SR,    ///< free SR Ca2+ [mM]
      Ca_ss,    ///< free subspace Ca2+ [mM]
      Na_i,     ///< intracellular Na+ [mM]
      K_i,      ///< intracellular K+ [mM]
    };
  };

  static constexpr std::array<std::string_view, n_states> state_names{"transmembrane_potential",
                                                                      "gate_xr1",
                                                                      "gate_xr2",
                                                                      "gate_xs",
                                                                      "gate_m",
                                                                      "gate_h",
                                                                      "gate_j",
                                                                      "gate_d",
                                                                      "gate_f",
                                                                      "gate_f2",
                                                                      "gate_fcass",
                                                                      "gate_s",
                                                                      "gate_r",
                                                                      "calcium_intracellular",
                                                                      "ryanodine_receptor_not_inactivated",
                                                                      "calcium_sarcoplasmic_reticulum",
                                                                      "calcium_subspace",
                                                                      "sodium_intracellular",
                                                                      "potassium_intracellular"};

  TenTusscherPanfilov2006() : TenTusscherPanfilov2006(Parameters{}) {}
  explicit TenTusscherPanfilov2006(Parameters parameters);

  /// The same model with its functions of V alone tabulated every `step` mV over valid_voltage()
  /// and interpolated linearly (the lookup tables of openCARP): the steady states and rates of the
  /// eleven voltage gates, and the voltage factors of I_pK, I_NaK, I_NaCa and I_CaL. Used by
  /// production_loss() and rbr_qss_step(); rates() (the CVODE reference) stays exact. step = 0: no
  /// table. The error this costs is measured by the `cell` scene (docs/electrophysiology.md).
  TenTusscherPanfilov2006 with_voltage_table(double step) const;
  double voltage_table_step() const { return table_ ? table_->step : 0.0; }
  const Parameters& parameters() const { return p_; }

  /// The resting state used by Niederer et al. 2011 for the epicardial cell (the CellML initial
  /// values).
  State initial_state() const;

  /// Production and loss of state k; `stimulus` [mV/ms] is the applied dV/dt (I_stim = -stimulus).
  ProductionLoss production_loss(std::size_t k, const State& y, double stimulus) const;

  /// dy/dt for all states.
  State rates(const State& y, double stimulus) const;

  /// One rbr_qss step (cell_integrators.hpp) that gives the generic forward and backward sweeps'
  /// result bit for bit: V is updated first in the forward sweep and last in the backward one, so
  /// the eleven gates that depend on V alone see the same V in both sweeps; their kinetics (x_inf,
  /// tau: most of the exponentials of the model) and QSS factors are computed once per step.
  void rbr_qss_step(State& y, double stimulus, double dt) const;

  /// The same step for lane_count cells at once (lanes.hpp): the scalar step's arithmetic in every
  /// lane, with vectorised elementary functions.
  using LaneState = std::array<Lanes, n_states>;
  void rbr_qss_step(LaneState& y, const Lanes& stimulus, double dt) const;

  /// [-200, 200] mV: every exponential in the model stays far from overflow there (arguments below
  /// about 50), and a cell never leaves about [-95, +50] mV, so a state outside this range has gone
  /// wrong.
  VoltageRange valid_voltage() const { return {-200, 200}; }

 private:
  // The equations are written once for a number type T: double for one cell, Lanes for several.
  template <class T>
  using StateOf = std::array<T, n_states>;

  /// A current or flux together with the coefficient c of its part c y that is proportional to the
  /// variable y being updated (c >= 0 for a term that removes y).
  template <class T>
  struct Split {
    T value;
    T coefficient;
  };
  /// The rate of one variable and its loss (the production is rate + loss y).
  template <class T>
  struct RateAndLoss {
    T rate;
    T loss;
  };
  template <class T>
  struct GateKinetics {
    T steady_state;   ///< x_inf [1]
    T time_constant;  ///< tau [ms]
  };
  /// The K+ currents [pA/pF] and the sum of their chord conductances [nS/pF].
  template <class T>
  struct PotassiumCurrents {
    T I_K1, I_to, I_Kr, I_Ks, I_pK;
    T conductance;
  };
  /// The Na+ channel currents [pA/pF] and the sum of their chord conductances [nS/pF].
  template <class T>
  struct SodiumCurrents {
    T I_Na, I_bNa;
    T conductance;
  };
  /// All sarcolemmal currents [pA/pF]; `linear_conductance` [nS/pF] is the sum of the chord
  /// conductances of the currents that are ohmic in V.
  template <class T>
  struct MembraneCurrents {
    PotassiumCurrents<T> K;
    SodiumCurrents<T> Na;
    T I_bCa, I_NaK;
    Split<T> I_CaL;   ///< coefficient: of Ca_ss
    Split<T> I_NaCa;  ///< coefficient: of Ca_i
    Split<T> I_pCa;   ///< coefficient: of Ca_i
    T linear_conductance;
  };

  template <class T>
  BasicProductionLoss<T> production_loss_of(std::size_t k, const StateOf<T>& y, const T& stimulus) const;
  template <class T>
  void rbr_qss_step_of(StateOf<T>& y, const T& stimulus, double dt) const;

  template <class T>
  GateKinetics<T> gate_kinetics(std::size_t k, const T& V, const T& Ca_ss) const;

  // Reversal potentials [mV].
  template <class T>
  T reversal_potential_Na(const T& Na_i) const;
  template <class T>
  T reversal_potential_K(const T& K_i) const;
  template <class T>
  T reversal_potential_Ks(const T& K_i, const T& Na_i) const;
  template <class T>
  T reversal_potential_Ca(const T& Ca_i) const;

  // Currents [pA/pF].
  template <class T>
  MembraneCurrents<T> membrane_currents(const StateOf<T>& y) const;
  template <class T>
  PotassiumCurrents<T> potassium_currents(const StateOf<T>& y) const;
  template <class T>
  SodiumCurrents<T> sodium_currents(const StateOf<T>& y) const;
  template <class T>
  T background_calcium(const T& V, const T& Ca_i) const;
  template <class T>
  Split<T> l_type_calcium(const StateOf<T>& y) const;
  template <class T>
  Split<T> sodium_calcium_exchange(const T& V, const T& Na_i, const T& Ca_i) const;
  template <class T>
  Split<T> calcium_pump(const T& Ca_i) const;
  template <class T>
  T sodium_potassium_pump(const T& V, const T& Na_i) const;

  // SR fluxes [mM/ms] and the RyR.
  template <class T>
  Split<T> uptake(const T& Ca_i) const;
  template <class T>
  T casr_dependence(const T& Ca_SR) const;
  template <class T>
  T ryanodine_open_probability(const StateOf<T>& y) const;

  // Rates of the non-gate variables from their currents and fluxes.
  template <class T>
  RateAndLoss<T> potential_rate(const MembraneCurrents<T>& I, const T& stimulus) const;
  template <class T>
  RateAndLoss<T> calcium_intracellular_rate(const StateOf<T>& y, const T& I_bCa, const Split<T>& I_NaCa,
                                            const Split<T>& I_pCa, const Split<T>& J_up) const;
  template <class T>
  RateAndLoss<T> calcium_subspace_rate(const StateOf<T>& y, const Split<T>& I_CaL, const T& open_probability) const;
  template <class T>
  RateAndLoss<T> calcium_sr_rate(const StateOf<T>& y, const T& J_up, const T& open_probability) const;
  template <class T>
  RateAndLoss<T> ryanodine_rate(const StateOf<T>& y) const;
  template <class T>
  T sodium_rate(const SodiumCurrents<T>& I_Na, const T& I_NaK, const T& I_NaCa) const;
  template <class T>
  T potassium_rate(const PotassiumCurrents<T>& I_K, const T& I_NaK, const T& stimulus) const;

  // The tabulated functions of V (with_voltage_table): columns of one row per V node.
  enum TableColumn : int {
    gate_columns = 0,  ///< 2 per voltage gate, in the order of tabulated_gate(): x_inf / tau, 1 / tau
    pK = 22,           ///< 1 / (1 + exp((25 - V) / 5.98))
    NaK,               ///< 1 / (1 + 0.1245 exp(-0.1 phi) + 0.0353 exp(-phi))
    NaCa_forward,      ///< exp(gamma phi) / (1 + K_sat exp((gamma - 1) phi))
    NaCa_reverse,      ///< exp((gamma - 1) phi) / (1 + K_sat exp((gamma - 1) phi))
    CaL,               ///< x / (exp(x) - 1), x = 2 (V - 15) F / (R T)
    CaL_ss,            ///< x exp(x) / (exp(x) - 1)
    n_columns
  };
  struct VoltageTable {
    double v_min = 0, step = 0, inverse_step = 0, last_node = 0;
    std::size_t rows = 0;
    std::vector<double> values;  ///< rows x n_columns
    double at(int column, double V) const;
    Lanes at(int column, const Lanes& V) const;
  };
  /// The table column pair of gate k (its index among the voltage gates), or -1 (fCass, not a gate).
  static int tabulated_gate(std::size_t k);

  Parameters p_;
  std::shared_ptr<const VoltageTable> table_;  ///< shared by the copies of the model
  double RT_over_F_ = 0;          ///< [mV]
  double sqrt_K_o_factor_ = 1;    ///< sqrt(K_o / 5.4 mM)
  double current_to_flux_c_ = 0;  ///< C_m / (V_c F): [mM/ms] per [pA/pF] in the cytoplasm
};

static_assert(ReactionModel<TenTusscherPanfilov2006>);

}  // namespace sph
