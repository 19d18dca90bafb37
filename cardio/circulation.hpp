#pragma once
// A 0D (lumped) blood circulation for the two ventricles: an open-loop three-element Windkessel
// per ventricle, or the closed-loop model of Regazzoni, Salvador, Africa, Fedele, Dede' &
// Quarteroni 2022, J. Comput. Phys. 457:111083 (doi:10.1016/j.jcp.2022.111083; preprint
// arXiv:2011.15040). Units: pressure kPa, volume mm^3, time ms, flow mm^3/ms, resistance
// kPa ms/mm^3, compliance mm^3/kPa, inductance kPa ms^2/mm^3, elastance kPa/mm^3.
// Conversions (once, in the defaults): 1 mmHg = 0.133322 kPa, 1 mL = 1000 mm^3, 1 s = 1000 ms, so
// 1 mmHg s/mL = 0.133322 kPa ms/mm^3, 1 mL/mmHg = 7500.6 mm^3/kPa, 1 mmHg s^2/mL = 133.322
// kPa ms^2/mm^3, 1 mmHg/mL = 1.33322e-4 kPa/mm^3.
//
// Chambers. A time-varying elastance chamber (the atria, and a ventricle in `elastance` mode):
//   p = E(t) (V - V0),  E(t) = E_pass + E_act e(t),
//   e(t) = (1 - cos(pi s_C / T_C)) / 2  for 0 <= s_C < T_C,  s_C = (t - t_C) mod T_HB,
//          (1 + cos(pi s_R / T_R)) / 2  for 0 <= s_R < T_R,  s_R = (t - t_C - T_C) mod T_HB,
//          0 otherwise,
// the chamber activation of Regazzoni et al. 2022 as written in the authors' reference code
// (github.com/FrancescoRegazzoni/cardioemulator, example/circulation_closed_loop.py at 4f1c757,
// `time_varying_elastance`: E_A = E_act, E_B = E_pass), used there and here for all four chambers.
// A ventricle in `coupled` mode takes its volume V_3D(t) from a 3D mechanics model. The circulation
// keeps V_b, the blood in the cavity, which changes only by the valve flows, and the cavity
// pressure is a stiff penalty on the mismatch:
//   dV_b/dt = Q_in - Q_out,   p = p_ref + (V_b - V_3D(t)) / C_c,
// with C_c the cavity compliance (compressibility of blood and cavity; default 20 mm^3/kPa) and
// p_ref set by initialise() so that p starts at the given pressure with V_b = V_3D.
// Isovolumic tolerance: while both valves of a coupled ventricle are closed, V_b changes only by
// the leakage through the closed valves (|p_up - p_down| / R_closed), so
//   Delta V_3D = -C_c Delta p + leakage:
// the 3D cavity can change by C_c times the pressure change, e.g. 20 mm^3/kPa x 10 kPa = 200 mm^3
// (0.2 mL) over an isovolumic contraction. A smaller C_c tightens this and stiffens the coupling:
// the pressure answers the 3D volume with dp/dV_3D = -1/C_c, which a mechanics step that is explicit
// in the pressure has to resolve.
//
// Valves: non-ideal diodes as in Regazzoni et al. 2022: Q = (p_up - p_down) / R with R = R_open if
// p_up > p_down, else R_closed. Deviation: the reference code smooths this switch (log R follows an
// arctan of p_down - p_up); here it is sharp, and the valve states are found by iteration.
//
// Model `windkessel` (open loop), per ventricle (LV systemic, RV pulmonary):
//   Q_in  = (p_fill - p) / R_in                 (mitral / tricuspid valve, p_fill constant),
//   Q_out = (p - p_C) / (R_out + Z)             (aortic / pulmonary valve in series with Z),
//   C dp_C/dt = Q_out - (p_C - p_dist) / R,     arterial pressure p_art = p_C + Z Q_out,
// the three-element Windkessel of Westerhof, Lankhaar & Westerhof 2009, Med. Biol. Eng. Comput.
// 47:131 (characteristic impedance Z in series with compliance C parallel to peripheral resistance
// R). The valve state of the outflow link follows sign(p - p_C), which is the sign of p - p_art.
// States: V (or V_b) of each ventricle, C p_C of each Windkessel.
//
// Model `closed_loop` (Regazzoni et al. 2022, as in the reference code): the four chambers
// LA, LV, RA, RV; valves MV (LA->LV), AV (LV->AR_SYS), TV (RA->RV), PV (RV->AR_PUL); and four
// R-L-C vessel compartments,
//   C_AR_SYS dp_AR_SYS/dt = Q_AV - Q_AR_SYS,     L_AR_SYS dQ_AR_SYS/dt = p_AR_SYS - p_VEN_SYS - R_AR_SYS Q_AR_SYS,
//   C_VEN_SYS dp_VEN_SYS/dt = Q_AR_SYS - Q_VEN_SYS, L_VEN_SYS dQ_VEN_SYS/dt = p_VEN_SYS - p_RA - R_VEN_SYS Q_VEN_SYS,
//   C_AR_PUL dp_AR_PUL/dt = Q_PV - Q_AR_PUL,     L_AR_PUL dQ_AR_PUL/dt = p_AR_PUL - p_VEN_PUL - R_AR_PUL Q_AR_PUL,
//   C_VEN_PUL dp_VEN_PUL/dt = Q_AR_PUL - Q_VEN_PUL, L_VEN_PUL dQ_VEN_PUL/dt = p_VEN_PUL - p_LA - R_VEN_PUL Q_VEN_PUL,
//   dV_LA/dt = Q_VEN_PUL - Q_MV, dV_LV/dt = Q_MV - Q_AV, dV_RA/dt = Q_VEN_SYS - Q_TV, dV_RV/dt = Q_TV - Q_PV.
// The compartments are stored by their (stressed) volume C p; the model has no unstressed vessel
// volumes, so the total blood volume sum V_chambers + sum C p is the whole circulating volume and
// is conserved. Parameters: the defaults of the authors' reference implementation (cardioemulator,
// example/circulation_closed_loop.py at 4f1c757, which cites this model), with the heart period
// T_HB = 800 ms (75 bpm, as in the baseline example/data/params_bsln.json of the same repository)
// and the chamber timings the same fractions of T_HB as there. The parameter table of the journal
// paper itself was not available here to check them against. With these defaults the pulmonary
// artery runs at about 40/35 mmHg (R_AR_PUL = R_VEN_PUL = 0.1625 mmHg s/mL); the later baseline
// (params_bsln.json) lowers them to 0.032 and 0.035 mmHg s/mL.
//
// Integration: with the valve states fixed, the system is linear in its states (elastances are
// given functions of time, V_3D is linear in time over a coupling step), and stiff (an open valve
// into a coupled ventricle has time constant R_open C_c = 0.02 ms). Each sub-step of at most
// max_step is backward Euler,
//   (I - h A(t_n+1, s)) y_n+1 = y_n + h f(t_n+1, s),
// solved densely (Eigen, fixed size, no allocation) for valve states s found by fixed-point
// iteration (solve, set s from the new pressures, repeat until s is unchanged, at most
// max_valve_iterations; if it does not settle the last solution is kept and counted). The volumes
// are then updated as y_n+1 = y_n + h (Q_in - Q_out) with the flows of that solution, so every
// flow leaves one compartment and enters another and the total volume is conserved to round-off
// whatever the accuracy of the solve. Backward Euler is L-stable: any step is stable.

#include <array>
#include <string>
#include <utility>
#include <vector>

#include "libsph/core/state_archive.hpp"

namespace sph {
class Parameters;
}

namespace cardio {

/// Units of the published 0D parameters in those of cardiosph (kPa, mm^3, ms).
namespace circulation_units {
constexpr double mmHg = 0.133322;  ///< [kPa]
constexpr double mL = 1000;        ///< [mm^3]
constexpr double s = 1000;         ///< [ms]
}  // namespace circulation_units

enum class CirculationModel { windkessel, closed_loop };
/// The names of the models as parameters take them.
const std::vector<std::pair<std::string, CirculationModel>>& circulation_model_names();

enum class VentricleMode { elastance, coupled };
const std::vector<std::pair<std::string, VentricleMode>>& ventricle_mode_names();

enum class Ventricle { left, right };
enum class Valve { mitral, aortic, tricuspid, pulmonary };

/// A time-varying elastance chamber: p = (E_pass + E_act e(t)) (V - V0) (see the header comment).
struct ElastanceChamberSettings {
  double passive_elastance = 0;     ///< E_pass [kPa/mm^3]
  double active_elastance = 0;      ///< E_act [kPa/mm^3]
  double rest_volume = 0;           ///< V0 [mm^3]
  double contraction_onset = 0;     ///< t_C [ms] within each beat
  double contraction_duration = 0;  ///< T_C [ms]
  double relaxation_duration = 0;   ///< T_R [ms]

  /// e(t) in [0, 1] for heart period T_HB [ms].
  double activation(double t, double period) const;
  /// E(t) [kPa/mm^3].
  double elastance(double t, double period) const { return passive_elastance + active_elastance * activation(t, period); }
};

/// A chamber from E_pass, E_act [mmHg/mL], V0 [mL] and its timings [ms].
constexpr ElastanceChamberSettings chamber_in_clinical_units(double E_pass, double E_act, double V0, double onset,
                                                            double contraction, double relaxation) {
  using namespace circulation_units;
  return {E_pass * mmHg / mL, E_act * mmHg / mL, V0 * mL, onset, contraction, relaxation};
}

/// One R-L-C vessel compartment of the closed loop.
struct VesselSettings {
  double resistance = 0;  ///< R [kPa ms/mm^3]
  double compliance = 0;  ///< C [mm^3/kPa]
  double inductance = 0;  ///< L [kPa ms^2/mm^3]
};

/// A vessel from R [mmHg s/mL], C [mL/mmHg] and L [mmHg s^2/mL].
constexpr VesselSettings vessel_in_clinical_units(double R, double C, double L) {
  using namespace circulation_units;
  return {R * mmHg * s / mL, C * mL / mmHg, L * mmHg * s * s / mL};
}

/// The open-loop load of one ventricle: constant filling pressure, three-element Windkessel.
struct WindkesselSettings {
  double filling_pressure = 0;          ///< p_fill [kPa] upstream of the inflow valve
  double characteristic_impedance = 0;  ///< Z [kPa ms/mm^3]
  double resistance = 0;                ///< R, peripheral [kPa ms/mm^3]
  double compliance = 0;                ///< C [mm^3/kPa]
  double distal_pressure = 0;           ///< p_dist [kPa] downstream of R
};

struct CirculationSettings {
  CirculationModel model = CirculationModel::closed_loop;
  /// Set by the caller: `coupled` for a ventricle whose volume comes from a 3D model.
  VentricleMode lv_mode = VentricleMode::elastance, rv_mode = VentricleMode::elastance;
  double heart_period = 800;       ///< T_HB [ms] (Regazzoni et al. 2022)
  double cavity_compliance = 20;   ///< C_c [mm^3/kPa] of a coupled ventricle
  double max_step = 0.1;           ///< [ms] largest backward Euler sub-step
  int max_valve_iterations = 6;    ///< fixed-point iterations on the valve states per sub-step

  // Valves: open resistances R_min and the common closed resistance R_max of Regazzoni et al.
  // (0.0075 and 75006.2 mmHg s/mL = 1e-3 and 1e4 kPa ms/mm^3). The Windkessel model uses the same
  // valves (mitral/aortic for the LV, tricuspid/pulmonary for the RV).
  double mitral_resistance = 1e-3;          ///< [kPa ms/mm^3] open
  double aortic_resistance = 1e-3;          ///< [kPa ms/mm^3] open
  double tricuspid_resistance = 1e-3;       ///< [kPa ms/mm^3] open
  double pulmonary_valve_resistance = 1e-3; ///< [kPa ms/mm^3] open
  double valve_closed_resistance = 1e4;     ///< [kPa ms/mm^3] every valve, closed

  // Chambers (reference code defaults; timings as fractions 0.17, 0.34, 0.80 of T_HB = 800 ms).
  ElastanceChamberSettings la = chamber_in_clinical_units(0.09, 0.07, 4, 640, 136, 136);
  ElastanceChamberSettings lv = chamber_in_clinical_units(0.08, 2.75, 5, 0, 272, 136);
  ElastanceChamberSettings ra = chamber_in_clinical_units(0.07, 0.06, 4, 640, 136, 136);
  ElastanceChamberSettings rv = chamber_in_clinical_units(0.05, 0.55, 10, 0, 272, 136);

  // Closed-loop vessels (reference code defaults), R [mmHg s/mL], C [mL/mmHg], L [mmHg s^2/mL]:
  // systemic arterial 0.8, 1.2, 5e-3; systemic venous 0.26, 60, 5e-4; pulmonary arterial 0.1625,
  // 10, 5e-4; pulmonary venous 0.1625, 16, 5e-4.
  VesselSettings systemic_arterial = vessel_in_clinical_units(0.8, 1.2, 5e-3);
  VesselSettings systemic_venous = vessel_in_clinical_units(0.26, 60, 5e-4);
  VesselSettings pulmonary_arterial = vessel_in_clinical_units(0.1625, 10, 5e-4);
  VesselSettings pulmonary_venous = vessel_in_clinical_units(0.1625, 16, 5e-4);

  // Windkessel loads of an adult at rest.
  // LV, systemic: R = 1 mmHg s/mL and C = 1.5 mL/mmHg (RC = 1.5 s), the adult orders of magnitude
  //   of Westerhof, Lankhaar & Westerhof 2009 (as in cardio/cavity_pressure.hpp); Z = 0.05 mmHg s/mL,
  //   taken as 5 % of R; p_fill = 1.2 kPa (9 mmHg), a normal mean left atrial pressure; p_dist = 0.
  // RV, pulmonary: R = 0.15 mmHg s/mL total pulmonary resistance (p_dist = 0) and C = 5 mL/mmHg,
  //   on the pulmonary RC time of 0.75 s (C = 0.75/R) of Lankhaar et al. 2006, Am. J. Physiol. Heart
  //   Circ. Physiol. 291:H1731; Z = 0.02 mmHg s/mL, as Z_c = 22 dyn s/cm^5 (0.017 mmHg s/mL) at rest
  //   in Slife et al. 1990, Am. J. Physiol. 258:H1823; p_fill = 0.5 kPa (3.75 mmHg), a normal mean
  //   right atrial pressure.
  WindkesselSettings lv_windkessel{1.2, 0.05 * circulation_units::mmHg * circulation_units::s / circulation_units::mL,
                                   1.0 * circulation_units::mmHg * circulation_units::s / circulation_units::mL,
                                   1.5 * circulation_units::mL / circulation_units::mmHg, 0};
  WindkesselSettings rv_windkessel{0.5, 0.02 * circulation_units::mmHg * circulation_units::s / circulation_units::mL,
                                   0.15 * circulation_units::mmHg * circulation_units::s / circulation_units::mL,
                                   5 * circulation_units::mL / circulation_units::mmHg, 0};

  // Initial state (reference code defaults: 65, 120, 65, 145 mL; 80, 30, 35, 24 mmHg; vessel flows
  // zero). The ventricle volumes apply to `elastance` ventricles (a coupled one starts from
  // Circulation::initialise); the Windkessel compliances start at the arterial pressures.
  double initial_la_volume = 65 * circulation_units::mL;   ///< [mm^3]
  double initial_lv_volume = 120 * circulation_units::mL;  ///< [mm^3]
  double initial_ra_volume = 65 * circulation_units::mL;   ///< [mm^3]
  double initial_rv_volume = 145 * circulation_units::mL;  ///< [mm^3]
  double initial_systemic_arterial_pressure = 80 * circulation_units::mmHg;   ///< [kPa] also p_C of the LV Windkessel
  double initial_systemic_venous_pressure = 30 * circulation_units::mmHg;     ///< [kPa]
  double initial_pulmonary_arterial_pressure = 35 * circulation_units::mmHg;  ///< [kPa] also p_C of the RV Windkessel
  double initial_pulmonary_venous_pressure = 24 * circulation_units::mmHg;    ///< [kPa]

  /// Throws std::invalid_argument naming the part, its parameter and the problem.
  void check() const;
};

/// Declares one parameter per setting, all prefixed circulation_: circulation_model,
/// circulation_lv_mode, circulation_rv_mode, circulation_heart_period, circulation_cavity_compliance,
/// circulation_max_step, circulation_max_valve_iterations, circulation_{mitral,aortic,tricuspid,
/// pulmonary_valve}_resistance, circulation_valve_closed_resistance,
/// circulation_{la,lv,ra,rv}_{passive_elastance,active_elastance,rest_volume,contraction_onset,
/// contraction_duration,relaxation_duration}, circulation_{systemic,pulmonary}_{arterial,venous}_
/// {resistance,compliance,inductance}, circulation_{lv,rv}_windkessel_{filling_pressure,
/// characteristic_impedance,resistance,compliance,distal_pressure} and circulation_initial_{la,lv,
/// ra,rv}_volume, circulation_initial_{systemic,pulmonary}_{arterial,venous}_pressure.
/// With `ventricles` false (the ventricles are the caller's 3D cavities, as in the heart), the
/// ventricle modes, the heart period, the ventricular elastance chambers and their initial volumes
/// are left out.
void declare_parameters(sph::Parameters& p, CirculationSettings& settings, bool ventricles = true);

class Circulation {
 public:
  /// Checks the settings and sets the initial state at t = 0. A coupled ventricle needs
  /// initialise() before the first advance().
  explicit Circulation(const CirculationSettings& settings);

  /// Sets the time to t0 [ms] and, for each coupled ventricle, V_b = V_3D and p_ref so that its
  /// pressure is the given one [mm^3, kPa]; the values of elastance ventricles are ignored.
  void initialise(double t0, double lv_volume_3d, double rv_volume_3d, double lv_pressure, double rv_pressure);

  /// Advances from t to t + dt [ms] (t must be the current time) in sub-steps of at most max_step,
  /// with V_3D of each coupled ventricle linear in time from its last value to the given end value
  /// [mm^3] (ignored for elastance ventricles). Throws std::runtime_error naming the compartment and
  /// the time if a state becomes non-finite.
  void advance(double t, double dt, double lv_volume_3d_end, double rv_volume_3d_end);
  /// The same without 3D volumes: only when both ventricles are elastance chambers.
  void advance(double t, double dt);

  double time() const { return time_; }
  /// Cavity pressure [kPa] at the current time: what the 3D mechanics applies next.
  double pressure(Ventricle v) const { return pressure_[ventricle_node_[index(v)]]; }
  /// The pressure a coupled ventricle would have at 3D volume V [mm^3] with its current blood
  /// volume: p_ref + (V_b - V) / C_c [kPa]; the 3D mechanics evaluates it at every sub-step, so the
  /// stiff penalty acts on the current volume without the lag of a coupling step.
  double pressure_at_volume(Ventricle v, double volume) const {
    return reference_pressure_[index(v)] + (ventricle_blood_volume(v) - volume) / settings_.cavity_compliance;
  }
  /// p_ref of a coupled ventricle [kPa] (set by initialise()).
  double reference_pressure(Ventricle v) const { return reference_pressure_[index(v)]; }
  /// V_b of a coupled ventricle, V of an elastance one [mm^3].
  double ventricle_blood_volume(Ventricle v) const { return state_[ventricle_node_[index(v)]]; }
  /// V_3D of a coupled ventricle (its last value), V of an elastance one [mm^3].
  double ventricle_3d_volume(Ventricle v) const;
  /// Pressure downstream of the outflow valve [kPa]: p_AR_SYS / p_AR_PUL in the closed loop,
  /// p_C + Z Q_out of the Windkessel.
  double arterial_pressure(Ventricle v) const;
  /// Sum of the chamber volumes (V_b for coupled ventricles) and C p of the vessel compartments
  /// [mm^3]; constant in the closed loop.
  double total_blood_volume() const;
  bool valve_open(Valve valve) const { return open_[valve_link_[static_cast<int>(valve)]]; }
  /// Flow through a valve over the last sub-step [mm^3/ms].
  double valve_flow(Valve valve) const { return flow_[valve_link_[static_cast<int>(valve)]]; }
  /// Sub-steps whose valve states did not settle within max_valve_iterations.
  long unsettled_valve_steps() const { return unsettled_steps_; }
  const CirculationSettings& settings() const { return settings_; }

  /// Names of row(): time; p_ and v_ of every compartment (v3d_ of coupled ventricles); q_ of every
  /// flow; valve_<mv|av|tv|pv>_open; p_ao and p_pa in the Windkessel model; v_total.
  std::vector<std::string> columns() const;
  std::vector<double> row() const;
  /// Saves or loads the state, the sources, the pressures, flows and valves, the coupled volumes
  /// and the time (checkpoints); the network itself comes from the settings.
  void checkpoint(sph::StateArchive& archive) {
    archive.io("sources", sources_);
    archive.io("state", state_);
    archive.io("a", a_);
    archive.io("b", b_);
    archive.io("pressure", pressure_);
    archive.io("flow", flow_);
    archive.io("open", open_);
    archive.io("volume_3d", volume_3d_);
    archive.io("reference_pressure", reference_pressure_);
    archive.io("time", time_);
    archive.io("initialised", initialised_);
    archive.io("unsettled_steps", unsettled_steps_);
  }

 private:
  static constexpr int max_nodes = 8, max_links = 8, max_states = 12, max_sources = 4;
  enum class NodeKind { chamber, coupled_ventricle, vessel };
  struct Node {
    NodeKind kind = NodeKind::vessel;
    std::string name, description;
    ElastanceChamberSettings chamber{};  // chamber, elastance ventricle
    double compliance = 0;               // vessel
    int ventricle = -1;                  // 0 LV, 1 RV
  };
  // A link carries a flow from `up` to `down` (node index >= 0, or -1 - source index). A valve
  // has two resistances; an inductive link has its flow as state n_nodes + inductor.
  struct Link {
    std::string name;
    int up = 0, down = 0;
    double open_resistance = 0, closed_resistance = 0;
    bool valve = false;
    double inductance = 0;
    int inductor = -1;
  };

  static int index(Ventricle v) { return v == Ventricle::left ? 0 : 1; }
  static Node chamber_node(const std::string& name, const std::string& description, const ElastanceChamberSettings& chamber);
  static Node vessel_node(const std::string& name, const std::string& description, double compliance);
  /// An elastance chamber or, in `coupled` mode, a coupled cavity.
  static Node ventricle_node(const std::string& name, const std::string& description,
                             const ElastanceChamberSettings& chamber, VentricleMode mode, int ventricle);
  int add_node(Node node, double state);
  int add_link(Link link);
  void build_closed_loop();
  void build_windkessel();
  /// Pressure coefficients p = a V + b of every node at time t with the current V_3D.
  void update_coefficients(double t);
  double endpoint_pressure(int endpoint, const double* state) const;
  void update_outputs();
  void step(double h, double t_new);
  void check_finite(double t) const;

  CirculationSettings settings_;
  std::array<Node, max_nodes> nodes_{};
  std::array<Link, max_links> links_{};
  int n_nodes_ = 0, n_links_ = 0, n_inductors_ = 0;
  std::array<double, max_sources> sources_{};
  std::array<double, max_states> state_{};
  std::array<double, max_nodes> a_{}, b_{}, pressure_{};
  std::array<double, max_links> flow_{};
  std::array<bool, max_links> open_{};
  std::array<int, 2> ventricle_node_{};
  std::array<int, 4> valve_link_{};
  std::array<double, 2> volume_3d_{}, reference_pressure_{};
  std::array<int, 2> arterial_node_{};  // AR_SYS / AR_PUL, or the Windkessel compliances
  double time_ = 0;
  bool initialised_ = false;
  long unsettled_steps_ = 0;
};

}  // namespace cardio
