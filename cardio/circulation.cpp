#include "cardio/circulation.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "libsph/io/parameters.hpp"

namespace cardio {

namespace {

std::string number(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

const char* chamber_key(int chamber) {
  static const char* keys[] = {"la", "lv", "ra", "rv"};
  return keys[chamber];
}

}  // namespace

const std::vector<std::pair<std::string, CirculationModel>>& circulation_model_names() {
  static const std::vector<std::pair<std::string, CirculationModel>> names{{"windkessel", CirculationModel::windkessel},
                                                                           {"closed_loop", CirculationModel::closed_loop}};
  return names;
}

const std::vector<std::pair<std::string, VentricleMode>>& ventricle_mode_names() {
  static const std::vector<std::pair<std::string, VentricleMode>> names{{"elastance", VentricleMode::elastance},
                                                                        {"coupled", VentricleMode::coupled}};
  return names;
}

double ElastanceChamberSettings::activation(double t, double period) const {
  // Phase in [0, T_HB) since the contraction onset and since the start of relaxation t_C + T_C.
  auto phase = [period](double s) { return s - period * std::floor(s / period); };
  const double s_C = phase(t - contraction_onset), s_R = phase(t - contraction_onset - contraction_duration);
  double e = 0;
  if (s_C < contraction_duration) e += 0.5 * (1 - std::cos(std::numbers::pi * s_C / contraction_duration));   // rise
  if (s_R < relaxation_duration) e += 0.5 * (1 + std::cos(std::numbers::pi * s_R / relaxation_duration));    // decay
  return std::clamp(e, 0.0, 1.0);
}

void CirculationSettings::check() const {
  auto fail = [](const std::string& part, const std::string& key, const std::string& problem, double value) {
    throw std::invalid_argument("circulation: " + part + " (circulation_" + key + ") " + problem + ", got " + number(value));
  };
  auto positive = [&](double v, const std::string& part, const std::string& key) {
    if (!(v > 0) || !std::isfinite(v)) fail(part, key, "must be positive and finite", v);
  };
  auto non_negative = [&](double v, const std::string& part, const std::string& key) {
    if (!(v >= 0) || !std::isfinite(v)) fail(part, key, "must be >= 0 and finite", v);
  };
  auto finite = [&](double v, const std::string& part, const std::string& key) {
    if (!std::isfinite(v)) fail(part, key, "must be finite", v);
  };

  positive(heart_period, "heart period", "heart_period");
  positive(cavity_compliance, "cavity compliance C_c", "cavity_compliance");
  positive(max_step, "largest 0D step", "max_step");
  if (max_valve_iterations < 1) fail("valve iterations", "max_valve_iterations", "must be at least 1", max_valve_iterations);

  positive(mitral_resistance, "mitral valve open resistance", "mitral_resistance");
  positive(aortic_resistance, "aortic valve open resistance", "aortic_resistance");
  positive(tricuspid_resistance, "tricuspid valve open resistance", "tricuspid_resistance");
  positive(pulmonary_valve_resistance, "pulmonary valve open resistance", "pulmonary_valve_resistance");
  positive(valve_closed_resistance, "closed valve resistance", "valve_closed_resistance");
  const double largest_open =
      std::max({mitral_resistance, aortic_resistance, tricuspid_resistance, pulmonary_valve_resistance});
  if (!(valve_closed_resistance > largest_open))
    fail("closed valve resistance", "valve_closed_resistance",
         "must exceed every open valve resistance (largest " + number(largest_open) + " kPa ms/mm^3)", valve_closed_resistance);

  const std::array<const ElastanceChamberSettings*, 4> chambers{&la, &lv, &ra, &rv};
  const char* chamber_names[] = {"left atrium", "left ventricle", "right atrium", "right ventricle"};
  for (int c = 0; c < 4; ++c) {
    const auto& ch = *chambers[c];
    const std::string part = chamber_names[c], key = std::string(chamber_key(c)) + "_";
    positive(ch.passive_elastance, part + " passive elastance", key + "passive_elastance");
    non_negative(ch.active_elastance, part + " active elastance", key + "active_elastance");
    non_negative(ch.rest_volume, part + " rest volume", key + "rest_volume");
    finite(ch.contraction_onset, part + " contraction onset", key + "contraction_onset");
    positive(ch.contraction_duration, part + " contraction duration", key + "contraction_duration");
    positive(ch.relaxation_duration, part + " relaxation duration", key + "relaxation_duration");
    if (ch.contraction_duration + ch.relaxation_duration > heart_period)
      fail(part + " contraction and relaxation", key + "contraction_duration",
           "plus the relaxation duration must not exceed the heart period " + number(heart_period) + " ms",
           ch.contraction_duration);
  }

  const std::array<const VesselSettings*, 4> vessels{&systemic_arterial, &systemic_venous, &pulmonary_arterial,
                                                      &pulmonary_venous};
  const char* vessel_names[] = {"systemic arterial", "systemic venous", "pulmonary arterial", "pulmonary venous"};
  const char* vessel_keys[] = {"systemic_arterial_", "systemic_venous_", "pulmonary_arterial_", "pulmonary_venous_"};
  for (int k = 0; k < 4; ++k) {
    const std::string part = vessel_names[k], key = vessel_keys[k];
    positive(vessels[k]->resistance, part + " resistance", key + "resistance");
    positive(vessels[k]->compliance, part + " compliance", key + "compliance");
    positive(vessels[k]->inductance, part + " inductance", key + "inductance");
  }

  const std::array<const WindkesselSettings*, 2> loads{&lv_windkessel, &rv_windkessel};
  const char* load_names[] = {"LV Windkessel", "RV Windkessel"};
  const char* load_keys[] = {"lv_windkessel_", "rv_windkessel_"};
  for (int k = 0; k < 2; ++k) {
    const std::string part = load_names[k], key = load_keys[k];
    finite(loads[k]->filling_pressure, part + " filling pressure", key + "filling_pressure");
    non_negative(loads[k]->characteristic_impedance, part + " characteristic impedance", key + "characteristic_impedance");
    positive(loads[k]->resistance, part + " peripheral resistance", key + "resistance");
    positive(loads[k]->compliance, part + " compliance", key + "compliance");
    finite(loads[k]->distal_pressure, part + " distal pressure", key + "distal_pressure");
  }

  non_negative(initial_la_volume, "initial LA volume", "initial_la_volume");
  non_negative(initial_lv_volume, "initial LV volume", "initial_lv_volume");
  non_negative(initial_ra_volume, "initial RA volume", "initial_ra_volume");
  non_negative(initial_rv_volume, "initial RV volume", "initial_rv_volume");
  finite(initial_systemic_arterial_pressure, "initial systemic arterial pressure", "initial_systemic_arterial_pressure");
  finite(initial_systemic_venous_pressure, "initial systemic venous pressure", "initial_systemic_venous_pressure");
  finite(initial_pulmonary_arterial_pressure, "initial pulmonary arterial pressure", "initial_pulmonary_arterial_pressure");
  finite(initial_pulmonary_venous_pressure, "initial pulmonary venous pressure", "initial_pulmonary_venous_pressure");
}

void declare_parameters(sph::Parameters& p, CirculationSettings& s, bool ventricles) {
  using sph::Range;
  p.add_enum("circulation_model", s.model, circulation_model_names(),
             "0D circulation: windkessel (filling pressure and three-element Windkessel per ventricle, open loop) or "
             "closed_loop (Regazzoni et al. 2022: atria, valves, systemic and pulmonary R-L-C compartments)");
  if (ventricles) {
    p.add_enum("circulation_lv_mode", s.lv_mode, ventricle_mode_names(),
               "LV: 0D time-varying elastance chamber, or coupled (volume from the 3D mechanics, penalty pressure)");
    p.add_enum("circulation_rv_mode", s.rv_mode, ventricle_mode_names(), "RV: elastance or coupled, as circulation_lv_mode");
    p.add("circulation_heart_period", s.heart_period, "ms", "heart period T_HB of the chamber activations", Range::positive());
  }
  p.add("circulation_cavity_compliance", s.cavity_compliance, "mm^3/kPa",
        "C_c of a coupled ventricle: p = p_ref + (V_b - V_3D)/C_c; while the valves are closed V_3D can move only by "
        "C_c times the pressure change",
        Range::positive());
  p.add("circulation_max_step", s.max_step, "ms", "largest backward Euler sub-step of the 0D model", Range::positive());
  p.add("circulation_max_valve_iterations", s.max_valve_iterations, "-",
        "fixed-point iterations on the valve states per sub-step", Range::closed(1, 100));

  p.add("circulation_mitral_resistance", s.mitral_resistance, "kPa ms/mm^3", "open mitral valve resistance R_min",
        Range::positive());
  p.add("circulation_aortic_resistance", s.aortic_resistance, "kPa ms/mm^3", "open aortic valve resistance R_min",
        Range::positive());
  p.add("circulation_tricuspid_resistance", s.tricuspid_resistance, "kPa ms/mm^3", "open tricuspid valve resistance R_min",
        Range::positive());
  p.add("circulation_pulmonary_valve_resistance", s.pulmonary_valve_resistance, "kPa ms/mm^3",
        "open pulmonary valve resistance R_min", Range::positive());
  p.add("circulation_valve_closed_resistance", s.valve_closed_resistance, "kPa ms/mm^3",
        "closed resistance R_max of every valve (leakage)", Range::positive());

  auto chamber = [&p](const std::string& key, const std::string& label, ElastanceChamberSettings& c) {
    const std::string k = "circulation_" + key + "_";
    p.add(k + "passive_elastance", c.passive_elastance, "kPa/mm^3", label + " passive elastance E_pass", Range::positive());
    p.add(k + "active_elastance", c.active_elastance, "kPa/mm^3", label + " active elastance E_act (peak E_pass + E_act)",
          Range::non_negative());
    p.add(k + "rest_volume", c.rest_volume, "mm^3", label + " volume V0 at zero pressure", Range::non_negative());
    p.add(k + "contraction_onset", c.contraction_onset, "ms", label + " contraction onset t_C within each beat");
    p.add(k + "contraction_duration", c.contraction_duration, "ms", label + " contraction duration T_C", Range::positive());
    p.add(k + "relaxation_duration", c.relaxation_duration, "ms", label + " relaxation duration T_R", Range::positive());
  };
  chamber("la", "LA", s.la);
  if (ventricles) chamber("lv", "LV (elastance mode)", s.lv);
  chamber("ra", "RA", s.ra);
  if (ventricles) chamber("rv", "RV (elastance mode)", s.rv);

  auto vessel = [&p](const std::string& key, const std::string& label, VesselSettings& v) {
    const std::string k = "circulation_" + key + "_";
    p.add(k + "resistance", v.resistance, "kPa ms/mm^3", label + " resistance R (closed loop)", Range::positive());
    p.add(k + "compliance", v.compliance, "mm^3/kPa", label + " compliance C (closed loop)", Range::positive());
    p.add(k + "inductance", v.inductance, "kPa ms^2/mm^3", label + " inductance L (closed loop)", Range::positive());
  };
  vessel("systemic_arterial", "systemic arterial", s.systemic_arterial);
  vessel("systemic_venous", "systemic venous", s.systemic_venous);
  vessel("pulmonary_arterial", "pulmonary arterial", s.pulmonary_arterial);
  vessel("pulmonary_venous", "pulmonary venous", s.pulmonary_venous);

  auto load = [&p](const std::string& key, const std::string& label, WindkesselSettings& w) {
    const std::string k = "circulation_" + key + "_windkessel_";
    p.add(k + "filling_pressure", w.filling_pressure, "kPa", label + " constant filling pressure upstream of the inflow valve");
    p.add(k + "characteristic_impedance", w.characteristic_impedance, "kPa ms/mm^3",
          label + " characteristic impedance Z (0: two-element Windkessel)", Range::non_negative());
    p.add(k + "resistance", w.resistance, "kPa ms/mm^3", label + " peripheral resistance R", Range::positive());
    p.add(k + "compliance", w.compliance, "mm^3/kPa", label + " arterial compliance C", Range::positive());
    p.add(k + "distal_pressure", w.distal_pressure, "kPa", label + " pressure downstream of R");
  };
  load("lv", "LV (systemic) Windkessel:", s.lv_windkessel);
  load("rv", "RV (pulmonary) Windkessel:", s.rv_windkessel);

  p.add("circulation_initial_la_volume", s.initial_la_volume, "mm^3", "initial LA volume", Range::non_negative());
  if (ventricles)
    p.add("circulation_initial_lv_volume", s.initial_lv_volume, "mm^3", "initial LV volume (elastance mode)", Range::non_negative());
  p.add("circulation_initial_ra_volume", s.initial_ra_volume, "mm^3", "initial RA volume", Range::non_negative());
  if (ventricles)
    p.add("circulation_initial_rv_volume", s.initial_rv_volume, "mm^3", "initial RV volume (elastance mode)", Range::non_negative());
  p.add("circulation_initial_systemic_arterial_pressure", s.initial_systemic_arterial_pressure, "kPa",
        "initial p_AR_SYS (closed loop) or p_C of the LV Windkessel");
  p.add("circulation_initial_systemic_venous_pressure", s.initial_systemic_venous_pressure, "kPa", "initial p_VEN_SYS");
  p.add("circulation_initial_pulmonary_arterial_pressure", s.initial_pulmonary_arterial_pressure, "kPa",
        "initial p_AR_PUL (closed loop) or p_C of the RV Windkessel");
  p.add("circulation_initial_pulmonary_venous_pressure", s.initial_pulmonary_venous_pressure, "kPa", "initial p_VEN_PUL");
}

// ---------------------------------------------------------------------------------------------

Circulation::Circulation(const CirculationSettings& settings) : settings_(settings) {
  settings_.check();
  if (settings_.model == CirculationModel::closed_loop) build_closed_loop();
  else build_windkessel();
  initialised_ = settings_.lv_mode == VentricleMode::elastance && settings_.rv_mode == VentricleMode::elastance;
  time_ = 0;
  update_coefficients(time_);
  for (int l = 0; l < n_links_; ++l)  // valve states from the initial pressures
    if (links_[l].valve) open_[l] = endpoint_pressure(links_[l].up, state_.data()) > endpoint_pressure(links_[l].down, state_.data());
  update_outputs();
}

int Circulation::add_node(Node node, double state) {
  nodes_[n_nodes_] = std::move(node);
  state_[n_nodes_] = state;
  return n_nodes_++;
}

int Circulation::add_link(Link link) {
  if (link.inductance > 0) link.inductor = n_inductors_++;
  links_[n_links_] = std::move(link);
  return n_links_++;
}

Circulation::Node Circulation::chamber_node(const std::string& name, const std::string& description,
                                            const ElastanceChamberSettings& chamber) {
  Node n{NodeKind::chamber, name, description};
  n.chamber = chamber;
  return n;
}

Circulation::Node Circulation::vessel_node(const std::string& name, const std::string& description, double compliance) {
  Node n{NodeKind::vessel, name, description};
  n.compliance = compliance;
  return n;
}

Circulation::Node Circulation::ventricle_node(const std::string& name, const std::string& description,
                                              const ElastanceChamberSettings& chamber, VentricleMode mode, int ventricle) {
  Node n = chamber_node(name, description, chamber);
  if (mode == VentricleMode::coupled) n.kind = NodeKind::coupled_ventricle;
  n.ventricle = ventricle;
  return n;
}

void Circulation::build_closed_loop() {
  const auto& s = settings_;
  const int la = add_node(chamber_node("la", "left atrium", s.la), s.initial_la_volume);
  const int lv = add_node(ventricle_node("lv", "left ventricle", s.lv, s.lv_mode, 0), s.initial_lv_volume);
  const int ra = add_node(chamber_node("ra", "right atrium", s.ra), s.initial_ra_volume);
  const int rv = add_node(ventricle_node("rv", "right ventricle", s.rv, s.rv_mode, 1), s.initial_rv_volume);
  // Vessel compartments hold their volume C p.
  const int ar_sys = add_node(vessel_node("ar_sys", "systemic arterial compartment", s.systemic_arterial.compliance),
                              s.systemic_arterial.compliance * s.initial_systemic_arterial_pressure);
  const int ven_sys = add_node(vessel_node("ven_sys", "systemic venous compartment", s.systemic_venous.compliance),
                               s.systemic_venous.compliance * s.initial_systemic_venous_pressure);
  const int ar_pul = add_node(vessel_node("ar_pul", "pulmonary arterial compartment", s.pulmonary_arterial.compliance),
                              s.pulmonary_arterial.compliance * s.initial_pulmonary_arterial_pressure);
  const int ven_pul = add_node(vessel_node("ven_pul", "pulmonary venous compartment", s.pulmonary_venous.compliance),
                               s.pulmonary_venous.compliance * s.initial_pulmonary_venous_pressure);
  ventricle_node_ = {lv, rv};
  arterial_node_ = {ar_sys, ar_pul};

  auto valve = [&s](const std::string& name, int up, int down, double open) {
    Link l;
    l.name = name;
    l.up = up;
    l.down = down;
    l.open_resistance = open;
    l.closed_resistance = s.valve_closed_resistance;
    l.valve = true;
    return l;
  };
  auto vessel_flow = [](const std::string& name, int up, int down, const VesselSettings& v) {
    Link l;
    l.name = name;
    l.up = up;
    l.down = down;
    l.open_resistance = l.closed_resistance = v.resistance;
    l.inductance = v.inductance;
    return l;
  };
  valve_link_ = {add_link(valve("mv", la, lv, s.mitral_resistance)), add_link(valve("av", lv, ar_sys, s.aortic_resistance)),
                 add_link(valve("tv", ra, rv, s.tricuspid_resistance)),
                 add_link(valve("pv", rv, ar_pul, s.pulmonary_valve_resistance))};
  add_link(vessel_flow("ar_sys", ar_sys, ven_sys, s.systemic_arterial));   // Q_AR_SYS
  add_link(vessel_flow("ven_sys", ven_sys, ra, s.systemic_venous));        // Q_VEN_SYS
  add_link(vessel_flow("ar_pul", ar_pul, ven_pul, s.pulmonary_arterial));  // Q_AR_PUL
  add_link(vessel_flow("ven_pul", ven_pul, la, s.pulmonary_venous));       // Q_VEN_PUL
  // The vessel flows start at zero (state_ is zero-initialised).
  for (int v = 0; v < 2; ++v) volume_3d_[v] = state_[ventricle_node_[v]];
}

void Circulation::build_windkessel() {
  const auto& s = settings_;
  const int lv = add_node(ventricle_node("lv", "left ventricle", s.lv, s.lv_mode, 0), s.initial_lv_volume);
  const int rv = add_node(ventricle_node("rv", "right ventricle", s.rv, s.rv_mode, 1), s.initial_rv_volume);
  const int c_sys = add_node(vessel_node("c_sys", "systemic Windkessel compliance", s.lv_windkessel.compliance),
                             s.lv_windkessel.compliance * s.initial_systemic_arterial_pressure);
  const int c_pul = add_node(vessel_node("c_pul", "pulmonary Windkessel compliance", s.rv_windkessel.compliance),
                             s.rv_windkessel.compliance * s.initial_pulmonary_arterial_pressure);
  ventricle_node_ = {lv, rv};
  arterial_node_ = {c_sys, c_pul};
  // Sources (fixed pressures), endpoint -1 - k.
  sources_ = {s.lv_windkessel.filling_pressure, s.lv_windkessel.distal_pressure, s.rv_windkessel.filling_pressure,
              s.rv_windkessel.distal_pressure};
  auto link = [](const std::string& name, int up, int down, double open, double closed, bool is_valve) {
    Link l;
    l.name = name;
    l.up = up;
    l.down = down;
    l.open_resistance = open;
    l.closed_resistance = closed;
    l.valve = is_valve;
    return l;
  };
  const double R_closed = s.valve_closed_resistance, Z_sys = s.lv_windkessel.characteristic_impedance,
               Z_pul = s.rv_windkessel.characteristic_impedance;
  valve_link_ = {add_link(link("mv", -1, lv, s.mitral_resistance, R_closed, true)),
                 // The outflow valve in series with Z: one link of resistance R_valve + Z.
                 add_link(link("av", lv, c_sys, s.aortic_resistance + Z_sys, R_closed + Z_sys, true)),
                 add_link(link("tv", -3, rv, s.tricuspid_resistance, R_closed, true)),
                 add_link(link("pv", rv, c_pul, s.pulmonary_valve_resistance + Z_pul, R_closed + Z_pul, true))};
  add_link(link("per_sys", c_sys, -2, s.lv_windkessel.resistance, s.lv_windkessel.resistance, false));
  add_link(link("per_pul", c_pul, -4, s.rv_windkessel.resistance, s.rv_windkessel.resistance, false));
  for (int v = 0; v < 2; ++v) volume_3d_[v] = state_[ventricle_node_[v]];
}

void Circulation::update_coefficients(double t) {
  for (int i = 0; i < n_nodes_; ++i) {
    const Node& n = nodes_[i];
    switch (n.kind) {
      case NodeKind::chamber: {  // p = E(t) (V - V0)
        const double E = n.chamber.elastance(t, settings_.heart_period);
        a_[i] = E;
        b_[i] = -E * n.chamber.rest_volume;
        break;
      }
      case NodeKind::coupled_ventricle:  // p = p_ref + (V_b - V_3D(t)) / C_c
        a_[i] = 1 / settings_.cavity_compliance;
        b_[i] = reference_pressure_[n.ventricle] - volume_3d_[n.ventricle] / settings_.cavity_compliance;
        break;
      case NodeKind::vessel:  // p = (C p) / C
        a_[i] = 1 / n.compliance;
        b_[i] = 0;
        break;
    }
  }
}

double Circulation::endpoint_pressure(int endpoint, const double* state) const {
  return endpoint >= 0 ? a_[endpoint] * state[endpoint] + b_[endpoint] : sources_[-1 - endpoint];
}

void Circulation::update_outputs() {
  for (int i = 0; i < n_nodes_; ++i) pressure_[i] = a_[i] * state_[i] + b_[i];
  for (int l = 0; l < n_links_; ++l) {
    const Link& k = links_[l];
    if (k.inductor >= 0) flow_[l] = state_[n_nodes_ + k.inductor];
    else
      flow_[l] = (endpoint_pressure(k.up, state_.data()) - endpoint_pressure(k.down, state_.data())) /
                 (open_[l] ? k.open_resistance : k.closed_resistance);
  }
}

void Circulation::step(double h, double t_new) {
  using Matrix = Eigen::Matrix<double, max_states, max_states>;
  using Vector = Eigen::Matrix<double, max_states, 1>;
  update_coefficients(t_new);
  std::array<bool, max_links> s = open_;
  Vector y = Vector::Zero();
  bool settled = false;
  for (int iteration = 0; iteration < settings_.max_valve_iterations; ++iteration) {
    // Backward Euler for fixed valve states s:
    //   node i:      y_i - h (sum_in Q - sum_out Q)(y) = y_i^n,
    //   resistive:   Q = (p_up - p_down) / R(s),  p = a y + b  (or a fixed source pressure),
    //   inductive m: y_m - (h/L) (p_up - p_down - R y_m) = y_m^n.
    // Unused rows stay identity with zero right-hand side.
    Matrix M = Matrix::Identity();
    Vector rhs = Vector::Zero();
    for (int i = 0; i < n_nodes_ + n_inductors_; ++i) rhs[i] = state_[i];
    for (int l = 0; l < n_links_; ++l) {
      const Link& k = links_[l];
      const int u = k.up, d = k.down;
      const double a_u = u >= 0 ? a_[u] : 0, b_u = u >= 0 ? b_[u] : sources_[-1 - u];
      const double a_d = d >= 0 ? a_[d] : 0, b_d = d >= 0 ? b_[d] : sources_[-1 - d];
      if (k.inductor >= 0) {
        const int m = n_nodes_ + k.inductor;
        const double c = h / k.inductance;
        if (u >= 0) M(u, m) += h;  // Q leaves up
        if (d >= 0) M(d, m) -= h;  // Q enters down
        M(m, m) += c * k.open_resistance;
        if (u >= 0) M(m, u) -= c * a_u;
        if (d >= 0) M(m, d) += c * a_d;
        rhs[m] += c * (b_u - b_d);
      } else {
        const double g = h / (s[l] ? k.open_resistance : k.closed_resistance);
        if (u >= 0) {
          M(u, u) += g * a_u;
          if (d >= 0) M(u, d) -= g * a_d;
          rhs[u] -= g * (b_u - b_d);
        }
        if (d >= 0) {
          M(d, d) += g * a_d;
          if (u >= 0) M(d, u) -= g * a_u;
          rhs[d] += g * (b_u - b_d);
        }
      }
    }
    y = M.partialPivLu().solve(rhs);
    // Valve states from the new pressures.
    bool changed = false;
    std::array<bool, max_links> next = s;
    for (int l = 0; l < n_links_; ++l)
      if (links_[l].valve) {
        next[l] = endpoint_pressure(links_[l].up, y.data()) > endpoint_pressure(links_[l].down, y.data());
        changed = changed || next[l] != s[l];
      }
    if (!changed) {
      settled = true;
      break;
    }
    if (iteration + 1 < settings_.max_valve_iterations) s = next;  // else keep the states of y
  }
  if (!settled) ++unsettled_steps_;

  // Conservative update with the flows of the solution: each flow leaves one compartment and
  // enters another, so sum_i y_i changes only by round-off (and by the sources of the Windkessel).
  std::array<double, max_states> next_state = state_;
  for (int l = 0; l < n_links_; ++l) {
    const Link& k = links_[l];
    const double Q = k.inductor >= 0 ? y[n_nodes_ + k.inductor]
                                     : (endpoint_pressure(k.up, y.data()) - endpoint_pressure(k.down, y.data())) /
                                           (s[l] ? k.open_resistance : k.closed_resistance);
    if (k.up >= 0) next_state[k.up] -= h * Q;
    if (k.down >= 0) next_state[k.down] += h * Q;
    if (k.inductor >= 0) next_state[n_nodes_ + k.inductor] = Q;
  }
  state_ = next_state;
  open_ = s;
  update_outputs();
  check_finite(t_new);
}

void Circulation::check_finite(double t) const {
  for (int i = 0; i < n_nodes_; ++i)
    if (!std::isfinite(state_[i]) || !std::isfinite(pressure_[i]))
      throw std::runtime_error("circulation: the " + nodes_[i].description + " (" + nodes_[i].name +
                               ") is not finite at t = " + number(t) + " ms: volume " + number(state_[i]) +
                               " mm^3, pressure " + number(pressure_[i]) + " kPa");
  for (int l = 0; l < n_links_; ++l)
    if (!std::isfinite(flow_[l]))
      throw std::runtime_error("circulation: the flow q_" + links_[l].name + " is not finite at t = " + number(t) + " ms");
}

void Circulation::initialise(double t0, double lv_volume_3d, double rv_volume_3d, double lv_pressure, double rv_pressure) {
  const double volume[2] = {lv_volume_3d, rv_volume_3d}, pressure[2] = {lv_pressure, rv_pressure};
  const char* names[2] = {"left", "right"};
  if (!std::isfinite(t0)) throw std::invalid_argument("circulation: initialise at a non-finite time");
  for (int v = 0; v < 2; ++v) {
    const int i = ventricle_node_[v];
    if (nodes_[i].kind != NodeKind::coupled_ventricle) continue;
    if (!(volume[v] > 0) || !std::isfinite(volume[v]) || !std::isfinite(pressure[v]))
      throw std::invalid_argument(std::string("circulation: initialise the coupled ") + names[v] +
                                  " ventricle with a positive 3D volume and a finite pressure, got " + number(volume[v]) +
                                  " mm^3 and " + number(pressure[v]) + " kPa");
    volume_3d_[v] = volume[v];
    state_[i] = volume[v];  // V_b = V_3D, so p = p_ref
    reference_pressure_[v] = pressure[v];
  }
  time_ = t0;
  initialised_ = true;
  update_coefficients(time_);
  for (int l = 0; l < n_links_; ++l)
    if (links_[l].valve) open_[l] = endpoint_pressure(links_[l].up, state_.data()) > endpoint_pressure(links_[l].down, state_.data());
  update_outputs();
}

void Circulation::advance(double t, double dt) {
  advance(t, dt, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN());
}

void Circulation::advance(double t, double dt, double lv_volume_3d_end, double rv_volume_3d_end) {
  if (!initialised_) throw std::logic_error("circulation: a coupled ventricle needs initialise() before advance()");
  if (!(dt > 0) || !std::isfinite(dt)) throw std::invalid_argument("circulation: the step dt must be positive, got " + number(dt));
  if (!(std::abs(t - time_) <= 1e-6 * std::max(1.0, std::abs(time_))))
    throw std::invalid_argument("circulation: advance from t = " + number(t) + " ms but the circulation is at " +
                                number(time_) + " ms");
  const double end[2] = {lv_volume_3d_end, rv_volume_3d_end};
  const char* names[2] = {"left", "right"};
  for (int v = 0; v < 2; ++v)
    if (nodes_[ventricle_node_[v]].kind == NodeKind::coupled_ventricle && !std::isfinite(end[v]))
      throw std::invalid_argument(std::string("circulation: the 3D volume of the coupled ") + names[v] +
                                  " ventricle must be finite, got " + number(end[v]));
  const double start[2] = {volume_3d_[0], volume_3d_[1]};
  const long n_sub = std::max(1L, static_cast<long>(std::ceil(dt / settings_.max_step * (1 - 1e-12))));
  const double h = dt / static_cast<double>(n_sub);
  for (long k = 1; k <= n_sub; ++k) {
    const double fraction = static_cast<double>(k) / static_cast<double>(n_sub);
    for (int v = 0; v < 2; ++v)
      if (nodes_[ventricle_node_[v]].kind == NodeKind::coupled_ventricle)
        volume_3d_[v] = k == n_sub ? end[v] : start[v] + (end[v] - start[v]) * fraction;  // V_3D linear in time
    step(h, k == n_sub ? t + dt : t + dt * fraction);
  }
  time_ = t + dt;
}

double Circulation::ventricle_3d_volume(Ventricle v) const {
  const int i = ventricle_node_[index(v)];
  return nodes_[i].kind == NodeKind::coupled_ventricle ? volume_3d_[index(v)] : state_[i];
}

double Circulation::arterial_pressure(Ventricle v) const {
  const int c = arterial_node_[index(v)];
  if (settings_.model == CirculationModel::closed_loop) return pressure_[c];
  // Windkessel: p_art = p_C + Z Q_out.
  const auto& w = v == Ventricle::left ? settings_.lv_windkessel : settings_.rv_windkessel;
  return pressure_[c] + w.characteristic_impedance * valve_flow(v == Ventricle::left ? Valve::aortic : Valve::pulmonary);
}

double Circulation::total_blood_volume() const {
  double total = 0;
  for (int i = 0; i < n_nodes_; ++i) total += state_[i];
  return total;
}

std::vector<std::string> Circulation::columns() const {
  std::vector<std::string> c{"time"};
  for (int i = 0; i < n_nodes_; ++i) {
    c.push_back("p_" + nodes_[i].name);
    c.push_back("v_" + nodes_[i].name);
    if (nodes_[i].kind == NodeKind::coupled_ventricle) c.push_back("v3d_" + nodes_[i].name);
  }
  for (int l = 0; l < n_links_; ++l) c.push_back("q_" + links_[l].name);
  for (int v = 0; v < 4; ++v) c.push_back("valve_" + links_[valve_link_[v]].name + "_open");
  if (settings_.model == CirculationModel::windkessel) {
    c.emplace_back("p_ao");
    c.emplace_back("p_pa");
  }
  c.emplace_back("v_total");
  return c;
}

std::vector<double> Circulation::row() const {
  std::vector<double> r{time_};
  for (int i = 0; i < n_nodes_; ++i) {
    r.push_back(pressure_[i]);
    r.push_back(state_[i]);
    if (nodes_[i].kind == NodeKind::coupled_ventricle) r.push_back(volume_3d_[nodes_[i].ventricle]);
  }
  for (int l = 0; l < n_links_; ++l) r.push_back(flow_[l]);
  for (int v = 0; v < 4; ++v) r.push_back(open_[valve_link_[v]] ? 1 : 0);
  if (settings_.model == CirculationModel::windkessel) {
    r.push_back(arterial_pressure(Ventricle::left));
    r.push_back(arterial_pressure(Ventricle::right));
  }
  r.push_back(total_blood_volume());
  return r;
}

}  // namespace cardio
