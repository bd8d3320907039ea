// What the two rod-end scenes (rod-end-kinematic, rod-end-actuator) share around their
// RodEndMechanism: the state layout, the contact, the energy-audit states, wear and the signal
// list. A scene (Derived) adds what drives the rod, the states that takes (kOwnStates of them,
// between the mechanism's and the audit's), the dynamics, the energy and the outputs.
//
// State: mechanism (28) | the scene's own (kOwnStates) | input work [J] | dissipated [J] and,
// with wear.model "archard", the sliding work F_N v_slip [J] (core/wear.hpp).
//
// Derived provides `RodEndMechanism::Eval mechanism_eval(double t, const double* x,
// const ContactLatch& l) const`, the mechanism at time t and state x, and the right-hand side
// as a template on the scalar, `template <class S> void rhs(double t, const S* x,
// const DiscreteState& d, S* dxdt) const`: derivatives() is rhs<double>, and the exact
// Jacobian is rhs on dual numbers (core/dual.hpp) seeded in every state ahead of the audit's.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "core/dual.hpp"
#include "core/scene.hpp"
#include "core/scenes/parts.hpp"
#include "core/scenes/rod_end_mechanism.hpp"

namespace rodend {

template <class Derived, int kOwnStates>
class RodEndScene : public OneContactScene<RodEndScene<Derived, kOwnStates>> {
 public:
  using Mech = RodEndMechanism;
  static constexpr int kMech = 0;
  static constexpr int kOwn = Mech::size;  ///< the scene's own states
  static constexpr int kWork = kOwn + kOwnStates;
  static constexpr int kDissipated = kWork + 1;
  static constexpr int kSliding = kDissipated + 1;  ///< sliding work [J], with wear only
  static constexpr int kStates = kDissipated + 1;   ///< without wear

  int state_size() const override { return kStates + (wears() ? 1 : 0); }
  /// The mechanism's and the audit's states (a scene with states of its own adds them).
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
  const ClearanceContactModel& contact() const { return mech_.contact(); }
  ContactGap contact_gap(int, const double* x) const override { return mech_.gap(x + kMech); }
  double stick_demand(int, double t, const double* x, const DiscreteState& d) const override {
    ContactLatch stuck = d.contacts[0];
    stuck.slipping = false;
    return self().mechanism_eval(t, x, stuck).contact.stick_demand;
  }
  ContactSnapshot contact_snapshot(int, double, const double* x,
                                   const DiscreteState& d) const override {
    return mech_.contact_snapshot(x + kMech, d.contacts[0]);
  }
  std::span<const SignalId> signals() const override { return signals_; }

  void derivatives(double t, const double* x, const DiscreteState& d, double* dxdt) const override {
    self().rhs(t, x, d, dxdt);
  }
  bool exact_jacobian() const override { return mech_.exact_jacobian(); }
  /// Forward-mode differentiation of rhs (one pass carrying kWork derivatives); the audit
  /// states' columns are zero (nothing reads them). On worn surfaces the default's differences.
  void jacobian(double t, const double* x, const DiscreteState& d, double* J) const override {
    if (!exact_jacobian()) return Scene::jacobian(t, x, d, J);
    dual_jacobian<kWork>(state_size(), x, J,
                         [&](const Dual<kWork>* xd, Dual<kWork>* fd) { self().rhs(t, xd, d, fd); });
  }

  // wear: the mechanism's model; the state's sliding work gives the worn-volume signal
  const WearModel* wear_model() const override { return mech_.wear_model(); }
  WearSource wear_source(double t, const double* x, const DiscreteState& d) const override {
    return mech_.wear_source(self().mechanism_eval(t, x, d.contacts[0]));
  }
  std::unique_ptr<Scene> with_worn_surfaces(std::shared_ptr<const WornSurfaces> w) const override {
    if (!wears()) return nullptr;
    auto copy = std::make_unique<Derived>(self());
    static_cast<RodEndScene&>(*copy).mech_.set_worn_surfaces(std::move(w));
    return copy;
  }
  std::optional<JointPlay> joint_play(double t, const double* x) const override {
    return mech_.joint_play(self().mechanism_eval(t, x, ContactLatch{}));
  }

 protected:
  /// Reads the mechanism; `own_signals`: what the scene adds to the mechanism's signals
  /// (RodEndMechanism::scene_signals).
  RodEndScene(const ParameterSet& p, std::span<const SignalId> own_signals)
      : mech_(p), signals_(mech_.scene_signals(own_signals)) {}

  bool wears() const { return mech_.wear_model() != nullptr; }

  Mech mech_;
  double initial_energy_ = 0.0;  ///< mechanical energy at t = 0 [J] (the scene sets it)

 private:
  static constexpr std::array kQuaternions{kMech + Mech::kBall + BodyStateLayout::q,
                                           kMech + Mech::kSocket + BodyStateLayout::q};
  static constexpr std::array kAudit{kWork, kDissipated};
  static constexpr std::array kAuditWear{kWork, kDissipated, kSliding};

  const Derived& self() const { return static_cast<const Derived&>(*this); }

  std::vector<SignalId> signals_;  ///< mech_.scene_signals(...)
};

}  // namespace rodend
