// Scene planar-linkage: a planar linkage composed from part files (docs/planar-linkage.md):
// bodies (core/linkage/body.hpp; rigid or, through make_body, other kinds), ideal revolute
// joints and prismatic guides as constraints, revolute joints with radial clearance as force
// elements (the scene's contact and friction laws), a prescribed actuator displacement, gravity.
// The assembly is core/linkage/assembly.hpp; the default linkage is the flap actuation linkage
// of Wan et al., Machines 2022, 10, 1098 (core/scenes/parts/flap-linkage.part.json).
//
// State: q (n) | q' (n) | input work [J] | dissipated energy [J]. The initial state is the
// ideal linkage assembled at t = 0 (every clearance joint concentric) with its consistent
// velocities. The output (linkage.output, the shaft) is reported as surface_angle beside the
// same linkage with every joint ideal at the same actuator displacement (surface_angle_command,
// ideal_surface_rate, ideal_surface_acceleration), solved for position, velocity and
// acceleration at each output from the current state (Newton on the ideal constraints).
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/linkage/read_linkage.hpp"
#include "core/scene.hpp"
#include "core/scenes/parts.hpp"

namespace rodend {
namespace {

using linkage::LinkageModel;

constexpr auto kLinkageSignals =
    concat(SignalId::time, SignalId::surface_angle, SignalId::surface_angle_command,
           SignalId::surface_rate, SignalId::surface_acceleration, SignalId::ideal_surface_rate,
           SignalId::ideal_surface_acceleration, SignalId::constraint_drift,
           SignalId::linkage_joint_forces, kEnergyAudit);
/// The drive's signals: a linear actuator's displacement, a rotary drive's angle and torque.
constexpr auto kLinearDriveSignals =
    concat(SignalId::actuator_position, SignalId::actuator_velocity);
constexpr auto kRotaryDriveSignals = concat(SignalId::crank_angle, SignalId::driving_torque);
/// The first prismatic guide's point along the guide (from the guide's ground point).
constexpr auto kSliderSignals =
    concat(SignalId::slider_position, SignalId::slider_velocity, SignalId::slider_acceleration);

/// The output point's angle, rate and acceleration.
struct Output {
  double angle = 0.0, rate = 0.0, acceleration = 0.0;
};

class PlanarLinkageScene final : public Scene {
 public:
  explicit PlanarLinkageScene(const ParameterSet& p) : m_(linkage::read_linkage(p)) {
    n_ = m_.linkage.coordinate_count();
    initial_assembly();
    signals_.assign(kLinkageSignals.begin(), kLinkageSignals.end());
    if (rotary())
      signals_.insert(signals_.end(), kRotaryDriveSignals.begin(), kRotaryDriveSignals.end());
    else
      signals_.insert(signals_.end(), kLinearDriveSignals.begin(), kLinearDriveSignals.end());
    if (m_.slider.body >= 0)
      signals_.insert(signals_.end(), kSliderSignals.begin(), kSliderSignals.end());
    if (contact_count() > 0) {
      signals_.insert(signals_.end(), kContactSignals.begin(), kContactSignals.end());
      signals_.push_back(SignalId::relative_velocity);
    }
    std::sort(signals_.begin(), signals_.end());
    audit_ = {2 * n_, 2 * n_ + 1};
    std::vector<double> x0(static_cast<std::size_t>(state_size()));
    initial_state(x0.data());
    initial_mechanical_ = energy(0.0, x0.data(), DiscreteState{}).mechanical;
  }

  std::string_view name() const override { return "planar-linkage"; }
  Features features() const override {
    Features f{Feature::planar, Feature::energy_audit};
    if (contact_count() > 0) f.set(Feature::contact);
    return f;
  }
  int state_size() const override { return 2 * n_ + 2; }
  void initial_state(double* x) const override {
    for (int i = 0; i < n_; ++i) {
      x[i] = q0_[i];
      x[n_ + i] = qd0_[i];
    }
    x[2 * n_] = x[2 * n_ + 1] = 0.0;
  }
  void state_scale(double* s) const override;
  std::span<const int> audit_offsets() const override { return audit_; }
  PeriodicInputs periodic_inputs() const override {
    PeriodicInputs in;
    if (m_.drive == LinkageDrive::linear || m_.drive == LinkageDrive::crank_angle)
      in.command = m_.motion->periodic();
    return in;
  }

  int contact_count() const override {
    return static_cast<int>(m_.linkage.clearance_joints().size());
  }
  double contact_clearance(int c) const override { return joint(c).model.clearance; }
  double contact_radius(int c) const override { return joint(c).model.ball_radius; }
  ContactGap contact_gap(int c, const double* x) const override {
    const auto [journal, bearing] = m_.linkage.joint_kinematics(c, q(x), qd(x));
    return rodend::contact_gap(joint(c).model, journal, bearing);
  }
  ContactSnapshot contact_snapshot(int c, double, const double* x,
                                   const DiscreteState& d) const override {
    const ContactEval e = contact(c, x, d, false);
    return {e.penetration, e.penetration_rate, e.eccentricity, e.normal_force};
  }

  void derivatives(double t, const double* x, const DiscreteState& d, double* dxdt) const override {
    const linkage::LinkageDynamics s = m_.linkage.dynamics(t, q(x), qd(x), d.contacts);
    for (int i = 0; i < n_; ++i) {
      dxdt[i] = x[n_ + i];
      dxdt[n_ + i] = s.qdd[i];
    }
    dxdt[2 * n_] = s.constraint_power + s.motor_power;
    dxdt[2 * n_ + 1] = s.dissipation;
  }

  std::span<const SignalId> signals() const override { return signals_; }
  EnergyTerms energy(double, const double* x, const DiscreteState& d) const override {
    const Eigen::VectorXd Q = q(x), Qd = qd(x);
    double e = m_.linkage.kinetic_energy(Q, Qd) + m_.linkage.potential_energy(Q);
    for (int c = 0; c < contact_count(); ++c) e += contact(c, x, d, false).potential;
    return {e, x[2 * n_], x[2 * n_ + 1]};
  }
  void outputs(double t, const double* x, const DiscreteState& d, SignalFrame& f) const override;

 private:
  Eigen::VectorXd q(const double* x) const { return Eigen::Map<const Eigen::VectorXd>(x, n_); }
  Eigen::VectorXd qd(const double* x) const {
    return Eigen::Map<const Eigen::VectorXd>(x + n_, n_);
  }
  const linkage::ClearanceJoint& joint(int c) const {
    return m_.linkage.clearance_joints()[static_cast<std::size_t>(c)];
  }
  ContactEval contact(int c, const double* x, const DiscreteState& d, bool friction) const {
    const auto [journal, bearing] = m_.linkage.joint_kinematics(c, q(x), qd(x));
    const ContactLatch latch =
        d.contacts.empty() ? ContactLatch{} : d.contacts[static_cast<std::size_t>(c)];
    return friction ? evaluate_contact(joint(c).model, journal, bearing, latch)
                    : evaluate_normal_contact(joint(c).model, journal, bearing, latch);
  }
  bool rotary() const { return m_.drive != LinkageDrive::linear; }
  void initial_assembly();
  /// The drive's and the slider's signals.
  void drive_outputs(double t, const Eigen::VectorXd& Q, const Eigen::VectorXd& Qd,
                     const linkage::LinkageDynamics& s, SignalFrame& f) const;
  /// The drive's largest speed: the actuator's [m/s], a rotary drive's at its body's radius.
  double drive_speed() const;
  /// The ideal linkage's output at t, assembled from q (NaN when it is not determined).
  Output ideal_output(double t, const Eigen::VectorXd& q) const;

  LinkageModel m_;
  int n_ = 0;
  Eigen::VectorXd q0_, qd0_;
  double angle0_ = 0.0;  ///< the output's angle at t = 0 [rad]
  std::vector<SignalId> signals_;
  std::array<int, 2> audit_{};
  double initial_mechanical_ = 0.0;
};

void PlanarLinkageScene::initial_assembly() {
  const linkage::Linkage& ideal = *m_.linkage.ideal();
  q0_ = m_.initial_guess;
  const double residual = ideal.assemble(0.0, q0_);
  if (!(residual < 1e-9))
    throw InputError("linkage",
                     "the bodies cannot be assembled at t = 0: the joints stay " +
                         format_number(residual) +
                         " m apart from the bodies' origin and angle; expected joint points "
                         "that meet (check the points and the origins)");
  qd0_ = ideal.consistent_velocity(0.0, q0_);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n_);
  angle0_ = m_.linkage.point(m_.output, q0_, zero).angle;
}

Output PlanarLinkageScene::ideal_output(double t, const Eigen::VectorXd& q) const {
  const linkage::Linkage& ideal = *m_.linkage.ideal();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (ideal.constraint_count() != n_) return {nan, nan, nan};  // not kinematically determined
  Eigen::VectorXd qi = q;
  if (!(ideal.assemble(t, qi, 20) < 1e-9)) return {nan, nan, nan};
  const Eigen::VectorXd qdi = ideal.consistent_velocity(t, qi);
  const linkage::ConstraintRows c = ideal.constraints(t, qi, qdi);
  const Eigen::VectorXd qddi = c.jacobian.partialPivLu().solve(-c.b2);
  const linkage::GlobalPoint o = ideal.point(m_.output, qi, qdi);
  return {o.angle, o.angular_velocity, o.angle_jacobian.dot(qddi) + o.angle_jacobian_dot_qdot};
}

void PlanarLinkageScene::outputs(double t, const double* x, const DiscreteState& d,
                                 SignalFrame& f) const {
  const Eigen::VectorXd Q = q(x), Qd = qd(x);
  const linkage::LinkageDynamics s = m_.linkage.dynamics(t, Q, Qd, d.contacts);
  drive_outputs(t, Q, Qd, s, f);
  const linkage::GlobalPoint o = m_.linkage.point(m_.output, Q, Qd);
  f.set(SignalId::surface_angle, o.angle - angle0_);
  f.set(SignalId::surface_rate, o.angular_velocity);
  f.set(SignalId::surface_acceleration, o.angle_jacobian.dot(s.qdd) + o.angle_jacobian_dot_qdot);
  const Output ideal = ideal_output(t, Q);
  f.set(SignalId::surface_angle_command, ideal.angle - angle0_);
  f.set(SignalId::ideal_surface_rate, ideal.rate);
  f.set(SignalId::ideal_surface_acceleration, ideal.acceleration);
  const linkage::ConstraintRows c = m_.linkage.constraints(t, Q, Qd);
  double drift = 0.0;
  for (int i = 0; i < c.value.size(); ++i)
    if (!c.is_angle[static_cast<std::size_t>(i)]) drift = std::max(drift, std::abs(c.value[i]));
  f.set(SignalId::constraint_drift, drift);
  for (int i = 0; i < 4; ++i)
    f.set_component(
        SignalId::linkage_joint_forces, i,
        i < contact_count() ? s.contacts[static_cast<std::size_t>(i)].normal_force : 0.0);
  if (contact_count() > 0) {  // the contact signals: the first clearance joint
    const auto [journal, bearing] = m_.linkage.joint_kinematics(0, Q, Qd);
    write_contact_signals(f, s.contacts[0], journal, bearing, d.contacts[0]);
    f.set(SignalId::relative_velocity, Vec3(journal.v_W - bearing.v_W));
  }
  f.set(SignalId::kinetic_energy, m_.linkage.kinetic_energy(Q, Qd));
  write_energy_signals(f, energy(t, x, d), initial_mechanical_);
}

void PlanarLinkageScene::drive_outputs(double t, const Eigen::VectorXd& Q,
                                       const Eigen::VectorXd& Qd, const linkage::LinkageDynamics& s,
                                       SignalFrame& f) const {
  if (rotary()) {
    f.set(SignalId::crank_angle, m_.linkage.point(m_.actuator, Q, Qd).angle);
    f.set(SignalId::driving_torque,
          m_.drive == LinkageDrive::motor ? s.motor_torques[0] : s.drive_forces[0]);
  } else {
    const Input::Sample a = m_.motion->at(t);
    f.set(SignalId::actuator_position, a.value);
    f.set(SignalId::actuator_velocity, a.rate);
  }
  if (m_.slider.body < 0) return;
  const linkage::GlobalPoint p = m_.linkage.point(m_.slider, Q, Qd);
  const Eigen::Vector2d& u = m_.slider_axis;
  f.set(SignalId::slider_position, u.dot(p.position));
  f.set(SignalId::slider_velocity, u.dot(p.velocity));
  f.set(SignalId::slider_acceleration, u.dot(p.jacobian * s.qdd + p.jacobian_dot_qdot));
}

double PlanarLinkageScene::drive_speed() const {
  if (m_.drive == LinkageDrive::crank_speed || m_.drive == LinkageDrive::motor)
    return std::abs(m_.crank_speed) * m_.drive_radius;
  double speed = 0.0;
  const double end = std::max(m_.motion->end_time(), 1e-3);
  for (int k = 0; k <= 256; ++k)
    speed = std::max(speed, std::abs(m_.motion->at(end * k / 256).rate));
  return rotary() ? speed * m_.drive_radius : speed;
}

void PlanarLinkageScene::state_scale(double* s) const {
  // positions on the smallest clearance (0.1 mm without one), angles on it over the body's
  // size; rates on the drive's largest speed (a rotary drive's at its body's radius)
  double speed = drive_speed();
  if (!(speed > 0.0)) speed = 1e-3;
  for (int b = 0; b < m_.linkage.body_count(); ++b) {
    const int o = m_.linkage.body_offset(b), k = m_.linkage.body(b).coordinate_count();
    const double r = m_.body_radius[static_cast<std::size_t>(b)];
    for (int i = 0; i < k; ++i) {
      const double per = i == 2 ? 1.0 / r : 1.0;  // the angle; modes as lengths
      s[o + i] = m_.length_scale * per;
      s[n_ + o + i] = speed * per;
    }
  }
  s[2 * n_] = s[2 * n_ + 1] = 1.0;
}

}  // namespace

std::unique_ptr<Scene> make_planar_linkage_scene(const ParameterSet& p) {
  return std::make_unique<PlanarLinkageScene>(p);
}

}  // namespace rodend
