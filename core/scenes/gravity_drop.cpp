// Scene gravity-drop: the socket is fixed (ground); the ball falls under gravity onto it
// (thesis §3.3, fig. 3.24). Checks the contact: static Hertz penetration, no lateral drift,
// restitution of an elastic contact.
//
// State: ball (13) | dissipated energy [J] (1).
#include <array>

#include "core/scene.hpp"
#include "core/scenes/parts.hpp"

namespace rodend {
namespace {

constexpr int kBall = 0;
constexpr int kDissipated = BodyStateLayout::size;
constexpr int kStates = kDissipated + 1;

constexpr auto kSignals =
    concat(SignalId::time, kBallMotion, SignalId::socket_position, kContactSignals, kBodyAudit);
static_assert(distinct(kSignals));
constexpr std::array kQuaternions{kBall + BodyStateLayout::q};
constexpr std::array kAudit{kDissipated};

class GravityDropScene final : public OneContactScene<GravityDropScene> {
 public:
  explicit GravityDropScene(const ParameterSet& p)
      : ball_(read_body(p, "ball")),
        contact_(read_clearance_contact(p, "contact", "friction")),
        gravity_(p.vec3("gravity")),
        offset_(p.vec3("ball.initial_offset")),
        v0_(p.vec3("ball.initial_velocity")),
        socket_(BodyKinematics::fixed(Vec3::Zero())) {
    // the ball cannot start inside the socket wall (README "Modelling decisions"): resting on
    // it, |offset| = clearance, is the deepest start (round-off allowed)
    if (offset_.norm() > contact_.clearance * (1.0 + 1e-12))
      throw InputError("ball.initial_offset",
                       "the ball would start inside the socket wall: |offset| = " +
                           format_number(offset_.norm()) +
                           " m exceeds contact.clearance = " + format_number(contact_.clearance) +
                           " m; expected |offset| <= the clearance (at most resting on the wall)");
  }

  std::string_view name() const override { return "gravity-drop"; }
  Features features() const override { return Features{Feature::contact, Feature::energy_audit}; }
  int state_size() const override { return kStates; }
  void initial_state(double* x) const override {
    body_initial_state(x + kBall, offset_, v0_);
    x[kDissipated] = 0.0;
  }
  void state_scale(double* s) const override {
    // lengths on the clearance, speeds on the free-fall impact speed sqrt(2 g c)
    const double L = contact_.clearance;
    const double V = std::max(std::sqrt(2.0 * gravity_.norm() * L), 1e-3);
    body_state_scale(s + kBall, L, V, V / contact_.ball_radius);
    s[kDissipated] = 1.0;
  }
  std::span<const int> quaternion_offsets() const override { return kQuaternions; }
  std::span<const int> audit_offsets() const override { return kAudit; }
  const ClearanceContactModel& contact() const { return contact_; }
  ContactGap contact_gap(int, const double* x) const override {
    return rodend::contact_gap(contact_, BodyKinematics::from_state(x + kBall), socket_);
  }

  void derivatives(double, const double* x, const DiscreteState& d, double* dxdt) const override {
    const BodyKinematics ball = BodyKinematics::from_state(x + kBall);
    const ContactEval c = evaluate_contact(contact_, ball, socket_, d.contacts[0]);
    const Vec3 F = ball_.mass * gravity_ + c.force_on_ball();
    body_derivatives(ball_, ball, F, c.moment_on_ball, x + kBall, dxdt + kBall);
    dxdt[kDissipated] = c.damping_power + c.friction_power;
  }

  std::span<const SignalId> signals() const override { return kSignals; }
  EnergyTerms energy(double, const double* x, const DiscreteState& d) const override {
    const BodyKinematics ball = BodyKinematics::from_state(x + kBall);
    const ContactEval c = evaluate_contact(contact_, ball, socket_, d.contacts[0]);
    return {kinetic_energy(ball_, ball) - ball_.mass * gravity_.dot(ball.p_W) + c.potential, 0.0,
            x[kDissipated]};
  }
  void outputs(double t, const double* x, const DiscreteState& d, SignalFrame& f) const override {
    const BodyKinematics ball = BodyKinematics::from_state(x + kBall);
    const ContactEval c = evaluate_contact(contact_, ball, socket_, d.contacts[0]);
    f.set(SignalId::ball_position, ball.p_W);
    f.set(SignalId::ball_velocity, ball.v_W);
    f.set(SignalId::ball_angular_velocity, ball.w_B);
    f.set(SignalId::socket_position, socket_.p_W);
    write_contact_signals(f, c, ball, socket_, d.contacts[0]);
    f.set(SignalId::kinetic_energy, kinetic_energy(ball_, ball));
    const double e0 = 0.5 * ball_.mass * v0_.squaredNorm() - ball_.mass * gravity_.dot(offset_);
    write_energy_signals(f, energy(t, x, d), e0);
    f.set(SignalId::quaternion_norm_error, quaternion_norm_error(x, kBall + BodyStateLayout::q));
  }

 private:
  RigidBodyParams ball_;
  ClearanceContactModel contact_;
  Vec3 gravity_, offset_, v0_;
  BodyKinematics socket_;
};

}  // namespace

std::unique_ptr<Scene> make_gravity_drop_scene(const ParameterSet& p) {
  return std::make_unique<GravityDropScene>(p);
}

}  // namespace rodend
