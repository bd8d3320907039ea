// Scene rod-end-actuator: the mechanism of rod-end-kinematic with the prescribed rod motion
// replaced by the electro-hydraulic actuator following the same profile as a position command
// (thesis §6.3, fig. 6.11). The external force on the rod is the reaction of the slider spring.
//
// State: mechanism (28) | actuator (10) | input work [J] | dissipated [J].
// With wear.model "archard" a last state integrates the sliding work F_N v_slip [J]
// (core/wear.hpp). The layout, contact and wear are RodEndScene's (rod_end_scene.hpp).
#include "core/scene.hpp"
#include "core/scenes/drivers.hpp"
#include "core/scenes/input_kinds.hpp"
#include "core/scenes/parts.hpp"
#include "core/scenes/rod_end_scene.hpp"
#include "core/scenes/servo_actuator.hpp"

namespace rodend {
namespace {

/// What the actuator adds to the mechanism's signals.
constexpr auto kActuatorSignals = concat(SignalId::actuator_command, kServoLoopSignals);

class RodEndActuatorScene final : public RodEndScene<RodEndActuatorScene, ServoActuator::size> {
 public:
  static constexpr int kAct = kOwn;

  explicit RodEndActuatorScene(const ParameterSet& p)
      : RodEndScene(p, kActuatorSignals),
        act_(read_servo_actuator(p, "actuator")),
        command_(read_motion(p, "motion")) {
    check_command_within_stroke(*command_, act_.params(), "motion");
    // the piston cannot take the mechanism beyond its stroke: check closure over the stroke
    StrokeParams full = read_stroke_params(InputKeys{p, "motion"});
    full.extension = full.retraction = act_.params().half_stroke;
    mech_.check_closure(RaisedCosineStroke(full), "actuator.half_stroke");
    double x[kStates + 1];
    initial_state(x);
    initial_energy_ = energy(0.0, x, DiscreteState{{ContactLatch{}}}).mechanical;
  }

  std::string_view name() const override { return "rod-end-actuator"; }
  PeriodicInputs periodic_inputs() const override {
    PeriodicInputs in;
    in.command = command_->periodic();
    in.load = mech_.hinge().periodic();
    return in;
  }
  Features features() const override {
    return mech_.features().set(Feature::actuator).set(Feature::energy_audit);
  }
  void initial_state(double* x) const override {
    RodEndScene::initial_state(x);
    act_.initial_state(x + kAct);
  }
  void state_scale(double* s) const override {
    RodEndScene::state_scale(s);
    act_.state_scale(s + kAct);
  }

  template <class S>
  struct EvalT {
    Mech::EvalT<S> mech;
    ServoActuator::EvalT<S> act;
    S external_force;  ///< on the piston along the rod [N]
  };
  using Eval = EvalT<double>;
  template <class S>
  EvalT<S> evaluate(double t, const S* x, const ContactLatch& l) const {
    const S u = x[kAct + ServoActuator::kPos], u_dot = x[kAct + ServoActuator::kVel];
    EvalT<S> e{mech_.evaluate(t, u, u_dot, x + kMech, l),
               act_.evaluate(command_->at(t).value, x + kAct), S(0.0)};
    // the slider spring pulls the rod end with the opposite of its force on the socket
    e.external_force = -mech_.rod_axial_force(e.mech);
    return e;
  }
  Mech::Eval mechanism_eval(double t, const double* x, const ContactLatch& l) const {
    return evaluate(t, x, l).mech;
  }

  template <class S>
  void rhs(double t, const S* x, const DiscreteState& d, S* dxdt) const {
    const EvalT<S> e = evaluate(t, x, d.contacts[0]);
    mech_.derivatives(e.mech, x + kMech, dxdt + kMech);
    act_.derivatives(e.act, x + kAct, e.external_force, 0.0, dxdt + kAct);
    const S* xa = x + kAct;
    const S u_dot = xa[ServoActuator::kVel];
    // inputs: the hydraulics (long route, see ServoActuator), the hinge moment, and the power
    // of the ideal rod pivot that turns the rod end about O (the slider spring's anchor power
    // less what the piston itself delivers along the rod)
    const S hydraulic = act_.hydraulic_net_power(e.act) - act_.orifice_loss(e.act, xa) -
                        act_.leak_loss(e.act, xa) - act_.compression_power(e.act, xa, dxdt + kAct);
    const S constraint = e.mech.slider_spring.anchor_power - mech_.rod_axial_force(e.mech) * u_dot;
    dxdt[kWork] = hydraulic + constraint + e.mech.hinge_moment * e.mech.theta_dot;
    dxdt[kDissipated] = mech_.dissipated_power(e.mech) + act_.dissipated_power(e.act, xa);
    if (wears()) dxdt[kSliding] = Mech::sliding_power(e.mech);
  }

  EnergyTerms energy(double t, const double* x, const DiscreteState& d) const override {
    const Eval e = evaluate(t, x, d.contacts[0]);
    return {mech_.mechanical_energy(e.mech) + act_.mechanical_energy(x + kAct, 0.0), x[kWork],
            x[kDissipated]};
  }
  // an accepted step's frame: the contact, the surface angle, the actuator (chamber
  // pressures) and the energy audit (kStepSignals)
  void step_outputs(double t, const double* x, const DiscreteState& d,
                    SignalFrame& f) const override {
    const Eval e = evaluate(t, x, d.contacts[0]);
    mech_.step_outputs(e.mech, e.act.command, kinetic_energy(e, x), f);
    write_contact_signals(f, e.mech.contact, e.mech.ball, e.mech.socket, d.contacts[0]);
    act_.outputs(e.act, x + kAct, e.external_force, f);
    write_energy_signals(f,
                         {mech_.mechanical_energy(e.mech) + act_.mechanical_energy(x + kAct, 0.0),
                          x[kWork], x[kDissipated]},
                         initial_energy_);
  }
  void outputs(double t, const double* x, const DiscreteState& d, SignalFrame& f) const override {
    const Eval e = evaluate(t, x, d.contacts[0]);
    mech_.outputs(e.mech, x + kMech, e.act.command, f);
    write_contact_signals(f, e.mech.contact, e.mech.ball, e.mech.socket, d.contacts[0]);
    act_.outputs(e.act, x + kAct, e.external_force, f);
    f.set(SignalId::kinetic_energy, kinetic_energy(e, x));
    write_energy_signals(f, energy(t, x, d), initial_energy_);
    if (wears()) mech_.write_wear_signals(x[kSliding], f);
  }

 private:
  /// spheres, crank and surface, plus the piston [J]
  double kinetic_energy(const Eval& e, const double* x) const {
    const double v = x[kAct + ServoActuator::kVel];
    return mech_.kinetic_energy(e.mech) + 0.5 * act_.params().piston_mass * v * v;
  }

  ServoActuator act_;
  InputPtr command_;
};

}  // namespace

std::unique_ptr<Scene> make_rod_end_actuator_scene(const ParameterSet& p) {
  return std::make_unique<RodEndActuatorScene>(p);
}

}  // namespace rodend
