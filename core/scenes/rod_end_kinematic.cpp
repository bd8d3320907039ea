// Scene rod-end-kinematic: the rod-end inside its slider-crank, the rod length following a
// prescribed smooth extension-retraction profile (thesis §4-§5, fig. 5.1). The thesis's
// validated base model, without hydraulics.
//
// State: mechanism (28: ball, socket, crank angle and rate) | input work [J] | dissipated [J].
// With wear.model "archard" a last state integrates the sliding work F_N v_slip [J]
// (core/wear.hpp).
#include <array>
#include <vector>

#include "core/scene.hpp"
#include "core/scenes/drivers.hpp"
#include "core/scenes/parts.hpp"
#include "core/scenes/rod_end_mechanism.hpp"

namespace rodend {
namespace {

using Mech = RodEndMechanism;
constexpr int kMech = 0;
constexpr int kWork = Mech::size;
constexpr int kDissipated = kWork + 1;
constexpr int kSliding = kDissipated + 1;  ///< sliding work [J], with wear.model archard only
constexpr int kStates = kDissipated + 1;

constexpr std::array kQuaternions{kMech + Mech::kBall + BodyStateLayout::q,
                                  kMech + Mech::kSocket + BodyStateLayout::q};
constexpr std::array kAudit{kWork, kDissipated};
constexpr std::array kAuditWear{kWork, kDissipated, kSliding};

class RodEndKinematicScene final : public Scene {
 public:
  explicit RodEndKinematicScene(const ParameterSet& p)
      : mech_(p), motion_(read_motion(p, "motion")) {
    if (motion_.shape == ActuatorMotion::Shape::step)
      throw InputError("motion.shape",
                       "a step has no velocity: the prescribed rod motion needs \"raised-cosine\" "
                       "or \"minimum-jerk\" (steps are for the actuator scenes' command)");
    mech_.check_closure(motion_, "motion.extension", "motion.retraction");
    signals_ = mech_.scene_signals({});
    double x[kStates + 1];
    initial_state(x);
    initial_energy_ = mech_.mechanical_energy(evaluate(0.0, x, ContactLatch{}));
  }

  std::string_view name() const override { return "rod-end-kinematic"; }
  Features features() const override { return mech_.features().set(Feature::energy_audit); }
  int state_size() const override { return kStates + (wears() ? 1 : 0); }
  void initial_state(double* x) const override {
    mech_.initial_state(x + kMech);
    x[kWork] = x[kDissipated] = 0.0;
    if (wears()) x[kSliding] = 0.0;
  }
  void state_scale(double* s) const override {
    mech_.state_scale(s + kMech);
    s[kWork] = s[kDissipated] = 1.0;
    if (wears()) s[kSliding] = 1.0;
  }
  std::span<const int> quaternion_offsets() const override { return kQuaternions; }
  std::span<const int> audit_offsets() const override {
    return wears() ? std::span<const int>(kAuditWear) : std::span<const int>(kAudit);
  }
  int contact_count() const override { return 1; }
  double contact_clearance(int) const override { return mech_.contact().clearance; }
  double contact_radius(int) const override { return mech_.contact().ball_radius; }
  ContactGap contact_gap(int, const double* x) const override { return mech_.gap(x + kMech); }

  Mech::Eval evaluate(double t, const double* x, const ContactLatch& l) const {
    const auto m = motion_.at(t);
    return mech_.evaluate(t, m.position, m.velocity, x + kMech, l);
  }

  void derivatives(double t, const double* x, const DiscreteState& d, double* dxdt) const override {
    const Mech::Eval e = evaluate(t, x, d.contacts[0]);
    mech_.derivatives(e, x + kMech, dxdt + kMech);
    dxdt[kWork] = mech_.input_power(e);
    dxdt[kDissipated] = mech_.dissipated_power(e);
    if (wears()) dxdt[kSliding] = Mech::sliding_power(e);
  }

  std::span<const SignalId> signals() const override { return signals_; }

  // wear: the mechanism's model; the state's sliding work gives the worn-volume signal
  const WearModel* wear_model() const override { return mech_.wear_model(); }
  WearSource wear_source(double t, const double* x, const DiscreteState& d) const override {
    return mech_.wear_source(evaluate(t, x, d.contacts[0]));
  }
  std::unique_ptr<Scene> with_worn_surfaces(std::shared_ptr<const WornSurfaces> w) const override {
    if (!wears()) return nullptr;
    auto copy = std::make_unique<RodEndKinematicScene>(*this);
    copy->mech_.set_worn_surfaces(std::move(w));
    return copy;
  }
  std::optional<JointPlay> joint_play(double t, const double* x) const override {
    return mech_.joint_play(evaluate(t, x, ContactLatch{}));
  }
  EnergyTerms energy(double t, const double* x, const DiscreteState& d) const override {
    return {mech_.mechanical_energy(evaluate(t, x, d.contacts[0])), x[kWork], x[kDissipated]};
  }
  // an accepted step's frame: the contact, the surface angle and the energy audit (kStepSignals)
  void step_outputs(double t, const double* x, const DiscreteState& d,
                    SignalFrame& f) const override {
    const Mech::Eval e = evaluate(t, x, d.contacts[0]);
    const double position = motion_.at(t).position;
    mech_.step_outputs(e, position, f);
    f.set(SignalId::actuator_position, position);
    write_contact_signals(f, e.contact, e.ball, e.socket, d.contacts[0]);
    write_energy_signals(f, {mech_.mechanical_energy(e), x[kWork], x[kDissipated]},
                         initial_energy_);
  }
  ContactSnapshot contact_snapshot(int, double, const double* x,
                                   const DiscreteState& d) const override {
    return mech_.contact_snapshot(x + kMech, d.contacts[0]);
  }
  void outputs(double t, const double* x, const DiscreteState& d, SignalFrame& f) const override {
    const Mech::Eval e = evaluate(t, x, d.contacts[0]);
    const auto m = motion_.at(t);
    mech_.outputs(e, x + kMech, m.position, f);
    write_contact_signals(f, e.contact, e.ball, e.socket, d.contacts[0]);
    f.set(SignalId::actuator_position, m.position);
    f.set(SignalId::actuator_velocity, m.velocity);
    write_energy_signals(f, {mech_.mechanical_energy(e), x[kWork], x[kDissipated]},
                         initial_energy_);
    if (wears()) mech_.write_wear_signals(x[kSliding], f);
  }

 private:
  bool wears() const { return mech_.wear_model() != nullptr; }

  Mech mech_;
  ActuatorMotion motion_;
  double initial_energy_ = 0.0;
  std::vector<SignalId> signals_;  ///< mech_.scene_signals(...)
};

}  // namespace

std::unique_ptr<Scene> make_rod_end_kinematic_scene(const ParameterSet& p) {
  return std::make_unique<RodEndKinematicScene>(p);
}

}  // namespace rodend
