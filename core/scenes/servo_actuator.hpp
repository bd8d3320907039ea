// Electro-hydraulic position actuator with a jet-pipe servovalve (thesis §6; model-notes §6):
// PI controller on the LVDT signal -> torque-motor current -> jet-pipe (armature) -> spool with
// the feedback wire and flow forces -> four-way spool orifices -> two chambers with bulk
// modulus, variable volumes, internal and external leakage -> piston with viscous friction and
// end stops.
//
// States (10, from the part's offset):
//   lvdt [m] | integral of the position error [m s] | x_j [m] | x_j' [m/s] | x_s [m] | x_s' [m/s]
//   | P1 [Pa] | P2 [Pa] | x [m] | x' [m/s]
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "core/choice.hpp"
#include "core/params.hpp"
#include "core/signals.hpp"

namespace rodend {

/// Force law of the torque motor (thesis eq. 6.1), the menu core/scenes/torque_motors.def:
///   linear:   F = motor_gain i (the push-pull motor with a polarising flux: (I0 + i)^2 -
///             (I0 - i)^2 = 4 I0 i, exactly linear in the current at a fixed air gap);
///   solenoid: eq. 6.1 as the thesis writes it, F = B^2 S / (2 mu) with B proportional to the
///             current of the one solenoid energised (no bias): F = motor_gain I_r (i/I_r)|i/I_r|,
///             I_r = current_limit, so both laws give the same force at the rated current.
#define RODEND_CHOICE_ENUM TorqueMotor
#define RODEND_CHOICE_FILE "core/scenes/torque_motors.def"
#include "core/choice.hpp"

struct ServoActuatorParams {
  // controller and sensor
  double kp = 2.0;                   ///< proportional gain [A/m] (thesis §6.2)
  double ki = 0.02;                  ///< integral gain [A/(m s)] (thesis §6.2)
  double current_limit = 0.01;       ///< rated current, smooth saturation [A]
  double lvdt_time_constant = 1e-3;  ///< [s]
  // torque motor and jet pipe (6.1-6.2), referred to the nozzle
  TorqueMotor torque_motor = TorqueMotor::linear;  ///< force law (eq. 6.1)
  double motor_gain = 12.5;                        ///< force per current at the nozzle [N/A]
  double jet_mass = 5e-4;                          ///< [kg]
  double jet_stiffness = 2000;                     ///< armature centring stiffness [N/m]
  double jet_damping = 2.0;                        ///< [N s/m]
  double wire_stiffness = 500;                     ///< feedback-wire stiffness [N/m]
  double jet_pressure_gain = 4e10;  ///< spool-end pressure difference per jet deflection [Pa/m]
  // spool (6.3)
  double spool_mass = 0.02;    ///< [kg]
  double spool_area = 3e-5;    ///< spool end area [m^2]
  double spool_damping = 100;  ///< viscous friction of the spool [N s/m]
  double port_width = 8.6e-3;  ///< area gradient of each metering edge [m]
  double leak_opening = 1e-6;  ///< radial-clearance equivalent opening of a closed edge [m]
  double discharge_coefficient = 0.61;  ///< C_d [-]
  double jet_angle = 1.2043;            ///< flow-force jet angle, 69 deg [rad]
  double transition_pressure = 1e5;     ///< laminar-turbulent regularisation of eq. 6.6 [Pa]
  // fluid and supply
  double supply_pressure = 21e6;   ///< P_s [Pa]
  double return_pressure = 0.3e6;  ///< P_r [Pa]
  double density = 850;            ///< [kg/m^3]
  double bulk_modulus = 1.2e9;     ///< effective, with hoses [Pa]
  // cylinder and piston (6.7-6.13)
  double piston_area = 5e-4;        ///< A_c, both sides [m^2]
  double half_stroke = 0.065;       ///< end stops at +-half_stroke [m]
  double dead_volume = 2e-5;        ///< each chamber's volume at its end of stroke [m^3]
  double internal_leakage = 2e-13;  ///< across the piston seal [m^3/(s Pa)]
  double external_leakage = 1e-14;  ///< from each chamber to return [m^3/(s Pa)]
  double piston_mass = 1.5;         ///< piston and rod [kg]
  double piston_friction = 1000;    ///< viscous friction gamma [N s/m]
  double stop_stiffness = 1e8;      ///< end-stop contact stiffness [N/m]
  double stop_damping = 1e4;        ///< end-stop damping [N s/m]
};

/// Reads `<prefix>.*`; throws InputError for supply <= return pressure, dead volume <= 0, bulk
/// modulus <= 0 and other non-physical values.
ServoActuatorParams read_servo_actuator(const ParameterSet& p, const std::string& prefix);

class Input;
/// Rejects a command that leaves the piston stroke, naming the key under `prefix` of the
/// offending extreme (Input::range_keys: extension, retraction, a waveform's amplitude, a
/// profile's file).
void check_command_within_stroke(const Input& m, const ServoActuatorParams& a,
                                 const std::string& prefix);

class ServoActuator {
 public:
  static constexpr int kLvdt = 0, kIntegral = 1, kJet = 2, kJetRate = 3, kSpool = 4, kSpoolRate = 5,
                       kP1 = 6, kP2 = 7, kPos = 8, kVel = 9;
  static constexpr int size = 10;

  explicit ServoActuator(const ServoActuatorParams& p) : p_(p) {}
  const ServoActuatorParams& params() const { return p_; }

  /// Everything computed at one instant. On a scalar S (double, or a dual number of
  /// core/dual.hpp for the exact Jacobians: the templates below are instantiated for double and
  /// RodEndMechanism::ActuatorDual, servo_actuator.cpp).
  template <class S>
  struct EvalT {
    double command = 0.0;
    S error = 0.0, current = 0.0;
    S supply_flow_1 = 0.0, tank_flow_1 = 0.0;  ///< supply->1, 1->tank [m^3/s]
    S supply_flow_2 = 0.0, tank_flow_2 = 0.0;  ///< supply->2, 2->tank [m^3/s]
    S q1 = 0.0, q2 = 0.0;                      ///< valve flow into 1 and out of 2 (6.4-6.5) [m^3/s]
    S internal_leak = 0.0, external_leak_1 = 0.0, external_leak_2 = 0.0;  ///< [m^3/s]
    S flow_force = 0.0;                                                   ///< on the spool [N]
    S stop_force = 0.0;    ///< end stops on the piston [N]
    S v1 = 0.0, v2 = 0.0;  ///< chamber volumes [m^3]
  };
  using Eval = EvalT<double>;
  template <class S>
  EvalT<S> evaluate(double command, const S* x) const;

  /// Derivatives of the 10 states under the external force on the rod along its axis
  /// `external_force` [N] and a mass `load_mass` [kg] moving with the piston (the equivalent
  /// mass of the calibration; 0 when the mechanism is modelled).
  template <class S>
  void derivatives(const EvalT<S>& e, const S* x, const S& external_force, double load_mass,
                   S* dxdt) const;

  void initial_state(double* x, double position = 0.0) const;
  void state_scale(double* s) const;

  /// Energy bookkeeping [W]. `hydraulic_net_power` - orifice - leak - compression equals the
  /// power of the pressure force on the piston, (P1 - P2) A_c x', when the chamber equations
  /// are consistent; the energy audit uses the long form as its check.
  template <class S>
  S hydraulic_net_power(const EvalT<S>& e) const;
  template <class S>
  S orifice_loss(const EvalT<S>& e, const S* x) const;
  template <class S>
  S leak_loss(const EvalT<S>& e, const S* x) const;
  template <class S>
  S compression_power(const EvalT<S>& e, const S* x, const S* dxdt) const;
  /// Piston kinetic energy (with the load mass) and end-stop elastic energy [J].
  double mechanical_energy(const double* x, double load_mass) const;
  /// Piston friction and end-stop damping [W].
  template <class S>
  S dissipated_power(const EvalT<S>& e, const S* x) const;

  void outputs(const Eval& e, const double* x, double external_force, SignalFrame& f) const;

  /// Torque-motor force on the jet pipe, referred to the nozzle, for current i [N] (eq. 6.1).
  template <class S>
  S motor_force(const S& current) const;

 private:
  template <class S>
  S orifice_flow(const S& area, const S& dp) const;
  ServoActuatorParams p_;
};

}  // namespace rodend
