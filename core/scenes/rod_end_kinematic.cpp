// Scene rod-end-kinematic: the rod-end inside its slider-crank, the rod length following a
// prescribed smooth extension-retraction profile (thesis §4-§5, fig. 5.1). The thesis's
// validated base model, without hydraulics.
//
// State: mechanism (28: ball, socket, crank angle and rate) | input work [J] | dissipated [J].
// With wear.model "archard" a last state integrates the sliding work F_N v_slip [J]
// (core/wear.hpp). The layout, contact and wear are RodEndScene's (rod_end_scene.hpp).
#include "core/scene.hpp"
#include "core/scenes/drivers.hpp"
#include "core/scenes/parts.hpp"
#include "core/scenes/profile.hpp"
#include "core/scenes/rod_end_scene.hpp"

namespace rodend {
namespace {

class RodEndKinematicScene final : public RodEndScene<RodEndKinematicScene, 0> {
 public:
  explicit RodEndKinematicScene(const ParameterSet& p)
      : RodEndScene(p, {}), motion_(read_motion(p, "motion")) {
    const MotionShape shape = read_choice<MotionShape>(p, "motion.shape");
    if (shape == MotionShape::step)
      throw InputError("motion.shape",
                       "a step has no velocity: the prescribed rod motion needs \"raised-cosine\" "
                       "or \"minimum-jerk\" (steps are for the actuator scenes' command)");
    if (shape == MotionShape::profile &&
        read_choice<ProfileInterpolation>(p, "motion.profile.interpolation") !=
            ProfileInterpolation::pchip)
      throw InputError("motion.profile.interpolation",
                       "the prescribed rod motion needs a velocity without jumps: expected "
                       "\"pchip\" (linear interpolation is for the actuator scenes' command)");
    const auto [short_key, long_key] = motion_->range_keys();
    mech_.check_closure(*motion_, "motion." + std::string(long_key),
                        "motion." + std::string(short_key));
    double x[kStates + 1];
    initial_state(x);
    initial_energy_ = mech_.mechanical_energy(mechanism_eval(0.0, x, ContactLatch{}));
  }

  std::string_view name() const override { return "rod-end-kinematic"; }
  Features features() const override { return mech_.features().set(Feature::energy_audit); }

  Mech::Eval mechanism_eval(double t, const double* x, const ContactLatch& l) const {
    const Input::Sample m = motion_->at(t);
    return mech_.evaluate(t, m.value, m.rate, x + kMech, l);
  }

  template <class S>
  void rhs(double t, const S* x, const DiscreteState& d, S* dxdt) const {
    const Input::Sample m = motion_->at(t);
    const Mech::EvalT<S> e = mech_.evaluate(t, S(m.value), S(m.rate), x + kMech, d.contacts[0]);
    mech_.derivatives(e, x + kMech, dxdt + kMech);
    dxdt[kWork] = mech_.input_power(e);
    dxdt[kDissipated] = mech_.dissipated_power(e);
    if (wears()) dxdt[kSliding] = Mech::sliding_power(e);
  }

  EnergyTerms energy(double t, const double* x, const DiscreteState& d) const override {
    return {mech_.mechanical_energy(mechanism_eval(t, x, d.contacts[0])), x[kWork], x[kDissipated]};
  }
  // an accepted step's frame: the contact, the surface angle and the energy audit (kStepSignals)
  void step_outputs(double t, const double* x, const DiscreteState& d,
                    SignalFrame& f) const override {
    // what the frame reads only (evaluate_state), the motion and the kinetic energy once
    const Input::Sample m = motion_->at(t);
    const Mech::Eval e = mech_.evaluate_state(t, m.value, m.rate, x + kMech, d.contacts[0]);
    const double kinetic = mech_.kinetic_energy(e);
    mech_.step_outputs(e, m.value, kinetic, f);
    f.set(SignalId::actuator_position, m.value);
    write_contact_signals(f, e.contact, e.ball, e.socket, d.contacts[0]);
    write_energy_signals(f, {mech_.mechanical_energy(e, kinetic), x[kWork], x[kDissipated]},
                         initial_energy_);
  }
  void outputs(double t, const double* x, const DiscreteState& d, SignalFrame& f) const override {
    const Mech::Eval e = mechanism_eval(t, x, d.contacts[0]);
    const Input::Sample m = motion_->at(t);
    mech_.outputs(e, x + kMech, m.value, f);
    write_contact_signals(f, e.contact, e.ball, e.socket, d.contacts[0]);
    f.set(SignalId::actuator_position, m.value);
    f.set(SignalId::actuator_velocity, m.rate);
    write_energy_signals(f, {mech_.mechanical_energy(e), x[kWork], x[kDissipated]},
                         initial_energy_);
    if (wears()) mech_.write_wear_signals(x[kSliding], f);
  }

 private:
  InputPtr motion_;
};

}  // namespace

std::unique_ptr<Scene> make_rod_end_kinematic_scene(const ParameterSet& p) {
  return std::make_unique<RodEndKinematicScene>(p);
}

}  // namespace rodend
