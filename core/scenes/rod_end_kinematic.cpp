// Scene rod-end-kinematic: the rod-end inside its slider-crank, the rod length following a
// prescribed smooth extension-retraction profile (thesis §4-§5, fig. 5.1). The thesis's
// validated base model, without hydraulics.
//
// State: mechanism (28: ball, socket, crank angle and rate) | input work [J] | dissipated [J].
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

constexpr std::array kSignals{SignalId::time,
                              SignalId::ball_position,
                              SignalId::ball_velocity,
                              SignalId::ball_angular_velocity,
                              SignalId::ball_euler_321,
                              SignalId::socket_position,
                              SignalId::socket_velocity,
                              SignalId::socket_angular_velocity,
                              SignalId::socket_euler_321,
                              SignalId::eccentricity_vector,
                              SignalId::eccentricity,
                              SignalId::relative_position,
                              SignalId::penetration,
                              SignalId::penetration_rate,
                              SignalId::impact_speed,
                              SignalId::contact_force_vector,
                              SignalId::contact_force,
                              SignalId::friction_force_vector,
                              SignalId::friction_force,
                              SignalId::slip_speed,
                              SignalId::wear_indicator,
                              SignalId::contact_angle,
                              SignalId::actuator_position,
                              SignalId::actuator_velocity,
                              SignalId::rod_inclination,
                              SignalId::slider_end_position,
                              SignalId::crank_end_position,
                              SignalId::surface_angle,
                              SignalId::surface_rate,
                              SignalId::surface_acceleration,
                              SignalId::hinge_moment,
                              SignalId::slider_spring_force,
                              SignalId::slider_spring_axial_force,
                              SignalId::slider_spring_moment,
                              SignalId::crank_spring_force,
                              SignalId::crank_spring_axial_force,
                              SignalId::crank_spring_moment,
                              SignalId::kinetic_energy,
                              SignalId::mechanical_energy,
                              SignalId::input_work,
                              SignalId::dissipated_energy,
                              SignalId::energy_residual,
                              SignalId::quaternion_norm_error};
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
    signals_with_wear_.assign(kSignals.begin(), kSignals.end());
    signals_with_wear_.insert(signals_with_wear_.end(),
                              {SignalId::sliding_work, SignalId::worn_volume});
    double x[kStates + 1];
    initial_state(x);
    initial_energy_ = mech_.mechanical_energy(evaluate(0.0, x, ContactLatch{}));
  }

  std::string_view name() const override { return "rod-end-kinematic"; }
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
    if (wears()) dxdt[kSliding] = e.contact.normal_force * e.contact.slip_speed;
  }

  std::span<const SignalId> signals() const override {
    return wears() ? std::span<const SignalId>(signals_with_wear_)
                   : std::span<const SignalId>(kSignals);
  }

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
  void outputs(double t, const double* x, const DiscreteState& d, SignalFrame& f) const override {
    const Mech::Eval e = evaluate(t, x, d.contacts[0]);
    mech_.outputs(e, x + kMech, f);
    write_contact_signals(f, e.contact, e.ball, e.socket, d.contacts[0]);
    const auto m = motion_.at(t);
    f.set(SignalId::actuator_position, m.position);
    f.set(SignalId::actuator_velocity, m.velocity);
    write_energy_signals(f, {mech_.mechanical_energy(e), x[kWork], x[kDissipated]},
                         initial_energy_);
    write_wear_signals(x, f);
  }

 private:
  bool wears() const { return mech_.wear_model() != nullptr; }
  void write_wear_signals(const double* x, SignalFrame& f) const {
    if (!wears()) return;
    f.set(SignalId::sliding_work, x[kSliding]);
    f.set(SignalId::worn_volume, mech_.worn_volume_per_work() * x[kSliding]);
  }

  Mech mech_;
  ActuatorMotion motion_;
  double initial_energy_ = 0.0;
  std::vector<SignalId> signals_with_wear_;
};

}  // namespace

std::unique_ptr<Scene> make_rod_end_kinematic_scene(const ParameterSet& p) {
  return std::make_unique<RodEndKinematicScene>(p);
}

}  // namespace rodend
