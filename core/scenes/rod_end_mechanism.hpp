// The rod-end inside the slider-crank (thesis §4-§5): rod end -> 3-D spring -> socket ->
// clearance contact -> ball -> 3-D spring -> crank end; the crank carries the control surface
// (a triangular plate, mass centre at s/3) with rotational damping and a hinge moment.
// What drives the rod length is left to the scene: a prescribed motion (rod-end-kinematic) or
// a hydraulic actuator (rod-end-actuator).
//
// States (28, from the part's offset): ball (13) | socket (13) | theta [rad] | theta' [rad/s].
#pragma once

#include <cmath>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "core/contact.hpp"
#include "core/dual.hpp"
#include "core/params.hpp"
#include "core/rigid_body.hpp"
#include "core/scene.hpp"
#include "core/scenes/drivers.hpp"
#include "core/scenes/servo_actuator.hpp"
#include "core/scenes/slider_crank.hpp"
#include "core/signals.hpp"
#include "core/spring3d.hpp"

namespace rodend {

class RodEndMechanism {
 public:
  static constexpr int kBall = 0;
  static constexpr int kSocket = BodyStateLayout::size;
  static constexpr int kTheta = 2 * BodyStateLayout::size;
  static constexpr int kThetaDot = kTheta + 1;
  static constexpr int size = kThetaDot + 1;
  /// The dual numbers of the rod-end scenes' exact Jacobians: one derivative per state ahead
  /// of the audit states (the mechanism's; with the actuator's too). The templates below are
  /// instantiated for double and these (rod_end_mechanism.cpp).
  using KinematicDual = Dual<size>;
  using ActuatorDual = Dual<size + ServoActuator::size>;

  /// Reads geometry.*, ball.*, socket.*, contact.*, friction.*, slider_spring.*,
  /// crank_spring.*, surface.*, hinge.*, gravity, wear.*. Throws InputError.
  explicit RodEndMechanism(const ParameterSet& p);

  /// Everything the mechanism computes at one instant, for rod extension u and rate u'. On a
  /// scalar S (double, or a dual number of core/dual.hpp for the exact Jacobians).
  template <class S>
  struct EvalT {
    BodyKinematicsT<S> ball, socket;
    S theta = 0.0, theta_dot = 0.0;
    S rod_length = 0.0, rod_angle_rate = 0.0;
    Vec3T<S> rod_direction = Vec3T<S>::UnitX();  ///< unit vector along the rod, O -> P
    /// Rod inclination to the x-axis [rad] (an output: the dynamics use the direction).
    double rod_angle() const {
      return std::atan2(value_of(rod_direction.y()), value_of(rod_direction.x()));
    }
    SpringAnchorT<S> slider_anchor, crank_anchor;
    ContactEvalT<S> contact;
    SpringEvalT<S> slider_spring, crank_spring;
    S hinge_moment = 0.0;
    S crank_torque = 0.0;  ///< spring torque on the crank about its pivot [N m]
  };
  using Eval = EvalT<double>;
  template <class S>
  EvalT<S> evaluate(double t, const S& u, const S& u_dot, const S* x, const ContactLatch& l) const;

  /// What an accepted step's frame reads (step_outputs, the contact's step signals and
  /// mechanical_energy): evaluate() without the springs' forces, moments and powers and the
  /// crank torque (left zero).
  Eval evaluate_state(double t, double u, double u_dot, const double* x,
                      const ContactLatch& l) const;

  void initial_state(double* x) const;
  void state_scale(double* s) const;
  /// Writes the 28 derivatives.
  template <class S>
  void derivatives(const EvalT<S>& e, const S* x, S* dxdt) const;
  /// Kinetic energy of the spheres and the surface [J].
  double kinetic_energy(const Eval& e) const;
  /// Kinetic + potential energy of the mechanism [J].
  double mechanical_energy(const Eval& e) const;
  /// The same from its kinetic energy `kinetic` = kinetic_energy(e) [J] (the same value).
  double mechanical_energy(const Eval& e, double kinetic) const;
  /// Power delivered by the rod end (through the slider spring) and the hinge moment [W].
  template <class S>
  S input_power(const EvalT<S>& e) const;
  /// Power dissipated by contact damping, friction, spring dampers and the crank damper [W].
  template <class S>
  S dissipated_power(const EvalT<S>& e) const;
  /// Force the rod end exerts on the slider spring along the rod: the actuator's external load
  /// (compression positive) [N].
  template <class S>
  S rod_axial_force(const EvalT<S>& e) const {
    return e.slider_spring.force_on_body.dot(e.rod_direction);
  }
  /// Writes the mechanism's signals (contact, spheres, springs, crank/surface); `command` is the
  /// commanded rod extension [m] (the surface_angle_command signal).
  void outputs(const Eval& e, const double* x, double command, SignalFrame& f) const;
  /// The mechanism's part of an accepted step's frame (kStepSignals): surface angle, the angle
  /// commanded by `command` [m] (surface_angle_command) and the kinetic energy `kinetic` [J]
  /// (kinetic_energy(e), or the scene's own with its further bodies).
  void step_outputs(const Eval& e, double command, double kinetic, SignalFrame& f) const;
  /// The surface's angular acceleration at e (its crank spring evaluated here) [rad/s^2].
  double surface_acceleration(const Eval& e) const;

  ContactGap gap(const double* x) const;

  /// The contact alone at the mechanism state x (the driver's peak location).
  ContactSnapshot contact_snapshot(const double* x, const ContactLatch& l) const;

  /// The signals of a rod-end scene: time, the mechanism's and the contact's, `own` (what the
  /// scene adds, e.g. the actuator's), the energy audit and, with a wear model, sliding_work
  /// and worn_volume.
  std::vector<SignalId> scene_signals(std::span<const SignalId> own) const;

  /// What the mechanism brings to a rod-end scene: the mechanism, its contact and, with a wear
  /// model, wear.
  const Input& hinge() const { return *hinge_; }
  /// Whether the exact Jacobian applies (not on worn surfaces, which are read in double only).
  bool exact_jacobian() const { return !contact_.worn; }
  Features features() const {
    return Features{Feature::mechanism, Feature::contact}.set(Feature::wear, wear_.has_value());
  }

  // wear (core/wear.hpp): null / nothing when wear.model is "none"
  const WearModel* wear_model() const { return wear_ ? &*wear_ : nullptr; }
  /// Worn volume per joule of sliding work, k_b/H_b + k_s/H_s [m^3/J].
  double worn_volume_per_work() const;
  WearSource wear_source(const Eval& e) const;
  /// F_N v_slip, the rate of the scene's sliding-work state [W].
  template <class S>
  static S sliding_power(const EvalT<S>& e) {
    return e.contact.normal_force * e.contact.slip_speed;
  }
  /// Writes sliding_work and worn_volume from the sliding-work state [J] (with a wear model).
  void write_wear_signals(double sliding_work, SignalFrame& f) const;
  /// Uses `worn` as the contact's surfaces from now on (a scene calls this on its own copy).
  void set_worn_surfaces(std::shared_ptr<const WornSurfaces> worn);
  /// Free play along the rod axis and at the surface in the configuration of `e`.
  JointPlay joint_play(const Eval& e) const;
  const ClearanceContactModel& contact() const { return contact_; }
  const SliderCrank& geometry() const { return geometry_; }

  /// Checks that the mechanism closes over a rod-extension history; throws InputError naming
  /// `key` with the offending time and rod length (or `short_key`, if given, when the rod is too
  /// short: the retraction, not the extension, is then the value to change).
  void check_closure(const Input& motion, const std::string& key,
                     const std::string& short_key = {}) const;

 private:
  /// The bodies, theta, the rod and both springs' anchors of evaluate().
  template <class S>
  void kinematics(const S& u, const S& u_dot, const S* x, EvalT<S>& e) const;
  /// friction.mode switch, stuck: the friction force that holds the contact's slip at zero
  /// (core/contact_stick.hpp) from the other forces evaluate() found, added to e.contact.
  template <class S>
  void hold_stuck_contact(EvalT<S>& e) const;

  SliderCrank geometry_;
  RigidBodyParams ball_, socket_;
  ClearanceContactModel contact_;
  Spring3DParams slider_spring_, crank_spring_;
  double surface_inertia_ = 0.0;  ///< m (s/3)^2 + I about the hinge [kg m^2] (eq. 4.15-4.16)
  double surface_damping_ = 0.0;  ///< c [N m s/rad]
  InputPtr hinge_;
  Vec3 gravity_;
  double misalignment_z_ = 0.0;  ///< socket offset along z [m]
  std::optional<WearModel> wear_;
};

}  // namespace rodend
