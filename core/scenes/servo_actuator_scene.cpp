// Scene servo-actuator: the electro-hydraulic actuator alone, its load concentrated in an
// equivalent mass at the rod (thesis §6.2, the calibration of the PI gains). No rod-end.
//
// State: actuator (10) | input work [J] | dissipated [J].
#include <array>

#include "core/scene.hpp"
#include "core/scenes/drivers.hpp"
#include "core/scenes/parts.hpp"
#include "core/scenes/servo_actuator.hpp"

namespace rodend {
namespace {

constexpr int kAct = 0;
constexpr int kWork = ServoActuator::size;
constexpr int kDissipated = kWork + 1;
constexpr int kStates = kDissipated + 1;

constexpr auto kSignals =
    concat(SignalId::time, SignalId::actuator_command, SignalId::actuator_position,
           SignalId::actuator_velocity, kServoLoopSignals, kEnergyAudit);
static_assert(distinct(kSignals));
constexpr std::array kAudit{kWork, kDissipated};

class ServoActuatorScene final : public Scene {
 public:
  explicit ServoActuatorScene(const ParameterSet& p)
      : act_(read_servo_actuator(p, "actuator")),
        motion_(read_motion(p, "command")),
        load_mass_(read_positive(p, "load.equivalent_mass", true)),
        load_force_(p.number("load.external_force")) {
    check_command_within_stroke(*motion_, act_.params(), "command");
  }

  std::string_view name() const override { return "servo-actuator"; }
  PeriodicInputs periodic_inputs() const override {
    PeriodicInputs in;
    in.command = motion_->periodic();
    return in;
  }
  Features features() const override { return Features{Feature::actuator, Feature::energy_audit}; }
  int state_size() const override { return kStates; }
  void initial_state(double* x) const override {
    act_.initial_state(x + kAct);
    x[kWork] = x[kDissipated] = 0.0;
  }
  void state_scale(double* s) const override {
    act_.state_scale(s + kAct);
    s[kWork] = s[kDissipated] = 1.0;
  }
  std::span<const int> audit_offsets() const override { return kAudit; }

  void derivatives(double t, const double* x, const DiscreteState&, double* dxdt) const override {
    const auto e = act_.evaluate(motion_->at(t).value, x + kAct);
    act_.derivatives(e, x + kAct, load_force_, load_mass_, dxdt + kAct);
    // input: what the hydraulics deliver to the piston, by the long route (net supply power
    // less orifice, leakage and compression), plus the external force's work
    dxdt[kWork] = act_.hydraulic_net_power(e) - act_.orifice_loss(e, x + kAct) -
                  act_.leak_loss(e, x + kAct) - act_.compression_power(e, x + kAct, dxdt + kAct) +
                  load_force_ * x[kAct + ServoActuator::kVel];
    dxdt[kDissipated] = act_.dissipated_power(e, x + kAct);
  }

  std::span<const SignalId> signals() const override { return kSignals; }
  EnergyTerms energy(double, const double* x, const DiscreteState&) const override {
    return {act_.mechanical_energy(x + kAct, load_mass_), x[kWork], x[kDissipated]};
  }
  void outputs(double t, const double* x, const DiscreteState& d, SignalFrame& f) const override {
    const auto e = act_.evaluate(motion_->at(t).value, x + kAct);
    act_.outputs(e, x + kAct, load_force_, f);
    const double v = x[kAct + ServoActuator::kVel];
    f.set(SignalId::kinetic_energy, 0.5 * (act_.params().piston_mass + load_mass_) * v * v);
    write_energy_signals(f, energy(t, x, d), 0.0);
  }

 private:
  ServoActuator act_;
  InputPtr motion_;
  double load_mass_, load_force_;
};

}  // namespace

std::unique_ptr<Scene> make_servo_actuator_scene(const ParameterSet& p) {
  return std::make_unique<ServoActuatorScene>(p);
}

}  // namespace rodend
