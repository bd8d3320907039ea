#include "core/scenes/servo_actuator.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/scenes/drivers.hpp"
#include "core/scenes/parts.hpp"
#include "core/scenes/rod_end_mechanism.hpp"

namespace rodend {
namespace {

/// Smooth opening of a metering edge: x for x >> e, e/2 at x = 0, -> 0 for x << -e.
template <class S>
S opening(const S& x, double e) {
  using std::sqrt;
  return 0.5 * (x + sqrt(x * x + e * e));
}

}  // namespace

ServoActuatorParams read_servo_actuator(const ParameterSet& p, const std::string& pre) {
  ServoActuatorParams a;
  auto pos = [&](const char* k, bool zero_ok = false) {
    return read_positive(p, pre + "." + k, zero_ok);
  };
  a.kp = pos("proportional_gain", true);
  a.ki = pos("integral_gain", true);
  a.current_limit = pos("current_limit");
  a.lvdt_time_constant = pos("lvdt_time_constant");
  a.torque_motor = read_choice<TorqueMotor>(p, pre + ".torque_motor");
  a.motor_gain = pos("motor_gain");
  a.jet_mass = pos("jet_mass");
  a.jet_stiffness = pos("jet_stiffness", true);
  a.jet_damping = pos("jet_damping", true);
  a.wire_stiffness = pos("wire_stiffness");
  a.jet_pressure_gain = pos("jet_pressure_gain");
  a.spool_mass = pos("spool_mass");
  a.spool_area = pos("spool_area");
  a.spool_damping = pos("spool_damping", true);
  a.port_width = pos("port_width");
  a.leak_opening = pos("leak_opening");
  a.discharge_coefficient = pos("discharge_coefficient");
  a.jet_angle = p.number(pre + ".jet_angle");
  a.transition_pressure = pos("transition_pressure");
  a.supply_pressure = p.number(pre + ".supply_pressure");
  a.return_pressure = p.number(pre + ".return_pressure");
  if (!(a.supply_pressure > a.return_pressure))
    throw InputError(pre + ".supply_pressure",
                     "expected a supply pressure > the return pressure (" +
                         format_number(a.return_pressure) + " Pa), got " +
                         format_number(a.supply_pressure) + " Pa");
  if (!(a.return_pressure >= 0.0))
    throw InputError(pre + ".return_pressure", "expected an absolute pressure >= 0 [Pa]");
  a.density = pos("density");
  a.bulk_modulus = pos("bulk_modulus");
  a.piston_area = pos("piston_area");
  a.half_stroke = pos("half_stroke");
  a.dead_volume = pos("dead_volume");
  a.internal_leakage = pos("internal_leakage", true);
  a.external_leakage = pos("external_leakage", true);
  a.piston_mass = pos("piston_mass");
  a.piston_friction = pos("piston_friction", true);
  a.stop_stiffness = pos("stop_stiffness");
  a.stop_damping = pos("stop_damping", true);
  return a;
}

void check_command_within_stroke(const Input& m, const ServoActuatorParams& a,
                                 const std::string& prefix) {
  // the range with the start, 0
  const double lo = std::min(0.0, m.range().first), hi = std::max(0.0, m.range().second);
  const auto [lo_key, hi_key] = m.range_keys();
  if (hi >= a.half_stroke)
    throw InputError(prefix + "." + std::string(hi_key), "the command " + format_number(hi) +
                                                             " m is outside the piston stroke +-" +
                                                             format_number(a.half_stroke) + " m");
  if (-lo >= a.half_stroke)
    throw InputError(prefix + "." + std::string(lo_key), "the command " + format_number(lo) +
                                                             " m is outside the piston stroke +-" +
                                                             format_number(a.half_stroke) + " m");
}

template <class S>
S ServoActuator::motor_force(const S& current) const {
  using std::abs;
  if (p_.torque_motor == TorqueMotor::solenoid) {  // eq. 6.1: B^2 S / (2 mu), B ~ i
    const S u = current / p_.current_limit;
    return p_.motor_gain * p_.current_limit * u * abs(u);
  }
  return p_.motor_gain * current;
}

template <class S>
S ServoActuator::orifice_flow(const S& area, const S& dp) const {
  using std::pow, std::sqrt;
  // turbulent orifice Q = C_d A sqrt(2 |dp| / rho) sign(dp) (thesis 6.6), regularised with a
  // laminar region below the transition pressure so the slope at dp = 0 stays finite
  // (model-notes §6): Q = C_d A sqrt(2/rho) dp / (dp^2 + p_t^2)^(1/4)
  const double pt = p_.transition_pressure;
  return p_.discharge_coefficient * area * std::sqrt(2.0 / p_.density) * dp /
         pow(dp * dp + pt * pt, 0.25);
}

template <class S>
ServoActuator::EvalT<S> ServoActuator::evaluate(double command, const S* x) const {
  using std::abs, std::tanh;
  EvalT<S> e;
  const S P1 = x[kP1], P2 = x[kP2], xs = x[kSpool], pos = x[kPos];
  const double Ps = p_.supply_pressure, Pr = p_.return_pressure;

  // PI controller on the LVDT reading, smoothly saturated at the rated current
  e.command = command;
  e.error = command - x[kLvdt];
  const S raw = p_.kp * e.error + p_.ki * x[kIntegral];
  e.current = p_.current_limit * tanh(raw / p_.current_limit);

  // four-way spool: x_s > 0 connects supply -> 1 and 2 -> tank (thesis 6.4-6.6, fig. 6.4)
  const S a_pos = p_.port_width * opening(xs, p_.leak_opening);
  const S a_neg = p_.port_width * opening(S(-xs), p_.leak_opening);
  e.supply_flow_1 = orifice_flow(a_pos, S(Ps - P1));
  e.tank_flow_2 = orifice_flow(a_pos, S(P2 - Pr));
  e.supply_flow_2 = orifice_flow(a_neg, S(Ps - P2));
  e.tank_flow_1 = orifice_flow(a_neg, S(P1 - Pr));
  e.q1 = e.supply_flow_1 - e.tank_flow_1;  // eq. 6.4
  e.q2 = e.tank_flow_2 - e.supply_flow_2;  // eq. 6.5 (front chamber; the text prints Q_1)
  e.internal_leak = p_.internal_leakage * (P1 - P2);
  e.external_leak_1 = p_.external_leakage * (P1 - Pr);
  e.external_leak_2 = p_.external_leakage * (P2 - Pr);

  // steady-state flow forces: each open edge pushes the spool closed (the F_fl of eq. 6.3)
  const double k = 2.0 * p_.discharge_coefficient * std::cos(p_.jet_angle);
  e.flow_force =
      -k * (a_pos * (abs(Ps - P1) + abs(P2 - Pr)) - a_neg * (abs(Ps - P2) + abs(P1 - Pr)));

  // chamber volumes (eq. 6.8-6.9), measured from the end-of-stroke dead volumes
  const double vmin = 1e-3 * p_.dead_volume;
  e.v1 = max_of(p_.dead_volume + p_.piston_area * (p_.half_stroke + pos), vmin);
  e.v2 = max_of(p_.dead_volume + p_.piston_area * (p_.half_stroke - pos), vmin);

  // end stops: stiff, damped, never pulling
  const S v = x[kVel];
  const S over = pos - p_.half_stroke, under = -p_.half_stroke - pos;
  if (over > 0.0) e.stop_force = -max_of(0.0, S(p_.stop_stiffness * over + p_.stop_damping * v));
  if (under > 0.0) e.stop_force = max_of(0.0, S(p_.stop_stiffness * under - p_.stop_damping * v));
  return e;
}

template <class S>
void ServoActuator::derivatives(const EvalT<S>& e, const S* x, const S& external_force,
                                double load_mass, S* dxdt) const {
  using std::tanh;
  const S xj = x[kJet], vj = x[kJetRate], xs = x[kSpool], vs = x[kSpoolRate];
  const S v = x[kVel];
  const double dP_range = p_.supply_pressure - p_.return_pressure;
  dxdt[kLvdt] = (x[kPos] - x[kLvdt]) / p_.lvdt_time_constant;
  dxdt[kIntegral] = e.error;
  // torque motor and jet pipe (eq. 6.2): motor force, centring spring, damping, feedback wire
  dxdt[kJet] = vj;
  dxdt[kJetRate] = (motor_force(e.current) - p_.jet_stiffness * xj - p_.jet_damping * vj -
                    p_.wire_stiffness * (xj + xs)) /
                   p_.jet_mass;
  // spool (eq. 6.3): jet-pipe pressure difference on its ends (limited to the available
  // pressure), feedback wire, flow forces, viscous friction
  const S dps = dP_range * tanh(p_.jet_pressure_gain * xj / dP_range);
  dxdt[kSpool] = vs;
  dxdt[kSpoolRate] =
      (p_.spool_area * dps - p_.wire_stiffness * (xs + xj) + e.flow_force - p_.spool_damping * vs) /
      p_.spool_mass;
  // chambers (eq. 6.11-6.12 with the leakages)
  const double A = p_.piston_area, beta = p_.bulk_modulus;
  dxdt[kP1] = beta / e.v1 * (e.q1 - A * v - e.internal_leak - e.external_leak_1);
  dxdt[kP2] = beta / e.v2 * (-e.q2 + A * v + e.internal_leak - e.external_leak_2);
  // piston (eq. 6.13)
  dxdt[kPos] = v;
  dxdt[kVel] = ((x[kP1] - x[kP2]) * A - p_.piston_friction * v + external_force + e.stop_force) /
               (p_.piston_mass + load_mass);
}

void ServoActuator::initial_state(double* x, double position) const {
  for (int i = 0; i < size; ++i) x[i] = 0.0;
  x[kLvdt] = position;
  x[kPos] = position;
  // a centred valve holds both chambers at the mean of supply and return
  x[kP1] = x[kP2] = 0.5 * (p_.supply_pressure + p_.return_pressure);
}

void ServoActuator::state_scale(double* s) const {
  s[kLvdt] = 1e-4;      // piston positions to a fraction of the rod-end clearance
  s[kIntegral] = 1e-5;  // [m s]
  s[kJet] = 1e-6;       // jet deflections are micrometres
  s[kJetRate] = 1e-3;
  s[kSpool] = 1e-5;  // spool strokes are tenths of a millimetre
  s[kSpoolRate] = 1e-2;
  s[kP1] = s[kP2] = 1e5;  // pressures to 0.1 bar
  s[kPos] = 1e-4;
  s[kVel] = 1e-2;
}

template <class S>
S ServoActuator::hydraulic_net_power(const EvalT<S>& e) const {
  return p_.supply_pressure * (e.supply_flow_1 + e.supply_flow_2) -
         p_.return_pressure *
             (e.tank_flow_1 + e.tank_flow_2 + e.external_leak_1 + e.external_leak_2);
}

template <class S>
S ServoActuator::orifice_loss(const EvalT<S>& e, const S* x) const {
  const S P1 = x[kP1], P2 = x[kP2];
  const double Ps = p_.supply_pressure, Pr = p_.return_pressure;
  return e.supply_flow_1 * (Ps - P1) + e.tank_flow_1 * (P1 - Pr) + e.supply_flow_2 * (Ps - P2) +
         e.tank_flow_2 * (P2 - Pr);
}

template <class S>
S ServoActuator::leak_loss(const EvalT<S>& e, const S* x) const {
  const double Pr = p_.return_pressure;
  return e.internal_leak * (x[kP1] - x[kP2]) + e.external_leak_1 * (x[kP1] - Pr) +
         e.external_leak_2 * (x[kP2] - Pr);
}

template <class S>
S ServoActuator::compression_power(const EvalT<S>& e, const S* x, const S* dxdt) const {
  return (e.v1 * x[kP1] * dxdt[kP1] + e.v2 * x[kP2] * dxdt[kP2]) / p_.bulk_modulus;
}

double ServoActuator::mechanical_energy(const double* x, double load_mass) const {
  const double over = std::max(x[kPos] - p_.half_stroke, 0.0);
  const double under = std::max(-p_.half_stroke - x[kPos], 0.0);
  return 0.5 * (p_.piston_mass + load_mass) * x[kVel] * x[kVel] +
         0.5 * p_.stop_stiffness * (over * over + under * under);
}

template <class S>
S ServoActuator::dissipated_power(const EvalT<S>& e, const S* x) const {
  const S v = x[kVel];
  const S over = max_of(x[kPos] - p_.half_stroke, 0.0);
  const S under = max_of(-p_.half_stroke - x[kPos], 0.0);
  // stop dissipation: -F v - dU/dt with U = k (over^2 + under^2) / 2
  const S stop = -e.stop_force * v - p_.stop_stiffness * (over - under) * v;
  return p_.piston_friction * v * v + stop;
}

void ServoActuator::outputs(const Eval& e, const double* x, double external_force,
                            SignalFrame& f) const {
  f.set(SignalId::actuator_command, e.command);
  f.set(SignalId::lvdt_position, x[kLvdt]);
  f.set(SignalId::controller_current, e.current);
  f.set(SignalId::jet_pipe_position, x[kJet]);
  f.set(SignalId::spool_position, x[kSpool]);
  f.set(SignalId::chamber_pressures, x[kP1], x[kP2]);
  // each positive into its chamber (thesis fig. 6.20-6.21): q2 of eq. 6.5 counts the flow out
  f.set(SignalId::chamber_flows, e.q1, -e.q2);
  f.set(SignalId::actuator_external_force, external_force);
  f.set(SignalId::hydraulic_power, hydraulic_net_power(e));
  f.set(SignalId::actuator_position, x[kPos]);
  f.set(SignalId::actuator_velocity, x[kVel]);
}

#define RODEND_SERVO_SCALAR(S)                                                                     \
  template S ServoActuator::motor_force(const S&) const;                                           \
  template ServoActuator::EvalT<S> ServoActuator::evaluate(double, const S*) const;                \
  template void ServoActuator::derivatives(const EvalT<S>&, const S*, const S&, double, S*) const; \
  template S ServoActuator::hydraulic_net_power(const EvalT<S>&) const;                            \
  template S ServoActuator::orifice_loss(const EvalT<S>&, const S*) const;                         \
  template S ServoActuator::leak_loss(const EvalT<S>&, const S*) const;                            \
  template S ServoActuator::compression_power(const EvalT<S>&, const S*, const S*) const;          \
  template S ServoActuator::dissipated_power(const EvalT<S>&, const S*) const;
RODEND_SERVO_SCALAR(double)
RODEND_SERVO_SCALAR(RodEndMechanism::ActuatorDual)
#undef RODEND_SERVO_SCALAR

}  // namespace rodend
